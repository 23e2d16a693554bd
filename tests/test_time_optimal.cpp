// The time-optimal reference (tests/time_optimal_reference.hpp) against hand-worked timings, and
// the planner held to it (issue 29): never faster than the optimum (it would break a limit), at
// most 2 % slower. The five jobs of the issue are bench/plan_optimality.cpp's.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iostream>
#include <limits>
#include <numbers>
#include <string>

#include "pkm/kinematics/cable_statics.hpp"
#include "pkm/kinematics/hanging_cables.hpp"
#include "real_corpus.hpp"
#include "test_support.hpp"
#include "time_optimal_reference.hpp"

namespace pkm::test {
namespace {

constexpr double kGridMm = 0.05;
constexpr double kPeriodS = 0.001;

const std::string kFastJoint = std::string(kFastCartesianJoint);

PlannedJob plan_text(const machine::Machine& machine, const std::string& program,
                     motion::PlanOptions options = {}) {
  const TempProgram file(program);
  return plan_pieces(machine, file.path(), options);
}

double reference_time(const machine::Machine& machine, const PlannedJob& job,
                      double grid_mm = kGridMm) {
  return solve_reference(machine, job.pieces, kPeriodS, grid_mm).duration_s;
}

// One line from rest to rest: the reference is exact on a trapezoid at any grid (each step is
// timed as accelerating, cruising and braking within its start point's limits), to rounding.
TEST(TimeOptimalReference, TrapezoidOnALine) {
  const machine::Machine machine = cartesian_machine(kFastJoint, kFastJoint);
  const PlannedJob job = plan_text(machine, "G1 X100 F3000\nM2\n");
  ASSERT_EQ(job.pieces.size(), 1u);
  // 100 mm at 50 mm/s reached at 1000 mm/s^2: L / v + v / A = 2 + 0.05 s.
  EXPECT_NEAR(reference_time(machine, job), 2.05, 1e-9);
}

// A diagonal where joint x binds: dq_x/ds = 1/sqrt(2), so v = 30 sqrt(2) mm/s (below the feed of
// 100 mm/s) and the path acceleration is 500 sqrt(2) = 707 mm/s^2 (below A = 1000): 141.42 mm at
// 42.43 mm/s takes 10/3 s, plus v / a = 0.06 s. Exact as the trapezoid above.
TEST(TimeOptimalReference, JointLimitedDiagonal) {
  const machine::Machine machine =
      cartesian_machine("max_velocity = 30.0\nmax_acceleration = 500.0\n", kFastJoint);
  const PlannedJob job = plan_text(machine, "G1 X100 Y100 F6000\nM2\n");
  ASSERT_EQ(job.pieces.size(), 1u);
  EXPECT_NEAR(reference_time(machine, job), 10.0 / 3.0 + 0.06, 1e-9);
}

// Two lines 0.5 mrad apart (below G64's tangent angle: passed without stopping). Joint y's rate
// along the path jumps there from 0 to d = 0.05 / L2, and within one 1 ms period its velocity
// changes by v d: with its max_acceleration of 10 mm/s^2 the junction takes at most
// v = 10 * 0.001 / d = 0.2 L2 = 20.0000025 mm/s. Each line: accelerate or brake between rest and
// 100 mm/s at A = 1000 mm/s^2 (0.1 s over 5 mm), brake to or accelerate from v at the junction
// ((100 - v) / A s over (100^2 - v^2) / 2A mm), cruise the rest at 100 mm/s. Joint y's limit
// inside the second line (|d u| <= 10, u <= 20,000 mm/s^2) does not bind.
TEST(TimeOptimalReference, JunctionWhereAJointsRateJumps) {
  const machine::Machine machine =
      cartesian_machine(kFastJoint, "max_velocity = 1000.0\nmax_acceleration = 10.0\n");
  const PlannedJob job = plan_text(machine, "G1 X100 F6000\nG1 X200 Y0.05\nM2\n");
  ASSERT_EQ(job.pieces.size(), 2u);
  ASSERT_FALSE(job.pieces[0].stop_after);
  const double second = std::hypot(100.0, 0.05), v = 0.2 * second, a = 1000.0, feed = 100.0;
  const auto line_time = [&](double length) {
    const double ramps = feed * feed / (2.0 * a) + (feed * feed - v * v) / (2.0 * a);
    return feed / a + (feed - v) / a + (length - ramps) / feed;
  };
  const ReferenceResult result = solve_reference(machine, job.pieces, kPeriodS, kGridMm);
  EXPECT_NEAR(result.piece_durations_s[0], line_time(100.0), 1e-9);
  EXPECT_NEAR(result.piece_durations_s[1], line_time(second), 1e-9);
}

// A full circle of r = 4 mm from rest to rest, the feed (100 mm/s) above sqrt(A r) = 63.2 mm/s.
// With the budget u^2 + (x / r)^2 <= A^2 shared, x = A r sin(2 s / r) while accelerating, which
// reaches cruise at s = pi r / 4 after (1/2) sqrt(r / A) I, I = int_0^(pi/2) sin^(-1/2) =
// Gamma(1/4)^2 / (2 sqrt(2 pi)) = 2.62206; braking mirrors it, and 3 pi r / 2 is cruise:
// t = sqrt(r / A) (3 pi / 2 + I) = 0.463872 s. The grid's collocation (each step's acceleration
// from its start point) errs by O(ds^2): 9.5e-7 s at 0.05 mm (steps of 0.0175 mm: 0.25 deg of
// turn), 2.9e-7 s at 0.01 mm (measured).
TEST(TimeOptimalReference, CurvatureLimitedCircle) {
  const machine::Machine machine = cartesian_machine(kFastJoint, kFastJoint);
  const PlannedJob job = plan_text(machine, "G0 X4\nG2 X4 Y0 I-4 J0 F6000\nM2\n");
  ASSERT_EQ(job.pieces.size(), 2u);
  ASSERT_TRUE(job.pieces[0].stop_after);  // a rapid, then a feed move: stops between them
  const double r = 4.0, a = 1000.0;
  const double integral =
      std::pow(std::tgamma(0.25), 2) / (2.0 * std::sqrt(2.0 * std::numbers::pi));
  const double expected = std::sqrt(r / a) * (1.5 * std::numbers::pi + integral);
  EXPECT_NEAR(expected, 0.463872, 1e-6);
  const ReferenceResult result = solve_reference(machine, job.pieces, kPeriodS, kGridMm);
  EXPECT_NEAR(result.piece_durations_s[1], expected, 2e-6);
  EXPECT_NEAR(solve_reference(machine, job.pieces, kPeriodS, 0.01).piece_durations_s[1], expected,
              1e-6);
}

// A point effector of 9 kg on straight cables from anchors 2,000 mm apart, moved straight up the
// centre line from 1,000 mm below the anchors to 950 mm below them, at most 68 N a cable. There a
// cable at cos(theta) = |y| / R(y), R(y) = sqrt(1000^2 + y^2), from the vertical holds
// T = m (g + a) / (2 cos(theta)), so the upward acceleration is at most
// a(y) = 2 T_max |y| / (m R(y)) - g: 878 mm/s^2 at the start, 601 at the end (below A = 1000, so
// the tensions bind; braking lowers them). Accelerating at a(y) from rest gives
// v^2(y) = 2 (2 T_max / m (R(y0) - R(y)) - g (y - y0)), which reaches the feed of 100 mm/s after
// about 6 mm; then it cruises and brakes at A over the last 5 mm (0.1 s). The accelerating part's
// time is integral dy / v(y), summed here in steps of 1e-4 mm. The grid's collocation takes each
// step's acceleration at its start, where a(y) is highest: 8e-6 s fast at 0.05 mm (measured).
TEST(TimeOptimalReference, TensionLimitedClimb) {
  const machine::Machine machine = machine::parse_machine(R"(name = "Hanging point effector"
units = "mm"
[kinematics]
type = "cable_plotter"
anchor_distance = 2000.0
effector_mass = 9.0
tension_limits = [5.0, 68.0]
[[joints]]
name = "left"
min = 100.0
max = 3000.0
max_velocity = 1000.0
max_acceleration = 100000.0
axis = "X"
[[joints]]
name = "right"
min = 100.0
max = 3000.0
max_velocity = 1000.0
max_acceleration = 100000.0
axis = "Y"
[cartesian]
max_feed = 6000.0
max_acceleration = 1000.0
home = [1000.0, -1000.0]
)",
                                                          "hanging-point.toml");
  const PlannedJob job = plan_text(machine, "G1 X1000 Y-950 F6000\nM2\n");
  ASSERT_EQ(job.pieces.size(), 1u);
  const double g = 9806.65, pull = 2.0 * 68.0 / 9.0 * 1000.0;  // mm/s^2
  const auto radius = [](double y) { return std::hypot(1000.0, y); };
  const auto speed_squared = [&](double y) {
    return 2.0 * (pull * (radius(-1000.0) - radius(y)) - g * (y + 1000.0));
  };
  EXPECT_NEAR(pull * 1000.0 / radius(-1000.0) - g, 878.0, 1.0);
  EXPECT_NEAR(pull * 950.0 / radius(-950.0) - g, 601.0, 1.0);
  const double feed = 100.0, a = 1000.0, step = 1e-4;
  double y = -1000.0, accelerating = 0.0;
  while (speed_squared(y + step) < feed * feed) {
    accelerating += 2.0 * step / (std::sqrt(speed_squared(y)) + std::sqrt(speed_squared(y + step)));
    y += step;
  }
  // The last part step up to the feed, then cruise to where braking at A starts.
  const double braking = feed * feed / (2.0 * a);
  const double expected = accelerating + 2.0 * step / (std::sqrt(speed_squared(y)) + feed) +
                          (-950.0 - braking - (y + step)) / feed + feed / a;
  EXPECT_NEAR(reference_time(machine, job), expected, 2e-5);
}

// The first `lines` lines of a file, ended by M2.
std::string excerpt(const std::filesystem::path& path, int lines) {
  std::ifstream in(path);
  std::string text, line;
  for (int k = 0; k < lines && std::getline(in, line); ++k) text += line + "\n";
  return text + "M2\n";
}

// The paper's sphere (examples/jobs/sphere.ngc): arcs whose tool axis turns.
std::string sphere_excerpt(int lines) {
  return excerpt(std::filesystem::path(PKM_SOURCE_DIR) / "examples" / "jobs" / "sphere.ngc", lines);
}

// PartKam's Dragon.nc of the real corpus: inch arcs of a few mm radius, joined tangent or at
// corners.
std::string dragon_excerpt(int lines) {
  return excerpt(real_corpus() / "cam" / "maslow" / "Dragon.nc", lines);
}

// tests/data/maslow-tension.toml: 9 kg on cables, 5..300 N, its joints and tool tip far faster
// than the tensions allow. The job: sideways lines near the top, where a cable nears slack, and a
// blended corner.
machine::Machine tension_machine() {
  return machine::load_machine(std::filesystem::path(PKM_SOURCE_DIR) / "tests" / "data" /
                               "maslow-tension.toml");
}
const char* kTensionJob =
    "G21 G90 G64\nG0 X-100 Y350\nG1 X100 F30000\nG1 X100 Y200\nG1 X-100 Y150\nM2\n";

// A real-shaped job with arcs, G64 blends and tangent joins on the wall plotter: halving the grid
// changes the optimum by less than 1e-7 of it, and by less each time.
const char* kPlotterJob = R"(G21 G90 G64 P0.2
G0 X0 Y0
G1 X100 Y0 F6000
G1 X100 Y60
G3 X60 Y100 I-40 J0
G1 X0 Y100
G2 X-30 Y70 I0 J-30
G1 X-30 Y30
G1 X0 Y0
G1 X50 Y5
G1 X100 Y0
M2
)";

