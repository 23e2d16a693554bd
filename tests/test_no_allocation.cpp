// The per-sample path allocates nothing: IK, Jacobian and FK along a path are counted against a
// replaced global operator new. A separate executable, so the counter sees only this test.
#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>

#include <unistd.h>
#include <filesystem>

#include "pkm/gcode/interpreter.hpp"
#include "pkm/io/sample_files.hpp"
#include "pkm/kinematics/cable_robot.hpp"
#include "pkm/kinematics/cable_tensions.hpp"
#include "pkm/kinematics/lanes.hpp"
#include "pkm/linuxcnc/kins_adapter.hpp"
#include "pkm/motion/planner.hpp"
#include "test_support.hpp"

namespace {
std::atomic<long> allocations{0};
}

void* operator new(std::size_t size) {
  ++allocations;
  if (void* memory = std::malloc(size == 0 ? 1 : size)) return memory;
  throw std::bad_alloc();
}
void operator delete(void* memory) noexcept {
  std::free(memory);
}
void operator delete(void* memory, std::size_t) noexcept {
  std::free(memory);
}

namespace pkm {
namespace {

TEST(AllocationCounter, SeesAnAllocation) {
  const long before = allocations.load();
  std::string* text = new std::string(100, 'x');
  volatile char first = (*text)[0];
  delete text;
  EXPECT_EQ(first, 'x');
  EXPECT_GE(allocations.load() - before, 2);  // the string object and its buffer
}

class NoAllocation : public ::testing::TestWithParam<std::string> {};

TEST_P(NoAllocation, InverseJacobianAndForwardAllocateNothing) {
  const machine::Machine machine = test::load_example(GetParam());
  std::mt19937_64 rng(1);
  const std::vector<geometry::Pose> poses =
      test::sample_reachable_poses(machine, 200, rng, 10.0, 0.05);
  std::vector<kinematics::JointVector> joints(poses.size());
  std::vector<kinematics::Status> statuses(poses.size());
  kinematics::JointJacobian jacobian;
  const kinematics::Kinematics& kinematics = machine.kinematics();
  const long before = allocations.load();
  kinematics.inverse_batch(poses, joints, statuses);
  for (std::size_t i = 0; i < poses.size(); ++i) {
    geometry::Pose pose = poses[i];
    pose.position_mm.x() += 0.01;  // a servo step away: the seed FK gets along a path
    kinematics.inverse(poses[i], joints[i]);
    kinematics.jacobian(poses[i], jacobian);
    kinematics.forward(joints[i], pose);
    machine.inverse(poses[i], joints[i]);
  }
  EXPECT_EQ(allocations.load() - before, 0);
}

// Along a path: FK with a track (the seed extrapolated, the Jacobian's factorisation kept), and
// the batch IK on both of its paths (AVX2 lanes where the CPU has them, scalar).
TEST_P(NoAllocation, ForwardAlongAPathAndBothBatchPathsAllocateNothing) {
  const machine::Machine machine = test::load_example(GetParam());
  std::vector<geometry::Pose> path;
  for (int i = 0; i < 400; ++i) {
    geometry::Pose pose = machine.home();
    pose.position_mm.x() += 2.0 * std::sin(0.01 * i);  // 0.02 mm servo steps
    pose.position_mm.y() += 2.0 * (1.0 - std::cos(0.01 * i));
    path.push_back(pose);
  }
  std::vector<kinematics::JointVector> joints(path.size());
  std::vector<kinematics::Status> statuses(path.size());
  machine.kinematics().inverse_batch(path, joints, statuses);
  kinematics::ForwardTrack track;
  geometry::Pose pose = machine.home();
  int solved = 0;
  const bool vector_path = kinematics::lanes::avx2_enabled();
  const long before = allocations.load();
  for (std::size_t i = 0; i < path.size(); ++i) {
    if (statuses[i].ok()) solved += machine.forward(joints[i], pose, track).ok() ? 1 : 0;
  }
  machine.kinematics().inverse_batch(path, joints, statuses);
  kinematics::lanes::set_avx2_enabled(false);
  machine.kinematics().inverse_batch(path, joints, statuses);
  kinematics::lanes::set_avx2_enabled(vector_path);
  EXPECT_EQ(allocations.load() - before, 0);
  EXPECT_GT(solved, 0);
}

// The pkmkins module's servo-thread calls: inverse, forward from the previous pose, the failure
// message, on every example machine.
TEST_P(NoAllocation, LinuxCncModuleAllocatesNothing) {
  linuxcnc::KinsAdapter kins(test::load_example(GetParam()), std::nullopt);
  std::mt19937_64 rng(2);
  const std::vector<geometry::Pose> poses =
      test::sample_reachable_poses(kins.machine(), 200, rng, 10.0, 0.05);
  std::vector<linuxcnc::WorldPose> worlds(poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i) kins.to_world(poses[i], worlds[i]);
  double joints[kinematics::kMaxJoints];
  char message[512];
  const long before = allocations.load();
  for (const linuxcnc::WorldPose& world : worlds) {
    ASSERT_TRUE(kins.inverse(world, joints).ok());
    linuxcnc::WorldPose seed = world;
    seed.x += 0.001;  // a servo step away
    kins.forward(joints, seed);
    kins.home(seed, joints);
  }
  linuxcnc::WorldPose far = worlds.front();
  far.x = 1e6;
  EXPECT_FALSE(kins.inverse(far, joints).ok());
  kins.failure_message(message, sizeof message);
  EXPECT_EQ(allocations.load() - before, 0);
  EXPECT_EQ(kins.counters().fk_failures, 0u) << kins.counters().fk_status;
}

// `pkm plan`'s samples into its files: a CSV row or NPY record per sample, the blocks written as
// they fill (more samples than a block holds, after one to warm up: the stream's own buffer).
TEST_P(NoAllocation, SampleFilesAllocateNothingPerSample) {
  const machine::Machine machine = test::load_example(GetParam());
  std::mt19937_64 rng(3);
  const std::vector<geometry::Pose> poses =
      test::sample_reachable_poses(machine, 200, rng, 10.0, 0.05);
  std::vector<motion::Sample> samples(poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i) {
    samples[i].line = static_cast<int>(i);
    samples[i].pose = poses[i].as_vector();
    ASSERT_TRUE(machine.inverse(poses[i], samples[i].joints).ok());
  }
  for (const char* extension : {".csv", ".npy"}) {
    const std::filesystem::path path = std::filesystem::temp_directory_path() /
                                       ("pkm-alloc-" + std::to_string(::getpid()) + extension);
    auto file = io::SampleFile::open(path, machine);
    file->write(samples.front());
    const long before = allocations.load();
    for (int i = 0; i < 5000; ++i) {
      motion::Sample& s = samples[static_cast<std::size_t>(i) % samples.size()];
      s.time_s = 0.001 * i;
      file->write(s);
    }
    EXPECT_EQ(allocations.load() - before, 0) << extension;
    file->commit();
    EXPECT_GT(std::filesystem::file_size(path), 5000u * 8u * 3u) << extension;
    std::filesystem::remove(path);
  }
}

// `pkm gcode --canon`'s lines: every command of the test programs formatted into the buffer the
// command line uses, emptied as it writes it out, allocates nothing.
TEST(NoAllocationOfText, CanonLinesAllocateNothing) {
  std::vector<gcode::Canon> commands;
  // The tool table the programs' G41 and G43 need, and their subroutine files.
  const std::filesystem::path programs = std::filesystem::path(PKM_SOURCE_DIR) / "tests" / "gcode";
  gcode::InterpreterOptions options;
  options.tool_table = gcode::read_tool_table(
      std::filesystem::path(PKM_SOURCE_DIR) / "tests" / "conformance" / "conformance.tbl",
      gcode::LengthUnits::inch);
  options.subroutine_path = {programs / "subroutines"};
  for (const auto& entry : std::filesystem::directory_iterator(programs)) {
    if (entry.path().extension() != ".ngc") continue;
    gcode::Interpreter interpreter(entry.path(), options);
    interpreter.run([&](const gcode::Canon& canon) { commands.push_back(canon); });
  }
  ASSERT_GT(commands.size(), 100u);
  text::TextBuffer out(1 << 16);
  long bytes = 0;
  const long before = allocations.load();
  for (int pass = 0; pass < 20; ++pass) {
    int sequence = 0;
    for (const gcode::Canon& canon : commands) {
      gcode::append_canon_line_start(++sequence, canon.n_label, out);
      gcode::append_canon_text(canon, out);
      out.push_back('\n');
      if (out.size() >= (1 << 15)) {
        bytes += static_cast<long>(out.size());
        out.clear();
      }
    }
  }
  EXPECT_EQ(allocations.load() - before, 0);
  EXPECT_GT(bytes, 20L * 100 * 40);  // 40 characters or more a line
}

// Notes the samples after which something allocated before the next one came (in a fixed
// array: the sink itself allocates nothing).
class AllocationsBetweenSamples final : public motion::SampleSink {
 public:
  void write(const motion::Sample& sample) override {
    const long now = allocations.load();
    if (seen_ > 0 && now != last_ && count_ < times_.size()) times_[count_++] = last_time_;
    last_ = now;
    last_time_ = sample.time_s;
    ++seen_;
  }
  // The times (s) of the samples after which an allocation came.
  std::vector<double> times() const { return {times_.begin(), times_.begin() + count_}; }
  long samples() const { return seen_; }

