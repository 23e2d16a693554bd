// Knowing a job before running it, and the pen channel of machines that do not move in Z: plan's
// estimate against the samples it stands for, the bound on samples, Z that takes no time, the pen
// changing at rest where the job's Z crosses its height, the guard against NaN joints, the job
// summary of `pkm gcode`, and the column names of the sample files.
#include <gtest/gtest.h>

#include <unistd.h>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <set>

#include "pkm/io/sample_files.hpp"
#include "pkm/motion/job_summary.hpp"
#include "pkm/motion/planner.hpp"
#include "pkm/motion/time_optimal.hpp"
#include "real_corpus.hpp"
#include "test_support.hpp"

namespace pkm::motion {
namespace {

namespace fs = std::filesystem;

const fs::path kSource = PKM_SOURCE_DIR;

struct Collect final : SampleSink {
  std::vector<Sample> samples;
  void write(const Sample& sample) override { samples.push_back(sample); }
};

struct Discard final : SampleSink {
  void write(const Sample&) override {}
};

using test::TempProgram;

machine::Machine pen_plotter() {
  return test::load_example("pen-plotter.toml");
}

// Drawings made about (0, 0) hang below the wall plotter's anchors with the program's X0 Y0 on its
// home (750, -700).
PlanOptions at_home() {
  PlanOptions options;
  options.origin << 750.0, -700.0, 0.0, 0.0, 0.0, 0.0;
  return options;
}

PlanReport plan_text(const machine::Machine& machine, const std::string& text, SampleSink& sink,
                     const PlanOptions& options) {
  const TempProgram program(text);
  return plan_program(machine, program.path(), {}, options, sink);
}

TEST(Estimate, CountsTheSamplesAndTheDurationOfThePlanExactly) {
  const machine::Machine hexapod = test::load_example("hexapod-bit.toml");
  const fs::path sphere = kSource / "examples" / "jobs" / "sphere.ngc";
  struct Count final : SampleSink {
    long n = 0;
    void write(const Sample&) override { ++n; }
  } count;
  const PlanReport planned = plan_program(hexapod, sphere, {}, {}, count);
  PlanOptions options;
  options.estimate_only = true;
  struct Refuse final : SampleSink {
    void write(const Sample&) override { ADD_FAILURE() << "an estimate made a sample"; }
  } refuse;
  const PlanReport estimate = plan_program(hexapod, sphere, {}, options, refuse);
  EXPECT_EQ(count.n, planned.samples);
  EXPECT_EQ(estimate.samples, planned.samples);
  EXPECT_EQ(estimate.duration_s, planned.duration_s);
  EXPECT_EQ(estimate.path_length_mm, planned.path_length_mm);
  ASSERT_EQ(estimate.feed_limits.size(), planned.feed_limits.size());
  for (std::size_t i = 0; i < 6; ++i) {
    // Ranges from the joints every 0.5 mm along the moves, velocities from their rate along the
    // path at the move's top speed: the same as the samples' within a few tenths.
    EXPECT_NEAR(estimate.joints[i].min, planned.joints[i].min, 0.05) << "leg " << i + 1;
    EXPECT_NEAR(estimate.joints[i].max, planned.joints[i].max, 0.05) << "leg " << i + 1;
    EXPECT_NEAR(estimate.joints[i].peak_velocity, planned.joints[i].peak_velocity, 0.5);
    EXPECT_GE(estimate.joints[i].peak_velocity, planned.joints[i].peak_velocity - 1e-9);
  }
}

// The estimate of one F6000 move on Hektor with its left cable slowed to 20 mm/s (from 60).
PlanReport slow_left_cable_estimate() {
  std::ifstream in(test::example_machine_path("hektor.toml"));
  std::string text((std::istreambuf_iterator<char>(in)), {});
  const std::string key = "max_velocity = 60.0";
  text.replace(text.find(key), key.size(), "max_velocity = 20.0");
  const machine::Machine hektor = machine::parse_machine(text, "slow-left-hektor.toml");
  Discard none;
  PlanOptions options;
  options.estimate_only = true;
  return plan_text(hektor, "G21 G90\nG1 F6000 X80 Y-50\nM2\n", none, options);
}

TEST(Estimate, TheFeedLimitReportsTheProgrammedFeed) {
  // F6000 (100 mm/s) on Hektor, whose max_feed is F2400 (40 mm/s) and whose left cable is slowed
  // here to 20 mm/s: "programmed" is what the program asked for, not what the machine's
  // max_feed left of it.
  const PlanReport report = slow_left_cable_estimate();
  ASSERT_EQ(report.feed_limits.size(), 1u);
  EXPECT_EQ(report.feed_limits[0].line, 2);
  EXPECT_EQ(report.feed_limits[0].joint, 0);
  EXPECT_DOUBLE_EQ(report.feed_limits[0].programmed_mm_per_s, 100.0);
  EXPECT_LT(report.feed_limits[0].allowed_mm_per_s, 40.0);
}

TEST(Estimate, AFeedLimitSaysWhichJointLimitBoundAndItsNumbers) {
  // The same move: the left cable's velocity bound it. At the programmed feed (capped at max_feed,
  // 40 mm/s) the joint would need 40/allowed times what it may use (99.9 % of its 20 mm/s).
  const PlanReport report = slow_left_cable_estimate();
  ASSERT_EQ(report.feed_limits.size(), 1u);
  const FeedLimit& limit = report.feed_limits[0];
  EXPECT_EQ(limit.bound, JointBound::velocity);
  EXPECT_EQ(limit.curve, CurveKind::none);
  EXPECT_DOUBLE_EQ(limit.usable, kGridLimitShare * 20.0);
  EXPECT_NEAR(limit.needed_at_programmed, 40.0 / limit.allowed_mm_per_s * limit.usable, 1e-9);
  EXPECT_GT(limit.needed_at_programmed, limit.usable);
}

TEST(Estimate, AG64CornerBlendNamesTheCornerAndTheAccelerationThatSlowedIt) {
  // The first square of the real corpus' vitruvianMan drawing at F1500 on the Makelangelo: its
  // 90-degree corners are G64 blends of radius 0.01 / (1 - cos 45 deg) = 0.034142 mm, on which
  // v^2/r within max_acceleration 1200 mm/s^2 allows sqrt(1200 r) = 6.40 mm/s (F384). It once
  // said "F1500.0 lowered to F271.3 by joint right", which a user read as a joint too slow (it
  // runs at a fraction of its 150 mm/s). With the joints' 1500 mm/s^2 the tool's own
  // acceleration holds the corner, and such corners are not listed; with 1000 mm/s^2 the joint's
  // bend holds it below the tool's, and the entry names the corner and both numbers.
  Discard none;
  PlanOptions options;
  options.estimate_only = true;
  const auto line_8 = [](const PlanReport& report) {
    return std::find_if(report.feed_limits.begin(), report.feed_limits.end(),
                        [](const FeedLimit& limit) { return limit.line == 8; });
  };
  const fs::path square = kSource / "tests/data/vitruvian-first-square.ngc";
  const PlanReport as_built =
      plan_program(test::load_example("makelangelo.toml"), square, {}, options, none);
  EXPECT_EQ(line_8(as_built), as_built.feed_limits.end());
  const PlanReport report =
      plan_program(test::load_example_changed("makelangelo.toml", "max_acceleration = 1500.0",
                                              "max_acceleration = 1000.0"),
                   square, {}, options, none);
  const auto corner = line_8(report);
  ASSERT_NE(corner, report.feed_limits.end());
  const double radius = 0.01 / (1.0 - std::cos(std::numbers::pi / 4.0));
  EXPECT_EQ(corner->curve, CurveKind::blend);
  EXPECT_EQ(corner->previous_line, 7);
  EXPECT_NEAR(corner->turn_rad, std::numbers::pi / 2.0, 0.01);  // the drawing's corner, 89.8 deg
  EXPECT_NEAR(corner->radius_mm, radius, 0.0003);
  EXPECT_DOUBLE_EQ(corner->curve_acceleration_mm_per_s2, 1200.0);
  EXPECT_NEAR(corner->curve_allowed_mm_per_s, std::sqrt(1200.0 * corner->radius_mm), 1e-12);
  EXPECT_DOUBLE_EQ(corner->programmed_mm_per_s, 25.0);
  EXPECT_LE(corner->allowed_mm_per_s, corner->curve_allowed_mm_per_s);
  ASSERT_EQ(corner->cause, LimitCause::joint);
  EXPECT_EQ(corner->bound, JointBound::acceleration);
  EXPECT_DOUBLE_EQ(corner->usable, kGridLimitShare * 1000.0);
  // v^2 C = usable at the allowed speed: at F1500 the joint would need (25/allowed)^2 as much.
  const double ratio = 25.0 / corner->allowed_mm_per_s;
  EXPECT_NEAR(corner->needed_at_programmed, ratio * ratio * corner->usable, 1e-6);
}

TEST(SampleBound, ATinyPeriodStopsThePlanBeforeItWritesWithoutEnd) {
  // A period of 1e-300 s: the 1.0125 s of this move would be 1e300 samples. The estimate counts
  // to its cap; the plan refuses at the move, having made only the start sample.
  const machine::Machine plotter = test::load_example("wall-plotter.toml");
  PlanOptions options = at_home();
  options.period_s = 1e-300;
  options.estimate_only = true;
  Discard none;
  const std::string job = "G21 G90\nG1 F600 X10\nM2\n";
  const PlanReport estimate = plan_text(plotter, job, none, options);
  EXPECT_EQ(estimate.samples, kSampleCountCap);
  EXPECT_NEAR(estimate.duration_s, 1.0125, 1e-9);
  options.estimate_only = false;
  options.max_samples = 1000;
  Collect out;
  try {
    plan_text(plotter, job, out, options);
    FAIL() << "a plan of 1e300 samples ran";
  } catch (const PlanError& error) {
    EXPECT_EQ(error.line(), 2);
    EXPECT_NE(std::string(error.what()).find("would pass 1000 samples"), std::string::npos)
        << error.what();
  }
  EXPECT_EQ(out.samples.size(), 1u);
}

TEST(ZFree, ZOnlyMovesTakeNoTimeOnAMachineWithoutZ) {
  const machine::Machine plotter = test::load_example("wall-plotter.toml");
  Collect out;
  const PlanReport report =
      plan_text(plotter, "G21 G90\nG0 Z5\nG1 Z-1 F100\nG0 Z5\nM2\n", out, at_home());
  EXPECT_EQ(report.duration_s, 0.0);
  EXPECT_EQ(report.samples, 1);
  EXPECT_EQ(report.path_length_mm, 0.0);
}

TEST(ZFree, ZIsNoPartOfTheLengthThatSetsTheFeed) {
  const machine::Machine plotter = test::load_example("wall-plotter.toml");
  Collect flat, ramp;
  const PlanReport a = plan_text(plotter, "G21 G90\nG1 X10 F600\nM2\n", flat, at_home());
  const PlanReport b = plan_text(plotter, "G21 G90\nG1 X10 Z-20 F600\nM2\n", ramp, at_home());
  EXPECT_NEAR(b.path_length_mm, 10.0, 1e-12);
  EXPECT_EQ(a.duration_s, b.duration_s);
  // 10 mm at F600 (10 mm/s), speeding up and slowing down at 800 mm/s^2: 1 s + 10/800 s.
  EXPECT_NEAR(b.duration_s, 1.0125, 1e-9);
  ASSERT_EQ(flat.samples.size(), ramp.samples.size());
  for (std::size_t k = 0; k < ramp.samples.size(); ++k) {
    EXPECT_EQ(ramp.samples[k].joints, flat.samples[k].joints) << "sample " << k;
  }
  EXPECT_EQ(ramp.samples.back().pose[2], -20.0);  // Z still follows the program in the pose
}

TEST(ZFree, AnArcInXZIsMeasuredAlongItsPathInXY) {
  // A half circle of radius 10 in the XZ plane, from X0 to X20: the plotter travels 20 mm in X.
  const machine::Machine plotter = test::load_example("wall-plotter.toml");
  Collect out;
  const PlanReport report =
      plan_text(plotter, "G21 G90 G18\nG2 X20 Z0 I10 K0 F600\nM2\n", out, at_home());
  EXPECT_NEAR(report.path_length_mm, 20.0, 1e-9);
  EXPECT_NEAR(out.samples.back().pose[0], 770.0, 1e-9);
}

TEST(ZFree, ATableThatIgnoresZHasNoPenAndSpendsNoTimeOnZ) {
  std::ifstream in(test::example_machine_path("pen-plotter.toml"));
  std::string text((std::istreambuf_iterator<char>(in)), {});
  text.replace(text.find("z = \"pen\""), 9, "z = \"ignore\"");
  const machine::Machine ignoring = machine::parse_machine(text, "ignoring.toml");
  ASSERT_EQ(ignoring.tool().z, machine::ToolZ::ignore);
  EXPECT_EQ(io::sample_columns(ignoring),
            (std::vector<std::string>{"t", "line", "x", "y", "z", "j_left", "j_right"}));
  Collect out;
  const PlanReport report =
      plan_text(ignoring, "G21 G90\nG0 X0 Y0 Z5\nG1 Z-1 F600\nG1 X10\nG0 Z5\nM2\n", out, at_home());
  EXPECT_NEAR(report.duration_s, 1.0125, 1e-9);  // the line alone: no pen, no delay
}

// The number of times the pen goes down and up along the samples.
std::pair<int, int> pen_changes(const std::vector<Sample>& samples) {
  int down = 0, up = 0;
  for (std::size_t k = 1; k < samples.size(); ++k) {
    if (samples[k].pen_down != samples[k - 1].pen_down) (samples[k].pen_down ? down : up)++;
  }
  return {down, up};
}

TEST(PenChannel, ThePenChangesAtRestForItsDelay) {
  const machine::Machine pen = pen_plotter();
  ASSERT_EQ(pen.tool().delay_s, 0.15);
  Collect out;
  const PlanReport report =
      plan_text(pen, "G21 G90\nG0 X0 Y0 Z5\nG1 Z-1 F600\nG1 X10\nG0 Z5\nM2\n", out, at_home());
  // Two pen changes of 0.15 s each and the 10 mm line of 1.0125 s; the Z moves take no time.
  EXPECT_NEAR(report.duration_s, 0.3 + 1.0125, 1e-9);
  EXPECT_EQ(pen_changes(out.samples), std::make_pair(1, 1));
  EXPECT_EQ(report.pen_changes, 2);
  EXPECT_FALSE(out.samples.front().pen_down);  // home's Z 0 is not below down_below 0
  int at_rest_down = 0;
  for (const Sample& s : out.samples) {
    EXPECT_EQ(s.pen_down, s.pose[2] < 0.0) << "t = " << s.time_s;
    if (s.time_s > 0.0 && s.time_s <= 0.15) {  // the pen going down, the carriage at rest
      EXPECT_TRUE(s.pen_down);
      EXPECT_EQ(s.pose[0], 750.0);
      ++at_rest_down;
    }
    if (s.pose[0] > 750.0 && s.pose[0] < 760.0) {
      EXPECT_TRUE(s.pen_down) << "t = " << s.time_s;
    }
  }
  EXPECT_NEAR(at_rest_down, 150, 1);  // 0.15 s of 1 ms samples
  EXPECT_FALSE(out.samples.back().pen_down);
  EXPECT_EQ(out.samples.back().pose[0], 760.0);
}

TEST(PenChannel, ThePenIsUpAtTheStartWhateverTheStartPosesZ) {
  // down_below = 10 puts home's Z 0 on the drawing side. The pen stays up over the travel to
  // X 10 and the feed to X 20 (the job has not moved in Z yet), and goes down where the job first
  // moves Z to the drawing side: the G1 Z2 at X 20, drawing the 10 mm to X 30 only.
  machine::Machine pen = pen_plotter();
  machine::ToolChannel tool = pen.tool();
  tool.pen_height_mm = 10.0;
  pen.set_tool(tool);
  Collect out;
  const PlanReport report = plan_text(
      pen, "G21 G90\nG0 X10 Y0\nG1 X20 F600\nG0 Z20\nG1 Z2\nG1 X30\nG0 Z20\nM2\n", out, at_home());
  EXPECT_FALSE(out.samples.front().pen_down);
  EXPECT_EQ(pen_changes(out.samples), std::make_pair(1, 1));
  EXPECT_EQ(report.pen_changes, 2);
  for (const Sample& s : out.samples) {
    if (s.pen_down) {
      EXPECT_GE(s.pose[0], 770.0 - 1e-9) << "t = " << s.time_s;
    }
  }
  EXPECT_TRUE(report.warnings.empty());
}

TEST(PenChannel, WarnsWhenThePenNeverGoesDown) {
  // A LinuxCNC polargraph's way (Z90 draws, Z0 travels) on the pen plotter (down below 0).
  Collect out;
  const PlanReport report = plan_text(pen_plotter(),
                                      "G21 G90\nG0 X1 Y0\nG0 Z90\nG1 X5 Y20 F400\nG1 X10\n"
                                      "G0 Z0\nG0 X18\nG0 Z90\nG1 X21 Y15\nG0 Z0\nM2\n",
                                      out, at_home());
  EXPECT_EQ(report.pen_changes, 0);
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_EQ(report.warnings[0].line, 2);
  EXPECT_EQ(report.warnings[0].message,
            "the pen never goes down: the job's moves in X and Y run at Z 90 mm (feed), 0 mm "
            "(rapid); the pen draws below Z 0 mm ([tool] down_below); [tool] down_above = 45 "
            "would draw at Z 90 and lift the pen at Z 0");
}

TEST(PenChannel, AMoveThatCrossesThePenHeightIsSplitWhereItCrosses) {
  // From Z5 to Z-1 over 12 mm of X: Z passes 0 at 10 mm, where the pen goes down.
  const machine::Machine pen = pen_plotter();
  Collect out;
  const PlanReport report =
      plan_text(pen, "G21 G90\nG0 X0 Y0 Z5\nG1 X12 Z-1 F600\nM2\n", out, at_home());
  EXPECT_NEAR(report.path_length_mm, 12.0, 1e-9);
  int at_the_crossing = 0;
  for (const Sample& s : out.samples) {
    if (s.pen_down) {
      EXPECT_GE(s.pose[0], 760.0 - 1e-9) << "drawn before the crossing, t = " << s.time_s;
    } else {
      EXPECT_LE(s.pose[0], 760.0 + 1e-9) << "travel after the crossing, t = " << s.time_s;
    }
    if (std::abs(s.pose[0] - 760.0) < 1e-9) ++at_the_crossing;
  }
  EXPECT_GE(at_the_crossing, 150);  // at rest there while the pen goes down
  EXPECT_EQ(pen_changes(out.samples), std::make_pair(1, 0));
}

TEST(PenChannel, AnArcThatDipsBelowThePenHeightDrawsOnlyBelowIt) {
  // A half circle in XZ of radius 10 about X10 Z1, from X0 to X20 through Z-9: below Z0 between
  // X 10 - sqrt(99) and X 10 + sqrt(99), where the pen goes down and then up again.
  const machine::Machine pen = pen_plotter();
  Collect out;
  const PlanReport report =
      plan_text(pen, "G21 G90\nG0 X0 Y0 Z1\nG18 G2 X20 Z1 I10 K0 F600\nM2\n", out, at_home());
  EXPECT_EQ(report.pen_changes, 2);
  EXPECT_EQ(pen_changes(out.samples), std::make_pair(1, 1));
  EXPECT_NEAR(report.path_length_mm, 20.0, 1e-9);
  for (const Sample& s : out.samples) {
    EXPECT_EQ(s.pen_down, s.pose[2] < 0.0) << "t = " << s.time_s;
    if (s.pen_down) {
      EXPECT_GE(s.pose[0], 760.0 - std::sqrt(99.0) - 1e-9) << "t = " << s.time_s;
      EXPECT_LE(s.pose[0], 760.0 + std::sqrt(99.0) + 1e-9) << "t = " << s.time_s;
    }
  }
}

TEST(PenChannel, ARealDrawingLiftsThePenWhereverItsZRises) {
  // An Inkscape drawing for a DexArm (pen Z 5 up, -1 down; 142 strokes) on the wall plotter.
  PKM_SKIP_WITHOUT_REAL_CORPUS();
  const fs::path job = test::readable_real_job("plotter/dexarm-inkscape/vitruvianMan.gcode");
  const machine::Machine pen = pen_plotter();
  machine::Machine no_pen = test::load_example("wall-plotter.toml");
  PlanOptions options;
  options.origin << 700.0, -1100.0, 0.0, 0.0, 0.0, 0.0;
  Collect out;
  const PlanReport with_pen = plan_program(pen, job, {}, options, out);
  Discard none;
  const PlanReport without = plan_program(no_pen, job, {}, options, none);
  for (const Sample& s : out.samples) {
    ASSERT_EQ(s.pen_down, s.pose[2] < 0.0) << "t = " << s.time_s << ", line " << s.line;
  }
  EXPECT_EQ(pen_changes(out.samples), std::make_pair(142, 142));
  EXPECT_EQ(with_pen.pen_changes, 284);
  EXPECT_EQ(with_pen.path_length_mm, without.path_length_mm);
  // Each change is a stop and 0.15 s of pen: at least 284 * 0.15 s more than without a pen.
  EXPECT_GE(with_pen.duration_s, without.duration_s + 284 * 0.15 - 1e-9);
  EXPECT_LE(with_pen.duration_s, without.duration_s + 284 * 0.15 + 5.0);
}

// A model whose inverse kinematics overflows to NaN beyond x = 100 and still says "ok", as a
// glide's does far outside its rails: what the planner's guard is for.
class OverflowingKinematics final : public kinematics::Kinematics {
 public:
  std::string_view type() const override { return "overflowing"; }
  int joint_count() const override { return 2; }
  geometry::Dof dof() const override { return geometry::Dof::planar_xy(); }
  kinematics::Status inverse(const geometry::Pose& pose,
                             kinematics::JointVector& joints) const override {
    joints.resize(2);
    const double x = pose.position_mm.x();
    joints << x, x > 100.0 ? std::numeric_limits<double>::quiet_NaN() : pose.position_mm.y();
    return kinematics::Status::success();
  }
  kinematics::Status forward(const kinematics::JointVector& joints,
                             geometry::Pose& pose) const override {
    pose.position_mm.x() = joints[0];
    pose.position_mm.y() = joints[1];
    return kinematics::Status::success();
  }
  kinematics::Status jacobian(const geometry::Pose& pose,
                              kinematics::JointJacobian& d) const override {
    return kinematics::numerical_jacobian(*this, pose, d);
  }
  std::vector<kinematics::Parameter> parameters() const override { return {}; }
  void set_parameters(std::span<const double>) override {}
  std::unique_ptr<kinematics::Kinematics> clone() const override {
    return std::make_unique<OverflowingKinematics>();
  }
};

TEST(NanGuard, AJointThatIsNotANumberStopsThePlanAtItsLine) {
  const std::vector<machine::JointSpec> joints = test::test_model_joints_uv();
  const machine::Machine machine("overflowing", "test", machine::LengthUnit::mm,
                                 std::make_unique<OverflowingKinematics>(), joints, {6000.0, 500.0},
                                 geometry::Pose::from_mm_deg(0.0, 0.0, 0.0));
  Collect out;
  try {
    plan_text(machine, "G21 G90\nG1 F600 X50\nG1 X150\nM2\n", out, {});
    FAIL() << "NaN joints were planned";
  } catch (const PlanError& error) {
    EXPECT_EQ(error.line(), 3);
    EXPECT_NE(std::string(error.what()).find("gives no number for joint 'v'"), std::string::npos)
        << error.what();
  }
  for (const Sample& s : out.samples) EXPECT_TRUE(s.joints.allFinite());
}

TEST(JobSummary, AHandMadeJobByKindOfMotion) {
  // From X0 Y0 Z0: a rapid of 5 mm up, a 3-4-5 line, a clockwise half circle of radius 10 about
  // (13, 4) over its top (13, 14), a dwell, T2, then in inches a line to X1 (25.4 mm) at F10.
  const TempProgram job(
      "G21 G90 T2 M6\nG0 Z5\nG1 F300 X3 Y4\nG2 X23 Y4 I10 J0 F600\nG4 P1.5\nG20\nG1 X1 F10\n"
      "M2\n");
  const JobSummary summary = summarize_job(job.path(), {});
  EXPECT_EQ(summary.moves, 4);
  EXPECT_EQ(summary.units,
            (std::set<gcode::LengthUnits>{gcode::LengthUnits::mm, gcode::LengthUnits::inch}));
  EXPECT_NEAR(summary.rapid_mm, 5.0, 1e-12);
  EXPECT_NEAR(summary.feed_mm, 5.0 + 2.4, 1e-9);
  EXPECT_NEAR(summary.arc_mm, 10.0 * std::numbers::pi, 1e-9);
  EXPECT_EQ(summary.tools, std::set<int>{2});
  EXPECT_EQ(summary.dwell_s, 1.5);
  EXPECT_DOUBLE_EQ(summary.min_feed_mm_per_min, 254.0);  // F10 in inches
  EXPECT_DOUBLE_EQ(summary.max_feed_mm_per_min, 600.0);
  EXPECT_NEAR(summary.box.max().y(), 14.0, 1e-9);  // the arc's top, not only its ends
  EXPECT_NEAR(summary.box.min().x(), 0.0, 1e-12);
  EXPECT_NEAR(summary.box.max().x(), 25.4, 1e-9);
  EXPECT_EQ(summary.box.max().z(), 5.0);
  EXPECT_NEAR(summary.feed_box.min().x(), 3.0, 1e-12);  // the rapid's end is not cut
  EXPECT_NEAR(summary.feed_box.min().y(), 4.0, 1e-12);
}

TEST(JobSummary, BoxesOfAJobWithoutMovesOrFeedsAreEmpty) {
  const TempProgram nothing("G21\nM2\n");
  const JobSummary none = summarize_job(nothing.path(), {});
  EXPECT_TRUE(none.box.isEmpty());
  EXPECT_TRUE(none.feed_box.isEmpty());
  // One rapid: a box of one point (not empty), nothing cut.
  const TempProgram rapid("G21 G0 X1 Y-2 Z3\nM2\n");
  const JobSummary one = summarize_job(rapid.path(), {});
  EXPECT_FALSE(one.box.isEmpty());
  EXPECT_EQ(one.box.min(), Eigen::Vector3d(1.0, -2.0, 3.0));
  EXPECT_EQ(one.box.max(), Eigen::Vector3d(1.0, -2.0, 3.0));
  EXPECT_TRUE(one.feed_box.isEmpty());
}

// The NPY header's dict, as NumPy reads it.
std::string npy_header(const fs::path& path, std::string& bytes) {
  std::ifstream in(path, std::ios::binary);
  bytes.assign(std::istreambuf_iterator<char>(in), {});
  if (bytes.size() < 10 || bytes.substr(0, 6) != "\x93NUMPY") return "";
  const std::size_t length =
      static_cast<unsigned char>(bytes[8]) + 256u * static_cast<unsigned char>(bytes[9]);
  return bytes.substr(10, length);
}

TEST(SampleFiles, CsvRowsKeepTheirFormat) {
  // Hektor at (34, -40): cables sqrt(34^2 + 40^2) and sqrt(66^2 + 40^2). Times with 6 decimals,
  // the line a whole number, everything else with 9: what tools reading these files expect.
  const machine::Machine hektor = test::load_example("hektor.toml");
  const fs::path path =
      fs::temp_directory_path() / ("pkm-row-" + std::to_string(::getpid()) + ".csv");
  Sample s;
  s.time_s = 0.5;
  s.line = 7;
  s.pose << 34, -40, 0, 0, 0, 0;
  ASSERT_TRUE(hektor.inverse(geometry::Pose::from_vector(s.pose), s.joints).ok());
  {
    auto file = io::SampleFile::open(path, hektor);
    file->write(s);
    file->commit();
  }
  std::ifstream in(path);
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  fs::remove(path);
  EXPECT_EQ(text,
            "t,line,x,y,z,j_left,j_right\n"
            "0.500000,7,34.000000000,-40.000000000,0.000000000,52.497618994,77.175125526\n");
}

TEST(SampleFiles, APenMachineHasAPenColumnInBothFormats) {
  const machine::Machine pen = pen_plotter();
  EXPECT_EQ(io::sample_columns(pen),
            (std::vector<std::string>{"t", "line", "x", "y", "z", "j_left", "j_right", "pen"}));
  const fs::path base = fs::temp_directory_path() / ("pkm-pen-" + std::to_string(::getpid()));
  Sample s;
  s.time_s = 0.25;
  s.line = 3;
  s.pose << 750, -700, -1, 0, 0, 0;
  s.pen_down = true;
  ASSERT_TRUE(pen.inverse(geometry::Pose::from_vector(s.pose), s.joints).ok());
  for (const char* extension : {".csv", ".npy"}) {
    auto file = io::SampleFile::open(base.string() + extension, pen);
    file->write(s);
    file->commit();
  }
  std::ifstream csv(base.string() + ".csv");
  std::string header, row;
  std::getline(csv, header);
  std::getline(csv, row);
  EXPECT_EQ(header, "t,line,x,y,z,j_left,j_right,pen");
  EXPECT_EQ(row,
            "0.250000,3,750.000000000,-700.000000000,-1.000000000,1025.914226434,"
            "1025.914226434,1");
  std::string bytes;
  const std::string dict = npy_header(base.string() + ".npy", bytes);
  EXPECT_EQ(dict.substr(0, dict.find(", 'fortran_order'")),
            "{'descr': [('t', '<f8'), ('line', '<f8'), ('x', '<f8'), ('y', '<f8'), ('z', '<f8'), "
            "('j_left', '<f8'), ('j_right', '<f8'), ('pen', '<f8')]");
  double values[8];
  ASSERT_EQ(bytes.size(), 10 + dict.size() + sizeof values);
  std::memcpy(values, bytes.data() + 10 + dict.size(), sizeof values);
  EXPECT_EQ(values[7], 1.0);
  fs::remove(base.string() + ".csv");
  fs::remove(base.string() + ".npy");
}

}  // namespace
}  // namespace pkm::motion