motion::PlanOptions at_origin(double x, double y, double z = 0.0) {
  motion::PlanOptions options;
  options.origin << x, y, z, 0.0, 0.0, 0.0;
  return options;
}

TEST(TimeOptimalReference, ConvergedByHalvingTheGrid) {
  const machine::Machine machine = load_example("wall-plotter.toml");
  const PlannedJob job = plan_text(machine, kPlotterJob, at_origin(700.0, -900.0));
  const double coarse = reference_time(machine, job, 0.1);
  const double fine = reference_time(machine, job, kGridMm);
  const double finer = reference_time(machine, job, 0.025);
  // Measured: 8.3e-8 from 0.1 to 0.05 mm, 2.0e-8 from 0.05 to 0.025 mm (second order).
  EXPECT_NEAR(fine / finer, 1.0, 1e-7) << coarse << " " << fine << " " << finer;
  EXPECT_LE(std::abs(fine - finer), 0.5 * std::abs(coarse - fine));
}

// The reference's own speed profile (its passes' steps, each at one acceleration) sampled every
// 0.1 ms, the joints by inverse kinematics of Segment::at: the largest share of each limit the
// samples' finite differences reach, joints' velocities and accelerations and the tool tip's
// acceleration. Only differences within one piece: at a junction the reference lets each joint
// take its jump of rate within a servo period on top of its acceleration, as a lower bound must.
struct LimitShares {
  double joint_velocity = 0.0, joint_acceleration = 0.0, tool_acceleration = 0.0;
  // On a cable machine whose effector has a mass: the furthest the sampled tensions go past
  // tension_min_N or tension_max_N (N; negative: within them by that much).
  double tension_excess_N = -std::numeric_limits<double>::infinity();
};

