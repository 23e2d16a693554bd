// docs/architecture.md's recipe "Adding a machine kind" followed with a model that lives in this
// file only: a slide pair (two linear joints, u = gain x + offset, v = gain y + offset), its
// reader, and its registration (KinematicsKind). Then what the recipe promises, from the interface
// and nothing else: the machine file loads and its bad keys are located, the reach, the certified
// check's refusal (no derivative bounds), a plan against its hand-computed trapezoid, a post with
// the sampled deviation, the verification of that joint program, the LinuxCNC export's rates, and
// the machine file written back.
#include <gtest/gtest.h>

#include <unistd.h>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <stdexcept>

#include "pkm/certify/job_check.hpp"
#include "pkm/kinematics/model_config.hpp"
#include "pkm/kinematics/model_config_writer.hpp"
#include "pkm/kinematics/registry.hpp"
#include "pkm/linuxcnc/config_export.hpp"
#include "pkm/machine/machine_file_error.hpp"
#include "pkm/machine/machine_writer.hpp"
#include "pkm/motion/job_reach.hpp"
#include "pkm/motion/planner.hpp"
#include "pkm/post/joint_program.hpp"
#include "pkm/post/program_header.hpp"
#include "pkm/verify/joint_path.hpp"
#include "test_support.hpp"

namespace pkm {
namespace {

// ---- the recipe's step 1: the class, its equations, its writer beside its reader -------------

class SlidePairKinematics final : public kinematics::Kinematics {
 public:
  SlidePairKinematics(double gain, double offset_mm) : gain_(gain), offset_mm_(offset_mm) {}

  std::string_view type() const override { return "slide_pair"; }
  int joint_count() const override { return 2; }
  geometry::Dof dof() const override { return geometry::Dof::planar_xy(); }

  kinematics::Status inverse(const geometry::Pose& pose,
                             kinematics::JointVector& joints) const override {
    if (!kinematics::all_finite(pose))
      return kinematics::Status::failure(kinematics::StatusCode::invalid_input);
    joints.resize(2);
    joints << gain_ * pose.position_mm.x() + offset_mm_, gain_ * pose.position_mm.y() + offset_mm_;
    return kinematics::Status::success();
  }
  kinematics::Status forward(const kinematics::JointVector& joints,
                             geometry::Pose& pose_inout) const override {
    if (joints.size() != 2 || !kinematics::all_finite(joints))
      return kinematics::Status::failure(kinematics::StatusCode::invalid_input);
    pose_inout.position_mm.x() = (joints[0] - offset_mm_) / gain_;
    pose_inout.position_mm.y() = (joints[1] - offset_mm_) / gain_;
    return kinematics::Status::success();
  }
  kinematics::Status jacobian(const geometry::Pose& /*pose*/,
                              kinematics::JointJacobian& d_joints_d_pose) const override {
    d_joints_d_pose.setZero(2, geometry::kPoseSize);
    d_joints_d_pose(0, 0) = d_joints_d_pose(1, 1) = gain_;
    return kinematics::Status::success();
  }

  std::vector<kinematics::Parameter> parameters() const override {
    return {{"gain", gain_, ""}, {"offset", offset_mm_, "mm"}};
  }
  void set_parameters(std::span<const double> values) override {
    if (values.size() != 2 || !(values[0] > 0.0)) {
      throw std::invalid_argument("a slide pair takes a positive gain and an offset");
    }
    gain_ = values[0];
    offset_mm_ = values[1];
  }
  std::unique_ptr<kinematics::Kinematics> clone() const override {
    return std::make_unique<SlidePairKinematics>(*this);
  }

  void write_config(kinematics::ModelConfigWriter& out) const override {
    out.number("gain", gain_);
    out.length("offset", offset_mm_);
  }

