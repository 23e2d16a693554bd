// Tension-limited motion of a hanging cable machine: the acceleration bound along a move, the
// junction speed and check's tension region against a symmetric V by hand, a refusal at rest that
// names the cable, and planned jobs (a real Maslow job and a hand-made aggressive one) whose
// every sample, with its acceleration by finite differences, keeps both cables within their
// tension limits, where the same jobs planned without the limits do not.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <numbers>
#include <sstream>

#include "pkm/kinematics/cable_plotter.hpp"
#include "pkm/machine/tension_region.hpp"
#include "pkm/motion/planner.hpp"
#include "pkm/motion/tension_limit.hpp"
#include "real_corpus.hpp"
#include "sample_limit_checks.hpp"
#include "test_support.hpp"

namespace pkm::motion {
namespace {

namespace fs = std::filesystem;

const fs::path kData = fs::path(PKM_SOURCE_DIR) / "tests" / "data";

std::string read_text(const fs::path& path) {
  std::ifstream file(path);
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

// The test frame (tests/data/maslow-tension.toml) as the ideal model sees it: chains tied at the
// bit, no mass, no tension limits; the same joints and Cartesian limits. The planner bounds
// nothing by tensions on it.
machine::Machine frame_without_tensions() {
  std::istringstream lines(read_text(kData / "maslow-tension.toml"));
  std::string text, line;
  while (std::getline(lines, line)) {
    if (line.starts_with("effector_") || line.starts_with("tension_limits")) continue;
    text += line + "\n";
  }
  return machine::parse_machine(text, "maslow-tension.toml without tensions");
}

machine::Machine frame() {
  return machine::load_machine(kData / "maslow-tension.toml");
}

const kinematics::CablePlotterKinematics& cables(const machine::Machine& machine) {
  return dynamic_cast<const kinematics::CablePlotterKinematics&>(machine.kinematics());
}

// Maslow jobs are written about the sheet's centre.
PlanOptions on_the_sheet() {
  PlanOptions options;
  options.origin << 1489.2, -1072.6, 0.0, 0.0, 0.0, 0.0;
  return options;
}

struct Discard final : SampleSink {
  void write(const Sample&) override {}
};

using test::TempProgram;

// The samples' tensions by statics (sample_limit_checks.hpp).
using test::TensionCheck;

// A symmetric V by hand: anchors 1000 mm apart, a 1 kg pen tied to both cables, tensions within
// [2, 20] N; joints and Cartesian limits out of the way. Home (500, -300).
const char* const kVee = R"(name = "V"
units = "mm"
[kinematics]
type = "cable_plotter"
anchor_distance = 1000.0
effector_mass = 1.0
tension_limits = [2.0, 20.0]
[[joints]]
name = "left"
min = 10.0
max = 2000.0
max_velocity = 10000.0
max_acceleration = 1e7
axis = "X"
[[joints]]
name = "right"
min = 10.0
max = 2000.0
max_velocity = 10000.0
max_acceleration = 1e7
axis = "Y"
[cartesian]
max_feed = 600000.0
max_acceleration = 100000.0
home = [500.0, -300.0]
)";

// On the V's axis, h below the anchors, each cable is at theta below level, sin theta =
// h / hypot(500, h), and carries T = m (g + a_y) / (2 sin theta). Up a vertical line from
// h = 500 to h = 300, accelerating upwards raises T, most where sin theta is least (h = 300):
// a_y <= 2 sin theta 20 N / 1 kg - g; braking (or accelerating downwards) lowers it, most where
// sin theta is greatest (h = 500): -a_y <= g - 2 sin theta 2 N / 1 kg. The moves use 0.8 of it.
TEST(TensionLimit, AlongAVerticalLineOfASymmetricVByHand) {
  const machine::Machine vee = machine::parse_machine(kVee, "vee.toml");
  const std::optional<TensionLimit> limit = TensionLimit::of(vee.kinematics());
  ASSERT_TRUE(limit.has_value());
  Segment line;
  line.start << 500.0, -500.0, 0.0, 0.0, 0.0, 0.0;
  line.end << 500.0, -300.0, 0.0, 0.0, 0.0, 0.0;
  const double g = 9.80665;                                  // m/s^2
  const double sin_high = 300.0 / std::hypot(500.0, 300.0);  // 0.514496
  const double sin_low = 500.0 / std::hypot(500.0, 500.0);   // 0.707107
  const double up = 2.0 * sin_high * 20.0 - g;               // 10.7732 m/s^2
  const double down = g - 2.0 * sin_low * 2.0;               // 6.97822 m/s^2: binds
  EXPECT_NEAR(up, 10.7732, 1e-4);
  EXPECT_NEAR(down, 6.97822, 1e-5);
  const TensionBound bound = limit->along(line, 200.0, 400, 1000.0, 1e5);
  EXPECT_FALSE(bound.speed_limited);
  EXPECT_EQ(bound.speed_mm_per_s, 1000.0);
  ASSERT_TRUE(bound.acceleration_limited);
  EXPECT_NEAR(bound.acceleration_mm_per_s2, 0.8 * 1000.0 * down, 1e-6);  // 5582.58 mm/s^2
  EXPECT_TRUE(bound.excess.slack);
  EXPECT_EQ(bound.excess.cable, 0);  // both alike: the left is named first
  // Below what the tensions allow, nothing changes.
  const TensionBound gentle = limit->along(line, 200.0, 400, 1000.0, 5000.0);
  EXPECT_FALSE(gentle.acceleration_limited);
  EXPECT_EQ(gentle.acceleration_mm_per_s2, 5000.0);
}

// At h = 500 (theta 45 deg) the path turns by 2 phi about the vertical, from (cos phi, -sin phi)
// to (cos phi, sin phi): the velocity's change v 2 sin phi points up and raises both tensions
// to m (g + c) / (2 sin theta) <= 20 N, c <= 18.4776 m/s^2, of which the junction has 0.2.
TEST(TensionLimit, AJunctionOfASymmetricVByHand) {
  const machine::Machine vee = machine::parse_machine(kVee, "vee.toml");
  const std::optional<TensionLimit> limit = TensionLimit::of(vee.kinematics());
  ASSERT_TRUE(limit.has_value());
  geometry::Vector6d at;
  at << 500.0, -500.0, 0.0, 0.0, 0.0, 0.0;
  const double phi = 0.01;
  const Eigen::Vector3d out(std::cos(phi), -std::sin(phi), 0.0),
      in(std::cos(phi), std::sin(phi), 0.0);
  const double jump = 2.0 * std::sin(phi);
  const double c = 0.2 * 1000.0 * (2.0 * std::sqrt(0.5) * 20.0 - 9.80665);  // 3695.52 mm/s^2
  EXPECT_NEAR(c, 3695.52, 0.01);
  // Long moves: the change happens within a period of 1 ms, v <= c 1 ms / jump.
  EXPECT_NEAR(limit->junction_speed(at, out, in, 1000.0, 1e-3, 1000.0), c * 1e-3 / jump, 1e-6);
  EXPECT_NEAR(c * 1e-3 / jump, 184.78, 0.01);
  // Chords of 0.1 mm: a change every 0.1 mm / v, v^2 jump / 0.1 mm <= c.
  EXPECT_NEAR(limit->junction_speed(at, out, in, 0.1, 1e-3, 1000.0), std::sqrt(c * 0.1 / jump),
              1e-6);
  // Slow enough already: unchanged.
  EXPECT_EQ(limit->junction_speed(at, out, in, 1000.0, 1e-3, 100.0), 100.0);
  // Machines without a hanging mass have no tension limit.
  EXPECT_FALSE(TensionLimit::of(machine::load_machine(fs::path(PKM_SOURCE_DIR) / "examples" /
                                                      "machines" / "wall-plotter.toml")
                                    .kinematics())
                   .has_value());
}

TEST(TensionLimitedPlan, ReportsTheMoveAndTheCableThatLimitedIt) {
  const machine::Machine vee = machine::parse_machine(kVee, "vee.toml");
  // Home (500, -300) down to h = 500 and back up at 100 mm/s: 2 s each at the feed, plus the
  // ramps. With 1 kg hanging at angle theta below both anchors, T = m (g - a_down) / (2 sin
  // theta): accelerating downwards (leaving the top, or braking there on the way up) takes the
  // cables towards their 2 N minimum, a_down <= g - 2 * 2 N sin theta / m; upwards (braking at
  // the bottom, or leaving it) towards their 20 N maximum, a_up <= 2 * 20 N sin theta / m - g.
  // Each ramp runs at what its own end allows (issue 29: not the least along the move).
  const TempProgram job("G1 Y-500 F6000\nG1 Y-300\nM2\n");
  TensionCheck check(cables(vee), 2.0, 20.0);
  const PlanReport report = plan_program(vee, job.path(), {}, {}, check);
  const double sin_top = 300.0 / std::hypot(500.0, 300.0), sin_bottom = std::sqrt(0.5);
  const double down_at_top = 9806.65 - 4000.0 * sin_top;       // 7748.67 mm/s^2
  const double up_at_bottom = 40000.0 * sin_bottom - 9806.65;  // 18477.6 mm/s^2
  const double least = 9806.65 - 4000.0 * sin_bottom;          // 6978.22: down, at the bottom
  ASSERT_EQ(report.tension_limits.size(), 2u);
  EXPECT_EQ(report.tension_limits[0].line, 1);
  EXPECT_EQ(report.tension_limits[1].line, 2);
  for (const TensionLimitedMove& move : report.tension_limits) {
    EXPECT_TRUE(move.slack);
    EXPECT_EQ(move.machine_mm_per_s2, 100000.0);
    EXPECT_NEAR(move.allowed_mm_per_s2, least, 1e-6);
  }
  // A ramp of 100 mm/s at a covers 100^2 / (2 a) mm and takes 100 / a s, 50 / a more than at the
  // feed: four ramps. Their 0.27 to 0.65 mm move the limit a little: 2e-5 s.
  const double ramps = 2.0 * (50.0 / down_at_top + 50.0 / up_at_bottom);
  EXPECT_NEAR(report.duration_s, 4.0 + ramps, 2e-5);  // 4.01832 s
  EXPECT_EQ(check.outside, 0) << check.first_outside;
  EXPECT_GT(check.worst_margin_N, 0.0);
}

TEST(TensionLimitedPlan, APoseOutsideTheLimitsAtRestNamesTheCableAndItsTension) {
  // Up from the sheet's centre towards the motors' line: the left cable (the bit left of the
  // middle) passes 300 N on the way.
  const TempProgram job("G1 X-100 Y800 F1000\nM2\n");
  Discard none;
  try {
    plan_program(frame(), job.path(), {}, on_the_sheet(), none);
    FAIL() << "planned";
  } catch (const PlanError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find(":1: the move leaves the machine's reach at "), std::string::npos)
        << message;
    EXPECT_NE(message.find("tension: the left cable would be overloaded: 300.00 N"),
              std::string::npos)
        << message;
    EXPECT_NE(message.find("above tension_limits' max 300 N (move the pen lower"),
              std::string::npos)
        << message;
  }
}

// One column of points on the V's axis (x = 500), 20 rows from the bottom of its reach (the left
// joint's 2000 mm: h = sqrt(2000^2 - 500^2)) up to the anchors: there T = m g / (2 sin theta) on
// both cables, above 20 N where h < 500 tan(asin(g / 40)) = 126.45 mm: the top row alone.
TEST(TensionRegion, OnTheAxisOfASymmetricVByHand) {
  const machine::Machine vee = machine::parse_machine(kVee, "vee.toml");
  const std::optional<machine::TensionRegion> region = machine::tension_region(vee, 1, 20);
  ASSERT_TRUE(region.has_value());
  const double bottom = std::sqrt(2000.0 * 2000.0 - 500.0 * 500.0);  // 1936.49 mm
  EXPECT_NEAR(region->min_mm.y(), -bottom, 1e-5);
  const double cell = bottom / 20.0;
  const auto tension = [](double h) { return 9.80665 / (2.0 * h / std::hypot(500.0, h)); };
  EXPECT_EQ(region->reached.points, 20);
  EXPECT_EQ(region->within.points, 19);
  for (std::size_t c = 0; c < 2; ++c) {
    EXPECT_EQ(region->over_max[c].points, 1);
    EXPECT_NEAR(region->over_max[c].min_mm.y(), -0.5 * cell, 1e-5);
    EXPECT_EQ(region->slack[c].points, 0);
  }
  // The reach's bottom is found to 1e-6 mm: so are the rows.
  EXPECT_NEAR(region->highest_N, tension(0.5 * cell), 1e-6);  // 50.88 N at h = 48.41 mm
  EXPECT_NEAR(region->highest_N, 50.88, 0.01);
  EXPECT_NEAR(region->lowest_N, tension(bottom - 0.5 * cell), 1e-6);  // 5.07 N
  EXPECT_NEAR(region->lowest_N, 5.07, 0.01);
  EXPECT_NEAR((region->highest_at_mm - Eigen::Vector2d(500.0, -0.5 * cell)).norm(), 0.0, 1e-5);
  // Machines without a hanging mass have none.
  EXPECT_FALSE(machine::tension_region(machine::load_machine(fs::path(PKM_SOURCE_DIR) / "examples" /
                                                             "machines" / "wall-plotter.toml"))
                   .has_value());
}

// Fast zig-zags (F30000, 500 mm/s) in the sheet's top corners and down its sides, then rapids
// across the top and corner to corner: where one chain pulls almost sideways with little
// tension, and where both pull nearly level with much.
std::string aggressive_job() {
  std::ostringstream job;
  job << "G21 G90 G64 P1\nG0 X-1150 Y580\nG1 F30000\n";
  for (int k = 0; k <= 12; ++k) job << "X" << -1150 + 25 * k << " Y" << (k % 2 ? 420 : 580) << "\n";
  for (int k = 0; k <= 12; ++k) job << "X" << 1150 - 25 * k << " Y" << (k % 2 ? 420 : 580) << "\n";
  job << "G0 X1180 Y560\nG1\n";
  for (int k = 0; k <= 20; ++k) job << "X" << (k % 2 ? 1060 : 1190) << " Y" << 560 - 55 * k << "\n";
  job << "G0 X-1190 Y560\nG1\n";
  for (int k = 0; k <= 20; ++k)
    job << "X" << (k % 2 ? -1060 : -1190) << " Y" << 560 - 55 * k << "\n";
  // The top half of a circle of 150 mm radius in the top-left corner at F60000 in 3500 chords
  // (0.13 mm, turning 0.9 mrad at each: tangent joins, no blends), as CAM output gives curves:
  // its centripetal acceleration comes as the chords' changes of direction, several per period.
  job << std::setprecision(10) << "G0 X-919 Y460\nG1 F60000\n";
  for (int k = 1; k <= 3500; ++k) {
    const double angle = std::numbers::pi * k / 3500.0;
    job << "X" << -1069.0 + 150.0 * std::cos(angle) << " Y" << 460.0 + 150.0 * std::sin(angle)
        << "\n";
  }
  // The same circle as one arc in the top-right corner: v^2 / r bounds its speed.
  job << "G0 X1219 Y460\nG2 X1219 Y460 I-150 J0\n";
  job << "G61\nG0 X-1150 Y590\nX1150\nX-1150 Y-590\nX1150 Y590\nX0 Y0\nM2\n";
  return job.str();
}

struct Outcome {
  PlanReport report;
  long outside = 0;
  double worst_margin_N = 0.0, lowest_N = 0.0, highest_N = 0.0;
  long checked = 0;
  std::string first_outside;
};

// Plans `job` on `machine` and checks its samples with the test frame's statics against its
// limits, 5 and 300 N.
Outcome plan_and_check(const machine::Machine& machine, const fs::path& job) {
  const machine::Machine checked_on = frame();
  TensionCheck check(cables(checked_on), 5.0, 300.0);
  Outcome outcome;
  outcome.report = plan_program(machine, job, {}, on_the_sheet(), check);
  outcome.outside = check.outside;
  outcome.worst_margin_N = check.worst_margin_N;
  outcome.lowest_N = check.lowest_N;
  outcome.highest_N = check.highest_N;
  outcome.checked = check.checked;
  outcome.first_outside = check.first_outside;
  return outcome;
}

void expect_bound_and_binding(const fs::path& job) {
  const Outcome limited = plan_and_check(frame(), job);
  EXPECT_EQ(limited.outside, 0) << limited.first_outside;
  EXPECT_GT(limited.checked, 1000);
  // The same job with the limits out of the way: its accelerations take the cables beyond them.
  const Outcome free = plan_and_check(frame_without_tensions(), job);
  EXPECT_GT(free.outside, 0);
  EXPECT_GT(limited.report.duration_s, free.report.duration_s);
  EXPECT_FALSE(limited.report.tension_limits.empty());
  std::printf(
      "  %s: %.3f s with tension limits, %.3f s without; tensions %.2f..%.2f N with "
      "(worst margin %.3f N), %.2f..%.2f N without (%ld of %ld samples outside "
      "[5, 300] N); %zu moves' acceleration lowered by tensions, %zu feeds\n",
      job.filename().string().c_str(), limited.report.duration_s, free.report.duration_s,
      limited.lowest_N, limited.highest_N, limited.worst_margin_N, free.lowest_N, free.highest_N,
      free.outside, free.checked, limited.report.tension_limits.size(),
      limited.report.feed_limits.size());
}

TEST(TensionLimitedPlan, NoSampleOfAnAggressiveJobLeavesTheTensionLimits) {
  const TempProgram job(aggressive_job());
  expect_bound_and_binding(job.path());
}

TEST(TensionLimitedPlan, NoSampleOfARealMaslowJobLeavesTheTensionLimits) {
  // GroundControl's calibration benchmark: marks across the whole 8 x 4 ft sheet.
  PKM_SKIP_WITHOUT_REAL_CORPUS();
  expect_bound_and_binding(test::real_corpus() / "cam" / "maslow" /
                           "calibration-benchmark-test.nc");
}

}  // namespace
}  // namespace pkm::motion