 private:
  std::array<double, 64> times_{};
  std::size_t count_ = 0;
  long seen_ = 0, last_ = 0;
  double last_time_ = 0.0;
};

// `pkm plan`'s samples along a move (the profile, the pose, the inverse kinematics, the report's
// ranges and peaks) allocate nothing: only where the plan starts and ends does anything allocate.
TEST(NoAllocationOfPlan, SamplesAlongAMoveAllocateNothing) {
  const machine::Machine machine = test::load_example("hexapod-bit.toml");
  const test::TempProgram program("G21 G91\nG1 X20 F120\nM2\n");
  AllocationsBetweenSamples sink;
  const motion::PlanReport report = motion::plan_program(machine, program.path(), {}, {}, sink);
  EXPECT_NEAR(report.duration_s, 10.0, 0.5);  // 20 mm at 2 mm/s, with its ramps
  EXPECT_EQ(sink.samples(), report.samples);
  for (const double t : sink.times()) {
    EXPECT_TRUE(t < 0.01 || t > report.duration_s - 0.01) << "an allocation after t = " << t;
  }
}

// The forces a cable robot's cables can exert (the planner asks them at every grid point of a
// heavy effector's moves) allocate nothing.
TEST(NoAllocationOfPlan, CableForcePolytopeAllocatesNothing) {
  const machine::Machine machine = test::load_example("hangprinter-v4.toml");
  const kinematics::CableTensions& cables = *machine.kinematics().cable_tensions();
  kinematics::CableForcePolytope polytope;
  int held = 0;
  const long before = allocations.load();
  for (int k = 0; k < 100; ++k) {
    geometry::Vector6d pose = geometry::Vector6d::Zero();
    pose.x() = 3.0 * k - 150.0;
    pose.z() = 5.0 * k;
    if (!cables.force_polytope(geometry::Pose::from_vector(pose), polytope)) continue;
    int facet = -1;
    bool high = false;
    const Eigen::Vector3d force = cables.cable_force_N(Eigen::Vector3d(0.0, 0.0, 100.0));
    if (polytope.margin_N(force, facet, high) > 0.0) ++held;
  }
  EXPECT_EQ(allocations.load() - before, 0);
  EXPECT_GT(held, 50);
}

// A cable robot whose cables run over swivelling pulleys: IK, Jacobian and FK allocate nothing.
TEST(NoAllocationOfPulleys, CableRobotOverPulleysAllocatesNothing) {
  kinematics::CableRobotGeometry g;
  const double corner[4][2] = {{-800.0, -800.0}, {800.0, -800.0}, {800.0, 800.0}, {-800.0, 800.0}};
  for (const auto& xy : corner) {
    kinematics::RobotCable cable;
    cable.anchor_mm = {xy[0], xy[1], 2000.0};
    cable.pulley_radius_mm = 18.85;
    cable.pulley_axis = {xy[0], xy[1], 0.0};
    g.cables.push_back(cable);
  }
  g.cables.push_back(g.cables.front());
  g.cables.back().anchor_mm = {0.0, 0.0, -200.0};
  g.cables.back().pulley_axis = {0.0, 1.0, 0.0};
  const kinematics::CableRobotKinematics model(g);
  kinematics::JointVector joints;
  kinematics::JointJacobian jacobian;
  int round_trips = 0;
  const long before = allocations.load();
  for (int k = 0; k < 100; ++k) {
    geometry::Pose pose;
    pose.position_mm = {4.0 * k - 200.0, 150.0 - 3.0 * k, 200.0 + 10.0 * k};
    if (!model.inverse(pose, joints).ok() || !model.jacobian(pose, jacobian).ok()) continue;
    geometry::Pose found;
    found.position_mm = {0.0, 0.0, 800.0};
    if (model.forward(joints, found).ok() && (found.position_mm - pose.position_mm).norm() < 1e-9) {
      ++round_trips;
    }
  }
  EXPECT_EQ(allocations.load() - before, 0);
  EXPECT_EQ(round_trips, 100);
}

INSTANTIATE_TEST_SUITE_P(Examples, NoAllocation, ::testing::ValuesIn(test::example_machine_files()),
                         [](const auto& test_info) { return test::test_name(test_info.param); });

}  // namespace
}  // namespace pkm