// The tensions' furthest excess (N) with the effector at `pose` accelerating at `acceleration`.
double tension_excess(const kinematics::HangingCables& cables, const geometry::Vector6d& pose,
                      const Eigen::Vector3d& acceleration) {
  kinematics::CableStatics out;
  if (!cables.statics(geometry::Pose::from_vector(pose), acceleration.head<2>(), out).ok()) {
    return std::numeric_limits<double>::infinity();
  }
  double excess = -std::numeric_limits<double>::infinity();
  for (int k = 0; k < 2; ++k) {
    excess = std::max({excess, cables.tension_min_N() - out.lowest_N[k],
                       out.highest_N[k] - cables.tension_max_N()});
  }
  return excess;
}

LimitShares profile_limit_shares(const machine::Machine& machine, const PlannedJob& job,
                                 const ReferenceResult& reference) {
  const double dt = 1e-4;
  LimitShares shares;
  std::size_t piece = job.pieces.size();
  int history = 0;
  const kinematics::HangingCables* cables = machine.kinematics().hanging_cables();
  if (cables && !(cables->effector_mass_kg() > 0.0)) cables = nullptr;
  geometry::Vector6d pose_before = geometry::Vector6d::Zero();
  kinematics::JointVector q, q1, q2;
  Eigen::Vector3d p = Eigen::Vector3d::Zero(), p1 = p, p2 = p;
  double start = 0.0;  // the step's start time
  long k = 0;          // the next sample, at k dt
  for (const ProfileStep& step : reference.profile) {
    const double u =
        (std::pow(step.v1_mm_per_s, 2) - std::pow(step.v0_mm_per_s, 2)) / (2.0 * step.step_mm);
    const double duration = 2.0 * step.step_mm / (step.v0_mm_per_s + step.v1_mm_per_s);
    const motion::Segment& segment = job.pieces[step.piece].segment;
    if (step.piece != piece) history = 0;
    piece = step.piece;
    for (; static_cast<double>(k) * dt < start + duration; ++k) {
      const double tau = static_cast<double>(k) * dt - start;
      const double s = step.s_mm + step.v0_mm_per_s * tau + 0.5 * u * tau * tau;
      const geometry::Vector6d pose = segment.at(s / segment.length());
      EXPECT_TRUE(machine.inverse(geometry::Pose::from_vector(pose), q).ok());
      p = pose.head<3>();
      if (segment.z_free) p.z() = 0.0;
      if (history >= 1) {
        for (int j = 0; j < q.size(); ++j) {
          const machine::JointSpec& joint = machine.joints()[static_cast<std::size_t>(j)];
          shares.joint_velocity =
              std::max(shares.joint_velocity, std::abs(q[j] - q1[j]) / dt / joint.max_velocity);
          if (history >= 2) {
            shares.joint_acceleration =
                std::max(shares.joint_acceleration,
                         std::abs(q[j] - 2.0 * q1[j] + q2[j]) / (dt * dt) / joint.max_acceleration);
          }
        }
      }
      if (history >= 2) {
        const Eigen::Vector3d acceleration = (p - 2.0 * p1 + p2) / (dt * dt);
        shares.tool_acceleration =
            std::max(shares.tool_acceleration,
                     acceleration.norm() / machine.cartesian().max_acceleration_mm_per_s2);
        if (cables) {  // the acceleration of the sample before, at its pose
          shares.tension_excess_N =
              std::max(shares.tension_excess_N, tension_excess(*cables, pose_before, acceleration));
        }
      }
      q2 = q1;
      q1 = q;
      p2 = p1;
      p1 = p;
      pose_before = pose;
      ++history;
    }
    start += duration;
  }
  return shares;
}

