// Properties of the time-optimal planner (issue 29) that hold on any job: no sample over a joint's
// velocity or acceleration limit by finite differences at the servo period, nor (on a hanging
// effector) a cable outside its tension limits by statics; the estimate's duration and sample
// count exactly the plan's; the motion time at or above the independent time-optimal reference
// (tests/time_optimal_reference.hpp) and within 2 % of it. On the issue's five jobs, on random
// short jobs about the example machines' homes (a fixed seed), and on the edge cases a user's job
// has (zero-length and tiny moves, angles alone, long rapids, reversals, tiny arcs, tiny feeds,
// dwells, the pen channel).
#include <gtest/gtest.h>

#include <cmath>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <numbers>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "pkm/kinematics/cable_plotter.hpp"
#include "pkm/motion/planner.hpp"
#include "real_corpus.hpp"
#include "sample_limit_checks.hpp"
#include "test_support.hpp"
#include "time_optimal_reference.hpp"

namespace pkm::test {
namespace {

namespace fs = std::filesystem;

const fs::path kSource = PKM_SOURCE_DIR;

// What a plan with every sample checked gives.
struct CheckedPlan {
  motion::PlanReport report;
  long samples_seen = 0;
  long joint_over = 0, not_numbers = 0, out_of_order = 0;
  double velocity_share = 0.0, acceleration_share = 0.0;
  std::string velocity_at, acceleration_at, first_over;
  long tool_over = 0;
  double tool_share = 0.0;
  std::string tool_first_over, tool_worst_at;
  bool tensions_checked = false;
  long tension_outside = 0;
  double tension_margin_N = 0.0;
  std::string first_tension_outside;
};

// The cables' statics when the machine hangs a mass on them (their tensions are limits then).
const kinematics::CablePlotterKinematics* hanging_mass(const machine::Machine& machine) {
  const kinematics::HangingCables* cables = machine.kinematics().hanging_cables();
  if (cables == nullptr || !(cables->effector_mass_kg() > 0.0)) return nullptr;
  return dynamic_cast<const kinematics::CablePlotterKinematics*>(&machine.kinematics());
}

// Plans `program` with every sample made, checks each joint's finite-difference velocity and
// acceleration against its limits within a relative 1e-9 and, on a hanging mass, the tensions.
CheckedPlan plan_checked(const machine::Machine& machine, const fs::path& program,
                         const motion::PlanOptions& options) {
  JointLimitCheck joints(machine);
  const kinematics::CablePlotterKinematics* cables = hanging_mass(machine);
  std::optional<TensionCheck> tensions;
  if (cables != nullptr)
    tensions.emplace(*cables, cables->tension_min_N(), cables->tension_max_N());
  ToolAccelerationCheck tool(machine);
  FanOut sink({&joints, tensions ? &*tensions : nullptr, &tool});
  CheckedPlan out;
  out.report = motion::plan_program(machine, program, {}, options, sink);
  out.samples_seen = joints.samples;
  out.joint_over = joints.over;
  out.not_numbers = joints.not_numbers;
  out.out_of_order = joints.out_of_order;
  out.velocity_share = joints.velocity_share;
  out.acceleration_share = joints.acceleration_share;
  out.velocity_at = joints.velocity_at;
  out.acceleration_at = joints.acceleration_at;
  out.first_over = joints.first_over;
  out.tool_over = tool.over;
  out.tool_share = tool.share;
  out.tool_first_over = tool.first_over;
  out.tool_worst_at = tool.worst_at;
  if (tensions) {
    out.tensions_checked = true;
    out.tension_outside = tensions->outside;
    out.tension_margin_N = tensions->worst_margin_N;
    out.first_tension_outside = tensions->first_outside;
  }
  return out;
}

motion::PlanReport estimate(const machine::Machine& machine, const fs::path& program,
                            motion::PlanOptions options) {
  struct Refuse final : motion::SampleSink {
    void write(const motion::Sample&) override { ADD_FAILURE() << "an estimate made a sample"; }
  } refuse;
  options.estimate_only = true;
  return motion::plan_program(machine, program, {}, options, refuse);
}

// The limits and the plan's own consistency: every sample a number, in time order, each counted,
// none over a joint's limit, no tension outside its limits.
void expect_within_limits(const CheckedPlan& plan, const std::string& label) {
  EXPECT_EQ(plan.not_numbers, 0) << label;
  EXPECT_EQ(plan.out_of_order, 0) << label;
  EXPECT_EQ(plan.samples_seen, plan.report.samples) << label;
  EXPECT_TRUE(std::isfinite(plan.report.duration_s)) << label;
  EXPECT_EQ(plan.joint_over, 0) << label << ": first over: " << plan.first_over;
  if (plan.tensions_checked) {
    EXPECT_EQ(plan.tension_outside, 0)
        << label << ": first outside: " << plan.first_tension_outside;
  }
  EXPECT_EQ(plan.tool_over, 0) << label << ": first over: " << plan.tool_first_over;
}

void expect_estimate_is_the_plan(const motion::PlanReport& estimated,
                                 const motion::PlanReport& planned, const std::string& label) {
  EXPECT_EQ(estimated.duration_s, planned.duration_s) << label;
  EXPECT_EQ(estimated.samples, planned.samples) << label;
}

std::string shares(const CheckedPlan& plan) {
  std::ostringstream text;
  text.precision(6);
  text << plan.report.samples << " samples, " << plan.report.duration_s
       << " s; joint velocity up to " << plan.velocity_share << " of its limit, acceleration up to "
       << plan.acceleration_share << " (" << plan.acceleration_at << ")";
  if (plan.tensions_checked) text << "; least tension margin " << plan.tension_margin_N << " N";
  text << "; tool acceleration up to " << plan.tool_share << " (" << plan.tool_worst_at << ", "
       << plan.tool_over << " samples over)";
  return text.str();
}

motion::PlanOptions at_origin(double x, double y, double z = 0.0) {
  motion::PlanOptions options;
  options.origin << x, y, z, 0.0, 0.0, 0.0;
  return options;
}

// ---------------------------------------------------------------------------------------------
// 1. The issue's five jobs (bench/plan_optimality.cpp's table), every sample at 1 ms checked.

struct IssueJob {
  const char* name;
  std::string program;  // under examples/jobs (example) or the real corpus
  bool real;
  const char* machine;
  double origin[3];
};

void check_issue_job(const IssueJob& job) {
  if (job.real) PKM_SKIP_WITHOUT_REAL_CORPUS();
  const fs::path program =
      job.real ? readable_real_job(job.program) : kSource / "examples" / "jobs" / job.program;
  const machine::Machine machine = load_example(job.machine);
  const motion::PlanOptions options = at_origin(job.origin[0], job.origin[1], job.origin[2]);
  const std::clock_t start = std::clock();
  const CheckedPlan plan = plan_checked(machine, program, options);
  const double cpu = static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC;
  expect_within_limits(plan, job.name);
  expect_estimate_is_the_plan(estimate(machine, program, options), plan.report, job.name);
  if (std::string(job.machine) == "maslow-frame.toml") {
    EXPECT_TRUE(plan.tensions_checked);
  }
  std::cout << job.name << " on " << job.machine << ": " << shares(plan)
            << "; planned and checked in " << cpu << " s CPU\n";
}

TEST(PlannerPropertiesIssueJobs, SphereOnHexapodBitKeepsEveryLimit) {
  check_issue_job({"sphere", "sphere.ngc", false, "hexapod-bit.toml", {0.0, 0.0, 0.0}});
}

TEST(PlannerPropertiesIssueJobs, VitruvianManOnWallPlotterKeepsEveryLimit) {
  check_issue_job({"vitruvianMan",
                   "plotter/dexarm-inkscape/vitruvianMan.gcode",
                   true,
                   "wall-plotter.toml",
                   {750.0, -1100.0, 0.0}});
}

// 917,418 samples, each with its tensions by statics: 5.7 s of CPU, 8.8 s on a shared machine
// (measured); run in the suite as it is (a disabled test shows in ctest's list of failures).
TEST(PlannerPropertiesIssueJobs, CalibrationBenchmarkOnMaslowFrameKeepsEveryLimitAndTension) {
  check_issue_job({"calibration-benchmark",
                   "cam/maslow/calibration-benchmark-test.nc",
                   true,
                   "maslow-frame.toml",
                   {1489.2, -1072.6, 0.0}});
}

TEST(PlannerPropertiesIssueJobs, TinyCatOutlineOnTriaglideKeepsEveryLimit) {
  check_issue_job({"tiny_cat_outline",
                   "cam/camotics/tiny_cat_outline.ngc",
                   true,
                   "triaglide.toml",
                   {-59.0, -54.0, 552.0}});
}

TEST(PlannerPropertiesIssueJobs, DragonOnMaslowKeepsEveryLimit) {
  check_issue_job({"Dragon", "cam/maslow/Dragon.nc", true, "maslow.toml", {1489.2, -1072.6, 0.0}});
}

// ---------------------------------------------------------------------------------------------
// 2. Random short jobs about each example machine's home (seed kRandomSeed): G0, G1, G2, G3 with
// random feeds, G61 and G64 (with and without P) mixed. Each is checked as the issue's jobs are,
// its estimate against its plan, and its motion time against the reference.

constexpr unsigned kRandomSeed = 20261128;
constexpr int kJobsPerMachine = 3;
constexpr int kMovesPerJob = 10;
// The reference's grid (mm): the ratio's lower bound 1 - 1e-6 needs its value within some 1e-7 of
// the optimum (test_time_optimal.cpp: 0.01 mm is within 5e-7 of 0.005 mm on the sphere's rings).
constexpr double kReferenceGridMm = 0.01;

struct RandomMachine {
  const char* file;
  double xy_mm;                // moves within this of home in x and y
  double z_low_mm, z_high_mm;  // and this far below and above it in z (0 0: Z not named)
  double angle_deg;            // A B C within this of home's (0: not named)
  double reference_grid_mm = kReferenceGridMm;
};

std::ostream& operator<<(std::ostream& out, const RandomMachine& machine) {
  return out << machine.file;
}

// The job's text: moves to random points of the box about `home`, arcs turning about centres
// towards home.
std::string random_job(const RandomMachine& spec, const geometry::Vector6d& home,
                       std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const auto within = [&](double low, double high) { return low + (high - low) * unit(rng); };
  const auto log_within = [&](double low, double high) {
    return low * std::pow(high / low, unit(rng));
  };
  std::ostringstream job;
  job.setf(std::ios::fixed);
  job.precision(6);
  job << "G21 G90 G17 G64 P" << log_within(0.001, 1.0) << "\n";
  double x = home[0], y = home[1];
  bool feed_set = false;
  for (int move = 0; move < kMovesPerJob; ++move) {
    const double mode = unit(rng);
    if (mode < 0.15) {
      job << "G61\n";
    } else if (mode < 0.25) {
      job << "G64\n";
    } else if (mode < 0.35) {
      job << "G64 P" << log_within(0.001, 1.0) << "\n";
    }
    const double kind = unit(rng);
    std::string words;
    if (kind < 0.15) {
      job << "G0";
    } else if (kind < 0.6) {
      job << "G1";
    } else {
      job << (kind < 0.8 ? "G2" : "G3");
    }
    if (kind >= 0.6) {
      // About a centre towards home: the circle through the tool, ending at a random angle.
      const double radius = log_within(0.5, 0.5 * spec.xy_mm);
      const double towards = std::atan2(home[1] - y, home[0] - x) + within(-1.0, 1.0);
      const double cx = x + radius * std::cos(towards), cy = y + radius * std::sin(towards);
      const double end = within(0.0, 2.0 * std::numbers::pi);
      const double ex = cx + radius * std::cos(end), ey = cy + radius * std::sin(end);
      job << " X" << ex << " Y" << ey << " I" << cx - x << " J" << cy - y;
      x = ex;
      y = ey;
    } else {
      x = home[0] + within(-spec.xy_mm, spec.xy_mm);
      y = home[1] + within(-spec.xy_mm, spec.xy_mm);
      job << " X" << x << " Y" << y;
    }
    if (spec.z_high_mm > spec.z_low_mm && unit(rng) < 0.4) {
      job << " Z" << home[2] + within(spec.z_low_mm, spec.z_high_mm);
    }
    if (spec.angle_deg > 0.0 && kind < 0.6 && unit(rng) < 0.5) {
      for (const char* letter : {" A", " B", " C"}) {
        job << letter << within(-spec.angle_deg, spec.angle_deg);
      }
    }
    if (kind >= 0.15 && (!feed_set || unit(rng) < 0.5)) {
      job << " F" << log_within(300.0, 12000.0);
      feed_set = true;
    }
    job << "\n";
  }
  job << "M2\n";
  return job.str();
}

// What one random job gave.
struct RandomOutcome {
  bool refused = false;
  std::string refusal;
  double ratio = 0.0;
};

RandomOutcome check_random_job(const machine::Machine& machine, const std::string& text,
                               double grid_mm, const std::string& label) {
  const TempProgram program(text);
  RandomOutcome outcome;
  CheckedPlan plan;
  try {
    plan = plan_checked(machine, program.path(), {});
  } catch (const motion::PlanError& error) {
    outcome.refused = true;
    outcome.refusal = error.what();
    return outcome;
  }
  expect_within_limits(plan, label);
  const PlannedJob pieces = plan_pieces(machine, program.path(), {});
  expect_estimate_is_the_plan(pieces.report, plan.report, label);
  if (pieces.pieces.empty()) return outcome;
  const double reference = solve_reference(machine, pieces.pieces, 0.001, grid_mm).duration_s;
  outcome.ratio = pieces.motion_time_s / reference;
  EXPECT_GE(outcome.ratio, 1.0 - 1e-6)
      << label << ": planner " << pieces.motion_time_s << " s, reference " << reference << " s";
  EXPECT_LE(outcome.ratio, 1.02) << label << ": planner " << pieces.motion_time_s
                                 << " s, reference " << reference << " s";
  return outcome;
}

class PlannerPropertiesRandomJobs : public ::testing::TestWithParam<RandomMachine> {};

TEST_P(PlannerPropertiesRandomJobs, KeepTheLimitsMatchTheEstimateAndNearTheOptimum) {
  const RandomMachine& spec = GetParam();
  const machine::Machine machine = load_example(spec.file);
  std::mt19937_64 rng(kRandomSeed + std::hash<std::string>{}(spec.file) % 1000);
  int refused = 0;
  double lowest = 1e300, highest = 0.0;
  for (int k = 0; k < kJobsPerMachine; ++k) {
    const std::string text = random_job(spec, machine.home().as_vector(), rng);
    const std::string label = std::string(spec.file) + " job " + std::to_string(k) + ":\n" + text;
    const RandomOutcome outcome = check_random_job(machine, text, spec.reference_grid_mm, label);
    if (outcome.refused) {
      ++refused;
      std::cout << spec.file << " job " << k << " refused: " << outcome.refusal << "\n";
      continue;
    }
    if (outcome.ratio > 0.0) {
      lowest = std::min(lowest, outcome.ratio);
      highest = std::max(highest, outcome.ratio);
    }
  }
  std::cout << spec.file << ": " << kJobsPerMachine - refused << " of " << kJobsPerMachine
            << " jobs planned; planner/reference " << lowest << " .. " << highest << "\n";
  // Most jobs about home are within reach: a generator that only makes refused jobs tests nothing.
  EXPECT_LE(refused, kJobsPerMachine / 2) << spec.file;
}

INSTANTIATE_TEST_SUITE_P(
    ExampleMachines, PlannerPropertiesRandomJobs,
    ::testing::Values(RandomMachine{"hexapod-bit.toml", 50.0, -50.0, 50.0, 5.0},
                      RandomMachine{"wall-plotter.toml", 150.0, 0.0, 0.0, 0.0},
                      RandomMachine{"triaglide.toml", 30.0, -20.0, 20.0, 0.0},
                      RandomMachine{"linear-delta.toml", 50.0, -30.0, 30.0, 0.0},
                      RandomMachine{"matrix-mill.toml", 50.0, -30.0, 30.0, 0.0},
                      // The tensions' statics make the reference slow: 0.05 mm
                      // (test_time_optimal.cpp: within 2e-8 of 0.01 mm on a tension-limited job).
                      RandomMachine{"maslow-frame.toml", 60.0, 0.0, 0.0, 0.0, 0.05},
                      RandomMachine{"linuxcnc-rdelta.toml", 25.0, -25.0, 0.0, 0.0}),
    [](const ::testing::TestParamInfo<RandomMachine>& param) {
      return test_name(param.param.file);
    });

// ---------------------------------------------------------------------------------------------
// 3. Edge cases of users' jobs: each plans (no NaN, no refusal), keeps the limits, its estimate is
// its plan; with `reference_grid_mm` > 0 its motion time is also held to the reference.

// The pieces the planner timed faster than the reference: where it may break a limit.
void print_faster_pieces(const PlannedJob& planned, const ReferenceResult& reference) {
  for (std::size_t k = 0; k < planned.pieces.size(); ++k) {
    const motion::PlannedPiece& piece = planned.pieces[k];
    if (piece.duration_s < reference.piece_durations_s[k] * (1.0 - 1e-9)) {
      std::cout << "  piece " << k << " (line " << piece.segment.line << ", "
                << (piece.segment.rapid ? "rapid" : "feed") << ", " << piece.length_mm
                << " mm, entry " << piece.entry_speed_mm_per_s << " exit "
                << piece.exit_speed_mm_per_s << " mm/s" << (piece.stop_after ? ", stops" : "")
                << "): planner " << piece.duration_s << " s, reference "
                << reference.piece_durations_s[k] << " s\n";
    }
  }
}

motion::PlanReport check_edge_case(const std::string& machine_file, const std::string& text,
                                   const motion::PlanOptions& options,
                                   double reference_grid_mm = kReferenceGridMm) {
  const machine::Machine machine = load_example(machine_file);
  const TempProgram program(text);
  const std::string label = machine_file + ":\n" + text;
  const CheckedPlan plan = plan_checked(machine, program.path(), options);
  expect_within_limits(plan, label);
  const PlannedJob pieces = plan_pieces(machine, program.path(), options);
  expect_estimate_is_the_plan(pieces.report, plan.report, label);
  std::cout << machine_file << ": " << shares(plan);
  if (reference_grid_mm > 0.0 && !pieces.pieces.empty()) {
    const ReferenceResult result =
        solve_reference(machine, pieces.pieces, options.period_s, reference_grid_mm);
    const double reference = result.duration_s;
    const double ratio = pieces.motion_time_s / reference;
    if (ratio < 1.0 - 1e-6) print_faster_pieces(pieces, result);
    EXPECT_GE(ratio, 1.0 - 1e-6) << label << ": planner " << pieces.motion_time_s
                                 << " s, reference " << reference << " s";
    EXPECT_LE(ratio, 1.02) << label << ": planner " << pieces.motion_time_s << " s, reference "
                           << reference << " s";
    std::cout << "; planner/reference " << ratio;
  }
  std::cout << "\n";
  return plan.report;
}

// The wall plotter's drawings about its home (750, -700).
const motion::PlanOptions kPlotterHome = at_origin(750.0, -700.0);

TEST(PlannerPropertiesEdgeCases, ZeroLengthMovesTakeNoTime) {
  const motion::PlanReport report = check_edge_case(
      "wall-plotter.toml",
      "G21 G90 G64\nG1 X0 Y0 F3000\nG1 X10\nG1 X10\nG0 X10 Y0\nG1 X10 Y0 F100\nG1 X0\nM2\n",
      kPlotterHome);
  // Two moves of 10 mm.
  EXPECT_NEAR(report.path_length_mm, 20.0, 1e-9);
}

TEST(PlannerPropertiesEdgeCases, MovesOfTheAnglesAlone) {
  const motion::PlanReport report = check_edge_case(
      "hexapod-bit.toml",
      "G21 G90 G64\nG1 A5 F600\nG1 B-3 C2\nG0 A0 B0 C0\nG1 A2 F6000\nG1 A4 B1\nG1 X0.5 A3\nM2\n",
      {});
  EXPECT_GT(report.duration_s, 0.0);
}

// Without the reference on the plotter: its corner blend of 8.7e-7 mm (between the second move
// and the third) the planner crosses 1.9e-8 s faster than the reference (2.9170e-5 s against
// 2.9189e-5 s, 1.7e-6 of the job), where the reference's curvature by differences of poses
// 4e-8 mm apart near x = 750 mm is good to some 1e-4 (rounding of 1e-13 mm): not a finding.
TEST(PlannerPropertiesEdgeCases, MovesOfAMillionthOfAMillimetre) {
  check_edge_case("wall-plotter.toml",
                  "G21 G90 G64\nG1 X0.000001 F3000\nG1 X0.000002 Y0.000001\nG1 X10\n"
                  "G1 X10.000001\nG61\nG1 X10.000002\nM2\n",
                  kPlotterHome, 0.0);
  check_edge_case("hexapod-bit.toml", "G21 G90 G64\nG1 X0.000001 F3000\nG1 Z1000.000001\nM2\n", {});
}

// Corner to corner of the Maslow's sheet (2,550 mm, its tensions checked), across the wall
// plotter's board and through the hexapod's workspace.
TEST(PlannerPropertiesEdgeCases, VeryLongRapids) {
  check_edge_case("maslow-frame.toml", "G21 G90\nG0 X-1150 Y-550\nM2\n", at_origin(1489.2, -1072.6),
                  0.0);
  check_edge_case("wall-plotter.toml", "G21 G90\nG0 X-450 Y-400\nG0 X450 Y300\nM2\n",
                  at_origin(750.0, -1100.0));
  check_edge_case("hexapod-bit.toml", "G21 G90\nG0 X-150 Y-150 Z900\nG0 X150 Y150 Z1150\nM2\n", {});
}

TEST(PlannerPropertiesEdgeCases, BackAndForthInPlace) {
  std::string job = "G21 G90 G64 P0.01\nG1 F6000\n";
  for (int k = 0; k < 10; ++k) job += k % 2 ? "X0\n" : "X10\n";
  for (int k = 0; k < 10; ++k) job += k % 2 ? "X10\n" : "X10.01\n";
  job += "M2\n";
  check_edge_case("wall-plotter.toml", job, kPlotterHome);
  check_edge_case("triaglide.toml", job, at_origin(0.0, 0.0, 200.0));
}

TEST(PlannerPropertiesEdgeCases, FullCircles) {
  const std::string job = "G21 G90 G17\nG1 X0 Y0 F6000\nG2 X0 Y0 I10 J0\nG3 X0 Y0 I0 J-30\nM2\n";
  check_edge_case("wall-plotter.toml", job, kPlotterHome);
  check_edge_case("hexapod-bit.toml", job, at_origin(0.0, 0.0, 1000.0));
}

// An arc of 0.001 mm radius is refused at its line and column, as LinuxCNC refuses it (a radius
// below a tenth of its arc tolerance, 0.00283 mm, is zero); one of 0.003 mm is planned.
TEST(PlannerPropertiesEdgeCases, ArcsOfAFewMicrometresRadius) {
  const machine::Machine plotter = load_example("wall-plotter.toml");
  const TempProgram refused("G21 G90 G17\nG1 X10 F6000\nG2 X10 Y0 I0.001 J0\nM2\n");
  struct Discard final : motion::SampleSink {
    void write(const motion::Sample&) override {}
  } discard;
  try {
    motion::plan_program(plotter, refused.path(), {}, kPlotterHome, discard);
    ADD_FAILURE() << "an arc of 0.001 mm radius was planned";
  } catch (const std::exception& error) {
    EXPECT_NE(std::string(error.what()).find(":3:1: zero radius arc"), std::string::npos)
        << error.what();
  }
  check_edge_case("wall-plotter.toml",
                  "G21 G90 G17 G64\nG1 X10 F6000\nG2 X10 Y0 I0.003 J0\nG3 X10.006 Y0 I0.003 J0\n"
                  "G1 X20\nM2\n",
                  kPlotterHome);
}

TEST(PlannerPropertiesEdgeCases, CornersBlendedWithinAMicrometre) {
  std::string job = "G21 G90 G64 P0.001\nG1 X0 Y0 F6000\n";
  for (int k = 1; k <= 20; ++k) {
    job +=
        "X" + std::to_string(5 * k) + " Y" + std::to_string(k % 2 ? 5 : (k % 4 ? 0.2 : 0)) + "\n";
  }
  job += "M2\n";
  check_edge_case("wall-plotter.toml", job, kPlotterHome);
  check_edge_case("triaglide.toml", job, at_origin(-20.0, 0.0, 200.0));
}

TEST(PlannerPropertiesEdgeCases, AFeedOfAThousandthOfAMillimetreAMinute) {
  // 0.001 mm at 0.001 mm/min: 60 s.
  const motion::PlanReport report =
      check_edge_case("wall-plotter.toml", "G21 G90\nG1 X0.001 F0.001\nM2\n", kPlotterHome);
  EXPECT_NEAR(report.duration_s, 60.0, 1e-3);
}

TEST(PlannerPropertiesEdgeCases, DwellsBetweenMoves) {
  const motion::PlanReport report = check_edge_case(
      "wall-plotter.toml", "G21 G90 G64\nG1 X10 F3000\nG4 P0.5\nG1 X20\nG4 P0\nG1 X30\nM2\n",
      kPlotterHome);
  EXPECT_GT(report.duration_s, 0.5);
}

TEST(PlannerPropertiesEdgeCases, PenUpAndDownBetweenMoves) {
  const motion::PlanReport report =
      check_edge_case("pen-plotter.toml",
                      "G21 G90 G64\nG0 Z5\nG0 X10 Y10\nG1 Z-1 F600\nG1 X50 F3000\nG1 Z5\n"
                      "G0 X0 Y0\nG1 Z-1\nG2 X0 Y0 I10 J0\nG1 X5 Y5 Z5\nM2\n",
                      kPlotterHome);
  EXPECT_EQ(report.pen_changes, 4);
}

// A circle of 5 mm radius in 7,000 chords, each turning 0.9 mrad from the one before (below
// G64's tangent angle: joined without a blend or a stop), as fine CAM output is: its bend comes
// as several changes of direction a servo period, each within the junction's own bound.
std::string tangent_chord_circle() {
  std::ostringstream job;
  job.setf(std::ios::fixed);
  job.precision(9);
  job << "G21 G90 G64\nG1 X5 Y0 F6000\n";
  const int chords = 7000;
  for (int k = 1; k <= chords; ++k) {
    const double angle = 2.0 * std::numbers::pi * k / chords;
    job << "X" << 5.0 * std::cos(angle) << " Y" << 5.0 * std::sin(angle) << "\n";
  }
  job << "M2\n";
  return job.str();
}

TEST(PlannerPropertiesEdgeCases, ACircleOfTangentChordsKeepsTheToolAcceleration) {
  check_edge_case("matrix-mill.toml", tangent_chord_circle(), at_origin(300.0, 200.0, -100.0), 0.0);
}

// The same circle where the joints bind: a Cartesian machine whose tool may accelerate at
// 100,000 mm/s^2 and whose x and y joints at 1,000 mm/s^2.
TEST(PlannerPropertiesEdgeCases, ACircleOfTangentChordsKeepsTheJointAcceleration) {
  const std::string slow = "max_velocity = 1000.0\nmax_acceleration = 1000.0\n";
  const machine::Machine machine = test::cartesian_machine(slow, slow, slow, 100000.0);
  const TempProgram program(tangent_chord_circle());
  const CheckedPlan plan = plan_checked(machine, program.path(), {});
  expect_within_limits(plan, "slow-joints.toml, the circle of tangent chords");
  std::cout << shares(plan) << "\n";
}

// ---------------------------------------------------------------------------------------------
// The smallest jobs that show where the planner passes a limit (found by the tests above; they
// fail until the planner is fixed). Each is one short curved move from rest to rest whose samples
// pass a limit just after the middle of the move, where it turns from accelerating to braking.
// The likely cause (src/pkm/motion/time_optimal.cpp, advance()): in the grid interval where the
// speed peaks, the braking phase's u is checked against the limits at the interval's start speed
// (range) and at its end bound (at_end), both below the speed at the kink where braking starts;
// with a bend term (the tool's kappa x, a joint's q'' x) the limit at the kink is tighter.

// By hand on the Cartesian matrix mill (x y z joints; the tool's budget u^2 + (x / r)^2 <= A^2,
// A = 800 mm/s^2, binds before the joints' 1000): an arc of r = 3 mm turning 0.53 rad (1.59 mm,
// a grid of 11 intervals of 0.145 mm) from rest to rest. It peaks near x = 1100 mm^2/s^2 in the
// middle interval; braking from its start speed at u = -sqrt(A^2 - (x / r)^2) where the kink is
// some 2 u 0.07 = 100 mm^2/s^2 faster passes the budget by some 2 % there: a sample every 1 ms
// sees 803.97 mm/s^2 (0.5 %) at t = 0.169 s.
TEST(PlannerPropertiesReproducers, ShortArcFromRestToRestKeepsTheMatrixMillsToolAcceleration) {
  check_edge_case("matrix-mill.toml",
                  "G21 G90 G17\nG0 X303 Y200\nG3 X302.588421 Y201.516600 I-3 J0 F2500\nM2\n", {});
  // Sampled every 10 us the kink shows as it is: 815.66 mm/s^2 (1.96 % over) at t = 0.16749 s,
  // 207 samples over in the 2 ms after it.
  motion::PlanOptions fine;
  fine.period_s = 1e-5;
  check_edge_case("matrix-mill.toml",
                  "G21 G90 G17\nG0 X303 Y200\nG3 X302.588421 Y201.516600 I-3 J0 F2500\nM2\n", fine,
                  0.0);
}

// A G64 blend between a slow move and a fast one (triaglide random job 23: its line 2 at
// F378.7 and line 4 at F5744, blended over 4.04 mm, 0.640 s against the reference's 0.107 s,
// 1.033 of the reference over the job). The planner gives the blend the slower feed
// (look_ahead.cpp, blend(): min of the two moves' max_speed); the reference takes the blend
// segment's own feed_mm_per_s, which is the next move's; LinuxCNC's blend arcs take the faster
// of the two (blendmath.c: v_req = fmax(prev_tc->reqvel, tc->reqvel)). One of planner and
// reference is to change; until they agree, this fails. Here: a 90 deg corner of the wall
// plotter from F360 to F6000 with P1, a blend of r = 3.41 mm (5.36 mm long).
TEST(PlannerPropertiesReproducers, CornerBlendBetweenTwoFeedsPlannerAndReferenceAgree) {
  check_edge_case("wall-plotter.toml", "G21 G90 G64 P1\nG1 X20 F360\nG1 X20 Y20 F6000\nM2\n",
                  kPlotterHome);
}

// A square of 20 mm with blended corners (G64 P0.01) on LinuxCNC's rotary delta, whose joints
// (50 deg/s^2) bind: 2.908 s against the reference's 2.801 s (1.038); each line 0.02-0.04 s
// slower, the corners passed at about 2 mm/s. With G61 the same square is within 1.0006. The
// likely cause (feed_limits.cpp, limit_junction()): a corner's reserve of up to 20 % of a
// joint's acceleration is sized by the programmed feed (`passing`), not by the speed the corner
// is passed at, and held over at least kJointSampleStepMm (0.5 mm) and the grid intervals
// reaching into it, which at 2 mm/s is a quarter of a second a corner.
TEST(PlannerPropertiesReproducers, BlendedSquareOnTheRotaryDeltaWithinTwoPercentOfTheReference) {
  check_edge_case("linuxcnc-rdelta.toml",
                  "G21 G90 G64 P0.01\nG1 X20 F4000\nG1 X20 Y20\nG1 X0 Y20\nG1 X0 Y0\nM2\n", {});
}

// Dragon.nc's line 103 alone (an arc of 3.0 mm radius, 1.31 mm long, at F60 in/min) on the
// Maslow of the examples: joint 'left' at 101.06 mm/s^2 against its 100, and the tool at
// 101.28 mm/s^2 against its 100, at t = 11.806 s (the whole job: 43 samples over a joint's
// limit by up to 1.3 %, at the same arc in each of its passes and at line 189's).
TEST(PlannerPropertiesReproducers, DragonArcFromRestToRestKeepsTheMaslowsJointAcceleration) {
  check_edge_case(
      "maslow.toml",
      "G20 G90 G17\nG0 X-5.8594 Y-1.5697\nG3 X-5.9093 Y-1.5587 I-0.0499 J-0.107 F60\nM2\n",
      at_origin(1489.2, -1072.6));
}

// A helix of 1.1 mm radius rising 12.5 mm on LinuxCNC's rotary delta (a random job's third
// line): joint0 at 0.8791 rad/s^2 against its 50 deg/s^2 (0.8727 rad/s^2, 0.73 % over) at
// t = 1.028 s.
TEST(PlannerPropertiesReproducers, HelixFromRestToRestKeepsTheRotaryDeltasJointAcceleration) {
  check_edge_case("linuxcnc-rdelta.toml",
                  "G21 G90 G17\nG0 X-12.447362 Y-3.152604 Z-272.709133\n"
                  "G3 X-10.683310 Y-4.489357 I0.920841 J-0.617154 Z-260.255985 F3488.67195\nM2\n",
                  {});
}

}  // namespace
}  // namespace pkm::test