 private:
  double gain_;       // joint mm per mm of the tool
  double offset_mm_;  // the joints' reading at x = 0, y = 0
};

std::unique_ptr<kinematics::Kinematics> make_slide_pair_kinematics(
    const kinematics::ModelConfig& config) {
  const double gain = config.number("gain");
  if (!(gain > 0.0)) config.fail("gain", "must be a positive number (joint mm per mm)");
  return std::make_unique<SlidePairKinematics>(gain, config.length_or("offset", 0.0));
}

// A bench slide pair: joints twice the tool's travel plus 5 mm, fast enough joints that the
// Cartesian limits (3000 mm/min, 500 mm/s^2) are what binds.
const char* const kSlidePairFile = R"(name = "Bench slide pair"
units = "mm"

[kinematics]
type = "slide_pair"
forward_max_iterations = 80
gain = 2.0
offset = 5.0

[[joints]]
name = "u"
min = -95.0
max = 205.0
max_velocity = 1000.0
max_acceleration = 100000.0
axis = "X"

[[joints]]
name = "v"
min = -15.0
max = 125.0
max_velocity = 1000.0
max_acceleration = 100000.0
axis = "Y"

[cartesian]
max_feed = 3000.0
max_acceleration = 500.0
home = [10.0, 20.0]
)";

// The kind is known to machine files for each test's lifetime only: other tests see the built-in
// kinds alone.
class SlidePair : public ::testing::Test {
 protected:
  kinematics::KinematicsKind kind_{"slide_pair", make_slide_pair_kinematics};
};

std::filesystem::path temp_file(const std::string& name) {
  return std::filesystem::temp_directory_path() /
         ("pkm-recipe-" + std::to_string(::getpid()) + "-" + name);
}

// ---- the registration ------------------------------------------------------------------------

TEST_F(SlidePair, ItsMachineFileLoadsAsTheKindTheRegistrationNames) {
  const machine::Machine machine = machine::parse_machine(kSlidePairFile, "slide-pair.toml");
  EXPECT_EQ(machine.kinematics().type(), "slide_pair");
  EXPECT_EQ(machine.kinematics().forward_options().max_iterations, 80);
  kinematics::JointVector home;
  ASSERT_TRUE(machine.inverse(machine.home(), home).ok());
  EXPECT_DOUBLE_EQ(home[0], 2.0 * 10.0 + 5.0);
  EXPECT_DOUBLE_EQ(home[1], 2.0 * 20.0 + 5.0);
  // IK and FK undo each other (FK seeded away from the pose).
  for (const geometry::Pose& pose : {geometry::Pose::from_mm_deg(-50.0, 60.0, 0.0),
                                     geometry::Pose::from_mm_deg(37.5, -3.25, 0.0)}) {
    kinematics::JointVector joints;
    ASSERT_TRUE(machine.inverse(pose, joints).ok());
    geometry::Pose found = machine.home();
    ASSERT_TRUE(machine.forward(joints, found).ok());
    EXPECT_NEAR((found.position_mm - pose.position_mm).norm(), 0.0, 1e-12);
  }
  const std::vector<std::string> types = kinematics::kinematics_types();
  EXPECT_EQ(types.back(), "slide_pair");  // after the built-in ones
  EXPECT_EQ(types.front(), "matrix");
}

TEST_F(SlidePair, ADuplicateNameIsRefusedAndTheFirstStaysRegistered) {
  try {
    const kinematics::KinematicsKind again("slide_pair", make_slide_pair_kinematics);
    FAIL() << "a second slide_pair was registered";
  } catch (const std::invalid_argument& error) {
    EXPECT_STREQ(error.what(), "kinematics type 'slide_pair' is already registered");
  }
  try {
    const kinematics::KinematicsKind matrix("matrix", make_slide_pair_kinematics);
    FAIL() << "a built-in name was registered";
  } catch (const std::invalid_argument& error) {
    EXPECT_STREQ(error.what(), "kinematics type 'matrix' is built in");
  }
  EXPECT_THROW(kinematics::KinematicsKind("", make_slide_pair_kinematics), std::invalid_argument);
  // A reader whose model names another type: the file it writes back would not read.
  const kinematics::KinematicsKind alias("slide_pair_alias", make_slide_pair_kinematics);
  std::string text = kSlidePairFile;
  text.replace(text.find("\"slide_pair\""), 12, "\"slide_pair_alias\"");
  try {
    machine::parse_machine(text, "alias.toml");
    FAIL() << "a model of another type loaded";
  } catch (const std::logic_error& error) {
    EXPECT_STREQ(error.what(),
                 "the reader of kinematics type 'slide_pair_alias' made no model of that type");
  }
  EXPECT_EQ(machine::parse_machine(kSlidePairFile, "slide-pair.toml").kinematics().type(),
            "slide_pair");
}

TEST(KinematicsKind, AMachineFileOfAnUnregisteredKindIsRefusedAtItsType) {
  {
    kinematics::KinematicsKind kind("slide_pair", make_slide_pair_kinematics);
    kinematics::KinematicsKind moved(std::move(kind));  // the moved-from handle unregisters nothing
    EXPECT_EQ(moved.type(), "slide_pair");
    EXPECT_NO_THROW(machine::parse_machine(kSlidePairFile, "slide-pair.toml"));
  }
  try {
    machine::parse_machine(kSlidePairFile, "slide-pair.toml");
    FAIL() << "an unregistered kind loaded";
  } catch (const machine::MachineFileError& error) {
    // The built-in kinds listed (whatever they are: a new kind must not have to edit this
    // test), the unregistered one not among them.
    const std::string message = error.what();
    const std::string start =
        "slide-pair.toml:5:kinematics.type: unknown kinematics type 'slide_pair' (known: matrix, ";
    EXPECT_EQ(message.substr(0, start.size()), start) << message;
    EXPECT_EQ(message.find("slide_pair", start.size()), std::string::npos) << message;
    EXPECT_EQ(message.back(), ')') << message;
  }
}

// The recipe's step 3: the machine file's bad keys, located by the machine module's reader.
TEST_F(SlidePair, ItsBadKeysAreNamedWithFileLineAndKey) {
  std::string text = kSlidePairFile;
  text.replace(text.find("gain = 2.0"), 10, "gain = -2.0");
  try {
    machine::parse_machine(text, "slide-pair.toml");
    FAIL() << "a negative gain loaded";
  } catch (const machine::MachineFileError& error) {
    EXPECT_EQ(std::string(error.what()),
              "slide-pair.toml:7:kinematics.gain: must be a positive number (joint mm per mm)");
  }
  text = kSlidePairFile;
  text.replace(text.find("offset = 5.0"), 12, "ofset = 5.0");
  try {
    machine::parse_machine(text, "slide-pair.toml");
    FAIL() << "a misspelt key loaded";
  } catch (const machine::MachineFileError& error) {
    EXPECT_EQ(std::string(error.what()),
              "slide-pair.toml:8:kinematics.ofset: unknown key 'ofset' (did you mean 'offset'?)");
  }
}

// ---- what the rest of pkm does with it, from the interface -----------------------------------

TEST_F(SlidePair, ItsReachIsTheJointRangeOverTheGain) {
  const machine::Machine machine = machine::parse_machine(kSlidePairFile, "slide-pair.toml");
  // x = (u - 5) / 2 over u in [-95, 205]: -50..100; y over v in [-15, 125]: -10..60.
  const std::vector<machine::AxisExtent> extents = machine::reachable_extent(machine);
  ASSERT_EQ(extents.size(), 2u);
  EXPECT_EQ(extents[0].axis, 0);
  EXPECT_NEAR(extents[0].min, -50.0, 1e-6);
  EXPECT_NEAR(extents[0].max, 100.0, 1e-6);
  EXPECT_EQ(extents[1].axis, 1);
  EXPECT_NEAR(extents[1].min, -10.0, 1e-6);
  EXPECT_NEAR(extents[1].max, 60.0, 1e-6);
  // d joints / d pose = 2 I: its columns scaled to unit length, perfectly conditioned.
  EXPECT_DOUBLE_EQ(machine::relative_conditioning_at_home(machine), 1.0);

  // A job within the reach has no hint; one 20 mm past it names both boxes.
  const test::TempProgram inside("G1 F600 X90 Y-5\nG1 X-40 Y55\nM2\n");
  EXPECT_EQ(motion::job_reach_hint(machine, inside.path(), {}, geometry::Vector6d::Zero()), "");
  const test::TempProgram outside("G1 F600 X120 Y0\nM2\n");
  const std::string hint =
      motion::job_reach_hint(machine, outside.path(), {}, geometry::Vector6d::Zero());
  EXPECT_NE(hint.find("hint"), std::string::npos) << hint;
  EXPECT_NE(hint.find("100.000"), std::string::npos) << hint;
}

// The certified check needs the model's derivative bounds, which a kind outside bounds/ does not
// have: it says so for every move instead of proving or failing them.
TEST_F(SlidePair, TheCertifiedCheckSaysItHasNoBoundForTheKind) {
  const machine::Machine machine = machine::parse_machine(kSlidePairFile, "slide-pair.toml");
  const test::TempProgram job("G1 F600 X50 Y20\nM2\n");
  const certify::JobCheck check = certify::check_job(machine, job.path(), {});
  EXPECT_FALSE(check.certified());
  EXPECT_EQ(check.proven, 0);
  EXPECT_NE(check.unavailable.find("slide_pair"), std::string::npos) << check.unavailable;
}

struct Collect final : motion::SampleSink {
  std::vector<motion::Sample> samples;
  void write(const motion::Sample& sample) override { samples.push_back(sample); }
};

TEST_F(SlidePair, APlannedLineIsTheHandComputedTrapezoidWithTheModelsJoints) {
  const machine::Machine machine = machine::parse_machine(kSlidePairFile, "slide-pair.toml");
  // From home (10, 20) 40 mm along x at F3000 (50 mm/s), 500 mm/s^2: ramps of 0.1 s over 2.5 mm
  // each, 35 mm cruising at 50 mm/s (0.7 s): 0.9 s. The joints move twice as fast (100 mm/s,
  // 1000 mm/s^2), well within theirs.
  const test::TempProgram job("G21 G90\nG1 F3000 X50 Y20\nM2\n");
  Collect out;
  const motion::PlanReport report = motion::plan_program(machine, job.path(), {}, {}, out);
  EXPECT_NEAR(report.duration_s, 0.9, 1e-12);
  EXPECT_NEAR(report.path_length_mm, 40.0, 1e-12);
  EXPECT_TRUE(report.feed_limits.empty());
  ASSERT_EQ(out.samples.size(), 901u);  // t = 0, 0.001, ..., 0.9
  for (const motion::Sample& sample : out.samples) {
    ASSERT_EQ(sample.joints.size(), 2);
    EXPECT_NEAR(sample.joints[0], 2.0 * sample.pose[0] + 5.0, 1e-12);
    EXPECT_NEAR(sample.joints[1], 2.0 * 20.0 + 5.0, 1e-12);
  }
  EXPECT_DOUBLE_EQ(out.samples.back().joints[0], 105.0);
  // At the end of the first ramp, 0.1 s in: 2.5 mm from the start, joint u 5 mm from its own.
  EXPECT_NEAR(out.samples[100].pose[0], 12.5, 1e-9);
  EXPECT_NEAR(out.samples[100].joints[0], 30.0, 1e-9);
  ASSERT_EQ(report.joints.size(), 2u);
  EXPECT_NEAR(report.joints[0].min, 25.0, 1e-12);
  EXPECT_NEAR(report.joints[0].max, 105.0, 1e-12);
  EXPECT_NEAR(report.joints[0].peak_velocity, 100.0, 1e-6);
}

// A line, a quarter circle of radius 10 mm about (40, 20), and a line back: the lines are one
// block each (the model is linear, so joint-linear blocks are straight), the arc is covered by
// chords whose sagitta at the middle, measured by forward kinematics, keeps within 0.01 mm.
const char* const kPostJob = "G21 G90 G17\nG1 F600 X50 Y20\nG3 X40 Y30 I-10 J0\nG1 X10 Y20\nM2\n";

TEST_F(SlidePair, PostCoversTheJobWithASampledDeviationAndVerifyAgrees) {
  const machine::Machine machine = machine::parse_machine(kSlidePairFile, "slide-pair.toml");
  const test::TempProgram job(kPostJob);
  post::PostOptions options;
  options.tolerance_mm = 0.01;
  std::vector<std::string> lines;
  const post::PostReport report = post::post_program(
      machine, job.path(), {}, options, [&](const std::string& line) { lines.push_back(line); });
  // No derivative bound for this kind: the deviation is sampled, and post says so.
  EXPECT_FALSE(report.bounded);
  EXPECT_EQ(report.moves, 3);
  // The chord of angle t whose sagitta 10 (1 - cos(t / 2)) is 0.01 mm: t = 0.08945 rad, so a
  // quarter circle takes ceil(1.5708 / 0.08945) = 18 chords (bisection finds each just short of
  // t), and the lines one block each.
  const double chord_rad = 2.0 * std::acos(1.0 - 0.01 / 10.0);
  const long arc_blocks = static_cast<long>(std::ceil(std::numbers::pi / 2.0 / chord_rad));
  EXPECT_EQ(arc_blocks, 18);
  EXPECT_EQ(report.blocks, arc_blocks + 2);
  EXPECT_LE(report.max_deviation_mm, 0.01);
  EXPECT_GT(report.max_deviation_mm, 0.0099);
  EXPECT_EQ(report.max_deviation_line, 3);
  // The blocks' ends are the model's joints at the job's points: the first line's end (50, 20),
  // the arc's end (40, 30), the second line's end (10, 20), to the dialect's 5 decimals.
  std::vector<std::string> moves;
  for (const std::string& line : lines) {
    if (line.find("G1 X") != std::string::npos) moves.push_back(line);
  }
  ASSERT_EQ(moves.size(), static_cast<std::size_t>(arc_blocks + 2));
  // Feeds in inverse time (G93): the first line, 40 mm at 10 mm/s, takes 4 s, 1/15 min.
  EXPECT_EQ(moves.front(), "G93 G1 X105.00000 Y45.00000 F15.000");
  EXPECT_NE(moves[moves.size() - 2].find("X85.00000 Y65.00000"), std::string::npos)
      << moves[moves.size() - 2];
  EXPECT_NE(moves.back().find("X25.00000 Y45.00000"), std::string::npos) << moves.back();

  // The program's header says the deviation was sampled, and verify reads its tolerance there.
  const std::string header =
      post::joint_program_header(machine, "job.ngc", post::Dialect::linuxcnc, 0.01, &report);
  EXPECT_NE(header.find("(tolerance    0.010000 mm; sampled deviation "), std::string::npos)
      << header;
  EXPECT_NE(header.find("mm,         20 blocks)"), std::string::npos) << header;
  const std::filesystem::path program = temp_file("slide-pair.ngc");
  {
    std::ofstream out(program);
    out << header;
    for (const std::string& line : lines) out << line << "\n";
  }
  EXPECT_EQ(verify::tolerance_in_header(program), 0.01);
  verify::VerifyOptions verify_options;
  verify_options.tolerance_mm = 0.01;
  const verify::VerifyReport verified =
      verify::verify_joint_program(machine, program, job.path(), verify_options);
  std::filesystem::remove(program);
  EXPECT_TRUE(verified.passed());
  EXPECT_EQ(verified.blocks, report.blocks);
  EXPECT_TRUE(verified.covered);
  EXPECT_NEAR(verified.job_length_mm, 40.0 + 5.0 * std::numbers::pi + std::hypot(30.0, 10.0), 1e-9);
  // Verify measures the distance to the path (at most the distance to the point at the same
  // fraction, which post samples): within the tolerance, and at most post's.
  EXPECT_LE(verified.max_deviation_mm, report.max_deviation_mm + 1e-9);
  EXPECT_GT(verified.max_deviation_mm, 0.0099);
}

// The LinuxCNC export's axis limits from the joint-rate bound, sampled for a kind without
// derivative bounds: with joints of 60 mm/s and 3000 mm/s^2, x and y each get 30 mm/s and
// 1500 mm/s^2 of joint budget over the gain of 2, below max_feed (50 mm/s) but not below
// max_acceleration (500 mm/s^2), which LinuxCNC gets divided by its planner's overshoot.
TEST_F(SlidePair, TheLinuxcncExportSplitsTheJointsRatesOverTheGain) {
  std::string text = kSlidePairFile;
  for (std::size_t at; (at = text.find("max_velocity = 1000.0")) != std::string::npos;) {
    text.replace(at, 21, "max_velocity = 60.0");
  }
  for (std::size_t at; (at = text.find("max_acceleration = 100000.0")) != std::string::npos;) {
    text.replace(at, 27, "max_acceleration = 3000.0");
  }
  const machine::Machine machine = machine::parse_machine(text, "slide-pair.toml");
  linuxcnc::ExportOptions options;
  options.sim = true;
  options.machine_file_name = "slide-pair.toml";
  options.machine_text = text;
  const linuxcnc::LinuxcncConfig config = linuxcnc::make_linuxcnc_config(machine, options);
  EXPECT_FALSE(config.bound.proven);
  EXPECT_NEAR(config.limits.velocity[0], 30.0, 1e-9);
  EXPECT_NEAR(config.limits.velocity[1], 30.0, 1e-9);
  EXPECT_NEAR(config.limits.acceleration[0], 500.0 / linuxcnc::kPlannerAccelerationOvershoot, 1e-9);
  EXPECT_NEAR(config.limits.acceleration[1], 500.0 / linuxcnc::kPlannerAccelerationOvershoot, 1e-9);
  // Z, which no joint follows, LinuxCNC moves at the machine's limits: the tool's speed cap is
  // max_feed.
  EXPECT_TRUE(config.moved.controls(2));
  EXPECT_NEAR(config.limits.velocity[2], 50.0, 1e-9);
  EXPECT_NEAR(config.limits.linear_velocity, 50.0, 1e-9);
}

TEST_F(SlidePair, ItsMachineFileIsWrittenBackAsItWasRead) {
  const machine::Machine machine = machine::parse_machine(kSlidePairFile, "slide-pair.toml");
  const std::string section = machine::kinematics_toml(machine.kinematics(), machine.units());
  EXPECT_EQ(section,
            "[kinematics]\n"
            "type = \"slide_pair\"\n"
            "forward_max_iterations = 80\n"
            "gain = 2.0\n"
            "offset = 5.0\n");
  const std::string rewritten = machine::replace_kinematics_section(
      kSlidePairFile, "slide-pair.toml", machine.kinematics(), machine.units());
  EXPECT_EQ(rewritten, kSlidePairFile);
  const machine::Machine reread = machine::parse_machine(rewritten, "slide-pair.toml");
  EXPECT_EQ(machine::kinematics_toml(reread.kinematics(), reread.units()), section);
  const std::vector<kinematics::Parameter> read = machine.kinematics().parameters();
  const std::vector<kinematics::Parameter> read_back = reread.kinematics().parameters();
  ASSERT_EQ(read_back.size(), 2u);
  for (std::size_t i = 0; i < read.size(); ++i) {
    EXPECT_EQ(read_back[i].name, read[i].name);
    EXPECT_EQ(read_back[i].value, read[i].value);
  }
  // In inch: the offset's 5 mm in the file's unit, the gain as it is.
  const std::string in_inch =
      machine::kinematics_toml(machine.kinematics(), machine::LengthUnit::inch);
  EXPECT_EQ(in_inch.substr(0, in_inch.find("offset = ") + 26),
            "[kinematics]\n"
            "type = \"slide_pair\"\n"
            "forward_max_iterations = 80\n"
            "gain = 2.0\n"
            "offset = 0.196850393700787")  // 5 / 25.4
      << in_inch;
}

}  // namespace
}  // namespace pkm