// The profile keeps every limit within 1 % (the steps' acceleration is chosen at their start
// point; within a step the path's curvature and the joints' rates move on).
void expect_profile_within_limits(const machine::Machine& machine, const PlannedJob& job,
                                  double tension_tolerance_N = 0.0) {
  const ReferenceResult reference = solve_reference(machine, job.pieces, kPeriodS, kGridMm, true);
  const LimitShares shares = profile_limit_shares(machine, job, reference);
  EXPECT_LE(shares.joint_velocity, 1.01);
  EXPECT_LE(shares.joint_acceleration, 1.01);
  EXPECT_LE(shares.tool_acceleration, 1.01);
  EXPECT_LE(shares.tension_excess_N, tension_tolerance_N);
  std::cout << "shares of the limits: joint velocity " << shares.joint_velocity
            << ", joint acceleration " << shares.joint_acceleration << ", tool tip acceleration "
            << shares.tool_acceleration << ", tensions past their limits by "
            << shares.tension_excess_N << " N\n";
}

TEST(TimeOptimalReference, OwnProfileKeepsTheLimitsOnTheWallPlotter) {
  const machine::Machine machine = load_example("wall-plotter.toml");
  expect_profile_within_limits(machine, plan_text(machine, kPlotterJob, at_origin(700.0, -900.0)));
}

TEST(TimeOptimalReference, OwnProfileKeepsTheLimitsOnTheTensionMachine) {
  const machine::Machine machine = tension_machine();
  expect_profile_within_limits(machine, plan_text(machine, kTensionJob, at_origin(1489.2, -1072.6)),
                               0.5);
}

TEST(TimeOptimalReference, OwnProfileKeepsTheLimitsOnTheHexapodSphere) {
  const machine::Machine machine = load_example("hexapod-bit.toml");
  expect_profile_within_limits(machine, plan_text(machine, sphere_excerpt(40)));
}

TEST(TimeOptimalReference, OwnProfileKeepsTheLimitsOnTheMaslowDragon) {
  PKM_SKIP_WITHOUT_REAL_CORPUS();
  const machine::Machine machine = load_example("maslow.toml");
  expect_profile_within_limits(machine,
                               plan_text(machine, dragon_excerpt(150), at_origin(1489.2, -1072.6)));
}

// The planner against the reference: >= 1 - 1e-6 (faster than the optimum, one of the two breaks
// a limit) and <= 1.02 (issue 29's bar). The reference on a grid of 0.01 mm: at 0.05 mm it lies
// up to 2e-6 from its value on finer grids (the sphere's rings, the circle), at 0.01 mm within
// 5e-7 of its value at 0.005 mm.
constexpr double kFineGridMm = 0.01;

void expect_near_optimal(const machine::Machine& machine, const PlannedJob& job,
                         double grid_mm = kFineGridMm) {
  ASSERT_FALSE(job.pieces.empty());
  const double reference = reference_time(machine, job, grid_mm);
  const double ratio = job.motion_time_s / reference;
  EXPECT_GE(ratio, 1.0 - 1e-6) << "planner " << job.motion_time_s << " s, reference " << reference
                               << " s";
  EXPECT_LE(ratio, 1.02) << "planner " << job.motion_time_s << " s, reference " << reference
                         << " s";
  ::testing::Test::RecordProperty("ratio", std::to_string(ratio));
  std::cout << "planner/reference " << job.motion_time_s << " / " << reference << " s = " << ratio
            << "\n";
}

TEST(PlannerAgainstReference, TrapezoidWithinTwoPercent) {
  const machine::Machine machine = cartesian_machine(kFastJoint, kFastJoint);
  expect_near_optimal(machine, plan_text(machine, "G1 X100 F3000\nM2\n"));
}

TEST(PlannerAgainstReference, JointLimitedDiagonalWithinTwoPercent) {
  const machine::Machine machine =
      cartesian_machine("max_velocity = 30.0\nmax_acceleration = 500.0\n", kFastJoint);
  expect_near_optimal(machine, plan_text(machine, "G1 X100 Y100 F6000\nM2\n"));
}

TEST(PlannerAgainstReference, JunctionWhereAJointsRateJumpsWithinTwoPercent) {
  const machine::Machine machine =
      cartesian_machine(kFastJoint, "max_velocity = 1000.0\nmax_acceleration = 10.0\n");
  expect_near_optimal(machine, plan_text(machine, "G1 X100 F6000\nG1 X200 Y0.05\nM2\n"));
}

TEST(PlannerAgainstReference, CurvatureLimitedCircleWithinTwoPercent) {
  const machine::Machine machine = cartesian_machine(kFastJoint, kFastJoint);
  expect_near_optimal(machine, plan_text(machine, "G0 X4\nG2 X4 Y0 I-4 J0 F6000\nM2\n"));
}

TEST(PlannerAgainstReference, WallPlotterBlendsAndArcsWithinTwoPercent) {
  const machine::Machine machine = load_example("wall-plotter.toml");
  expect_near_optimal(machine, plan_text(machine, kPlotterJob, at_origin(700.0, -900.0)));
}

// The paper's sphere on the hexapod: arcs whose tool axis turns, joined where the joints' rates
// jump.
TEST(PlannerAgainstReference, HexapodSphereFirstRingsWithinTwoPercent) {
  const machine::Machine machine = load_example("hexapod-bit.toml");
  expect_near_optimal(machine, plan_text(machine, sphere_excerpt(40)));
}

// The tension-limited machine and job (tension_machine(), kTensionJob).
TEST(PlannerAgainstReference, TensionLimitedMovesWithinTwoPercent) {
  const machine::Machine machine = tension_machine();
  // At 0.05 mm: within 2e-8 of the reference on 0.025 and 0.01 mm, and five times faster.
  expect_near_optimal(machine, plan_text(machine, kTensionJob, at_origin(1489.2, -1072.6)),
                      kGridMm);
}

// The first 150 lines of a real Maslow job (Dragon.nc) on the Maslow of the examples.
TEST(PlannerAgainstReference, MaslowDragonExcerptWithinTwoPercent) {
  PKM_SKIP_WITHOUT_REAL_CORPUS();
  const machine::Machine machine = load_example("maslow.toml");
  expect_near_optimal(machine, plan_text(machine, dragon_excerpt(150), at_origin(1489.2, -1072.6)));
}

}  // namespace
}  // namespace pkm::test
