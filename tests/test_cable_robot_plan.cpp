// Tension-limited planning for an effector held by n cables (a cable_robot): the force polytope
// (cable_force_polytope.hpp) against the tension distribution on random structures and loads,
// and jobs planned on a Hangprinter v4 with a heavy effector whose every sample's acceleration
// (finite differences) the cables hold within their limits, with the limit reached, where the
// same jobs planned without it are not held. Maslow 4 (no mass) plans no tension limit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <regex>
#include <sstream>

#include "pkm/kinematics/cable_force_polytope.hpp"
#include "pkm/kinematics/cable_tensions.hpp"
#include "pkm/machine/machine.hpp"
#include "pkm/motion/planner.hpp"
#include "pkm/motion/tension_limit.hpp"
#include "real_corpus.hpp"
#include "test_support.hpp"

namespace pkm::motion {
namespace {

namespace fs = std::filesystem;
using kinematics::CableForcePolytope;
using kinematics::StructureMatrix;
using kinematics::TensionTargets;

const fs::path kMachines = fs::path(PKM_SOURCE_DIR) / "examples" / "machines";

std::string read_text(const fs::path& path) {
  std::ifstream file(path);
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

// The Hangprinter v4 example with its effector's mass set to `kg` (0: no tension limit planned).
machine::Machine hangprinter(double kg) {
  const std::string text = std::regex_replace(read_text(kMachines / "hangprinter-v4.toml"),
                                              std::regex("effector_mass = 1\\.0"),
                                              "effector_mass = " + std::to_string(kg));
  return machine::parse_machine(text, "hangprinter-v4.toml");
}

// Random unit columns (d rows, n cables) spanning the d directions.
StructureMatrix random_structure(std::mt19937& random, int d, int n) {
  std::normal_distribution<double> normal(0.0, 1.0);
  StructureMatrix a(d, n);
  for (int k = 0; k < n; ++k) {
    Eigen::Vector3d column(normal(random), normal(random), normal(random));
    a.col(k) = column.head(d).normalized();
  }
  return a;
}

// Inside the polytope exactly where the distribution holds the load, away from the border by
// 1e-9 of the forces' scale; with finite limits and with [min, inf).
void expect_polytope_is_the_distribution(int d, bool finite_max) {
  std::mt19937 random(1234 + d + (finite_max ? 10 : 0));
  long inside = 0, outside = 0;
  for (int trial = 0; trial < 30; ++trial) {
    const int n = d + 1 + trial % 5;
    const StructureMatrix a = random_structure(random, d, n);
    const double max = finite_max ? 70.0 : std::numeric_limits<double>::infinity();
    const TensionTargets targets = finite_max ? TensionTargets::middle(n, 2.0, max)
                                              : TensionTargets::uniform(n, 2.0, max, 5.0);
    CableForcePolytope polytope;
    ASSERT_TRUE(kinematics::cable_force_polytope(a, targets, polytope));
    EXPECT_EQ(polytope.count, d == 2 ? n : n * (n - 1) / 2);
    std::uniform_real_distribution<double> force(-150.0, 150.0);
    for (int sample = 0; sample < 100; ++sample) {
      const Eigen::Vector3d f(force(random), force(random), d == 3 ? force(random) : 0.0);
      int facet = -1;
      bool high = false;
      const double margin = polytope.margin_N(f, facet, high);
      if (std::abs(margin) < 1e-9 * 150.0 * n) continue;
      const kinematics::WrenchVector wrench = -f.head(d);
      const kinematics::TensionDistribution distribution =
          kinematics::distribute_tensions(a, wrench, targets);
      EXPECT_EQ(margin > 0.0, distribution.held())
          << "d " << d << " n " << n << " margin " << margin << " N, violation "
          << distribution.largest_violation_N;
      (margin > 0.0 ? inside : outside) += 1;
    }
  }
  // Both answers are tried many times.
  EXPECT_GT(inside, 200);
  EXPECT_GT(outside, 200);
}

TEST(CableForcePolytope, PlanarIsTheTensionDistribution) {
  expect_polytope_is_the_distribution(2, true);
  expect_polytope_is_the_distribution(2, false);
}

TEST(CableForcePolytope, SpatialIsTheTensionDistribution) {
  expect_polytope_is_the_distribution(3, true);
  expect_polytope_is_the_distribution(3, false);
}

TEST(CableForcePolytope, TwoCablesAlongXByHand) {
  // Cables along +x and +y, tensions in [1, 10] N: forces [1, 10] x [1, 10]; the facets are the
  // square's sides, normals perpendicular to each cable: cable 1's (0, 1) bounds F_y, cable 2's
  // (-1, 0) bounds -F_x within [-10, -1].
  StructureMatrix a(2, 2);
  a << 1.0, 0.0, 0.0, 1.0;
  CableForcePolytope polytope;
  ASSERT_TRUE(kinematics::cable_force_polytope(a, TensionTargets::middle(2, 1.0, 10.0), polytope));
  ASSERT_EQ(polytope.count, 2);
  int facet = -1;
  bool high = false;
  EXPECT_DOUBLE_EQ(polytope.margin_N(Eigen::Vector3d(4.0, 9.0, 0.0), facet, high), 1.0);
  EXPECT_TRUE(high);
  EXPECT_EQ(polytope.facets[static_cast<std::size_t>(facet)].first_cable, 0);  // normal along y
  EXPECT_DOUBLE_EQ(polytope.margin_N(Eigen::Vector3d(0.5, 5.0, 0.0), facet, high), -0.5);
  EXPECT_TRUE(high);  // -F_x = -0.5 above -1
  EXPECT_EQ(polytope.facets[static_cast<std::size_t>(facet)].first_cable, 1);
  // Parallel cables span one direction only: refused.
  a << 1.0, 1.0, 0.0, 0.0;
  EXPECT_FALSE(kinematics::cable_force_polytope(a, TensionTargets::middle(2, 1.0, 10.0), polytope));
}

// Each sample's acceleration by finite differences (x y z), the tensions that hold the effector
// there (the distribution), how far any goes beyond its limits, and the largest share of the
// headroom at rest the acceleration used along any facet.
class ForceCheck final : public SampleSink {
 public:
  explicit ForceCheck(const kinematics::CableTensions& cables) : cables_(cables) {}

  void write(const Sample& sample) override {
    window_[0] = window_[1];
    window_[1] = window_[2];
    window_[2] = sample;
    if (++count_ >= 3) check(window_[0], window_[1], window_[2]);
  }

  long checked = 0, outside = 0;
  double worst_violation_N = 0.0;  // beyond a limit, at the least-violating tensions
  double most_used = 0.0;          // of a facet's headroom at rest
  std::string first_outside;

 private:
  void check(const Sample& before, const Sample& at, const Sample& after) {
    const double dt0 = at.time_s - before.time_s, dt1 = after.time_s - at.time_s;
    if (!(dt0 > 0.0) || !(dt1 > 0.0)) return;
    const Eigen::Vector3d v0 = (at.pose.head<3>() - before.pose.head<3>()) / dt0;
    const Eigen::Vector3d v1 = (after.pose.head<3>() - at.pose.head<3>()) / dt1;
    const Eigen::Vector3d acceleration = 2.0 * (v1 - v0) / (dt0 + dt1);
    const geometry::Pose pose = geometry::Pose::from_vector(at.pose);
    ++checked;
    const std::optional<kinematics::TensionDistribution> held =
        cables_.tensions(pose, acceleration);
    ASSERT_TRUE(held.has_value());
    if (!held->held()) {
      if (outside++ == 0) {
        std::ostringstream text;
        text << "line " << at.line << " t " << at.time_s << " s, a " << acceleration.transpose()
             << ": " << kinematics::describe_refusal(*held);
        first_outside = text.str();
      }
      worst_violation_N = std::max(worst_violation_N, held->largest_violation_N);
    }
    kinematics::CableForcePolytope polytope;
    ASSERT_TRUE(cables_.force_polytope(pose, polytope));
    const Eigen::Vector3d rest = cables_.cable_force_N(Eigen::Vector3d::Zero());
    const Eigen::Vector3d force = cables_.cable_force_N(acceleration);
    for (int f = 0; f < polytope.count; ++f) {
      const kinematics::ForceFacet& facet = polytope.facets[static_cast<std::size_t>(f)];
      const double change = facet.normal.dot(force - rest), here = facet.normal.dot(rest);
      const double room = change > 0.0 ? facet.high_N - here : here - facet.low_N;
      if (room > 1e-9) most_used = std::max(most_used, std::abs(change) / room);
    }
  }

  const kinematics::CableTensions& cables_;
  std::array<Sample, 3> window_{};
  long count_ = 0;
};

struct Outcome {
  PlanReport report;
  long checked = 0, outside = 0;
  double worst_violation_N = 0.0, most_used = 0.0;
  std::string first_outside;
};

// Plans `job` on `planned_on` and checks its samples with `checked_on`'s cables.
Outcome plan_and_check(const machine::Machine& planned_on, const machine::Machine& checked_on,
                       const fs::path& job, const PlanOptions& options) {
  ForceCheck check(*checked_on.kinematics().cable_tensions());
  Outcome outcome;
  outcome.report = plan_program(planned_on, job, {}, options, check);
  outcome.checked = check.checked;
  outcome.outside = check.outside;
  outcome.worst_violation_N = check.worst_violation_N;
  outcome.most_used = check.most_used;
  outcome.first_outside = check.first_outside;
  return outcome;
}

// A heavy effector (the Hangprinter's 6 kg: 59 N of the 70 N its lines may carry, most of it on D
// above; Maslow's 9 kg sled): the limited plan keeps every sample held, uses nearly all of the
// headroom's move share, and is slower than the plan of `massless` (the same machine without its
// mass), which ignores the tensions and whose samples the cables do not all hold.
void expect_held_and_binding(const machine::Machine& heavy, const machine::Machine& massless,
                             const fs::path& job, const PlanOptions& options) {
  const Outcome limited = plan_and_check(heavy, heavy, job, options);
  const Outcome free = plan_and_check(massless, heavy, job, options);
  EXPECT_GT(limited.checked, 1000);
  EXPECT_EQ(limited.outside, 0) << limited.first_outside;
  EXPECT_EQ(limited.worst_violation_N, 0.0);
  EXPECT_LE(limited.most_used, 1.0 + 1e-6);
  // The limit is reached: the moves take nearly their share of the headroom (the junctions the
  // rest).
  EXPECT_GT(limited.most_used, 0.95 * kTensionMoveShare);
  EXPECT_FALSE(limited.report.tension_limits.empty());
  EXPECT_GT(free.outside, 0);
  EXPECT_GT(limited.report.duration_s, free.report.duration_s);
  std::printf(
      "  %s: %.3f s with the tension limit, %.3f s without; with: %.4f of a facet's headroom "
      "used at most, %ld of %ld samples not held; without: %ld not held (worst %.3f N beyond); "
      "%zu moves' acceleration lowered by tensions, first line %d cable %d (%s)\n",
      job.filename().string().c_str(), limited.report.duration_s, free.report.duration_s,
      limited.most_used, limited.outside, limited.checked, free.outside, free.worst_violation_N,
      limited.report.tension_limits.size(),
      limited.report.tension_limits.empty() ? 0 : limited.report.tension_limits.front().line,
      limited.report.tension_limits.empty() ? -1 : limited.report.tension_limits.front().cable + 1,
      limited.report.tension_limits.empty()
          ? ""
          : (limited.report.tension_limits.front().slack ? "slack" : "at its max"));
}

TEST(CableRobotPlan, VerticalZigzagIsHeldAndTheLimitBinds) {
  // Up and down through the middle and out sideways: braking a rise and starting a descent
  // unload D, starting a rise loads it towards 70 N.
  const test::TempProgram job(
      "G21 G90 G64 P0.1\nG1 X0 Y0 Z200 F30000\nG1 Z900\nG1 X200 Y-150 Z150\nG1 Z350\nG1 "
      "X-150 Y100 Z200\nG1 X0 Y0 Z500\nG0 Z100\nG0 Z900\nG0 Z0\nM2\n");
  expect_held_and_binding(hangprinter(6.0), hangprinter(0.0), job.path(), {});
}

TEST(CableRobotPlan, JerkLimitedZigzagIsHeld) {
  // With --jerk one acceleration serves a move: the least the tensions allow along it, 80 % of
  // the headroom (the rest for the junctions).
  const test::TempProgram job(
      "G21 G90 G64 P0.1\nG1 X0 Y0 Z200 F30000\nG1 Z900\nG1 X200 Y-150 Z150\nG1 Z350\nG1 "
      "X-150 Y100 Z200\nG1 X0 Y0 Z500\nG0 Z100\nG0 Z900\nG0 Z0\nM2\n");
  PlanOptions options;
  options.jerk_mm_per_s3 = 1e5;
  const machine::Machine heavy = hangprinter(6.0);
  const Outcome limited = plan_and_check(heavy, heavy, job.path(), options);
  const Outcome free = plan_and_check(hangprinter(0.0), heavy, job.path(), options);
  EXPECT_GT(limited.checked, 1000);
  EXPECT_EQ(limited.outside, 0) << limited.first_outside;
  EXPECT_LE(limited.most_used, 1.0 + 1e-6);
  EXPECT_FALSE(limited.report.tension_limits.empty());
  EXPECT_GT(free.outside, 0);
  std::printf(
      "  jerk-limited zigzag: %.3f s with the tension limit, %.3f s without; %.4f of a "
      "facet's headroom used at most; without: %ld of %ld samples not held (worst %.3f N)\n",
      limited.report.duration_s, free.report.duration_s, limited.most_used, free.outside,
      free.checked, free.worst_violation_N);
}

TEST(CableRobotPlan, RealSurfacingJobAtAHeightIsHeld) {
  // LinuxCNC's 3D_Chips (a 100 x 100 x 50 mm ball-nose surfacing, all G1 with z) at z 400 mm,
  // its feed scaled up by its own #<fscale>.
  PKM_SKIP_WITHOUT_REAL_CORPUS();
  PlanOptions options;
  options.origin << 0.0, 0.0, 400.0, 0.0, 0.0, 0.0;
  expect_held_and_binding(hangprinter(6.0), hangprinter(0.0),
                          test::real_corpus() / "linuxcnc" / "3D_Chips.ngc", options);
}

// Maslow 4 given a 9 kg sled on a frame tilted 15 deg from level, belts within [5, 30] N and a
// fast router (3000 mm/s^2): a planar robot's facets (one per belt) bound its acceleration.
machine::Machine heavy_maslow(double kg) {
  std::string text = read_text(kMachines / "maslow4.toml");
  text = std::regex_replace(text, std::regex("cables_follow_z = true"),
                            "cables_follow_z = true\neffector_mass = " + std::to_string(kg) +
                                "\ngravity = [0.0, -0.259, -0.966]\ntension_limits = [5.0, 30.0]");
  text = std::regex_replace(text, std::regex("max_acceleration = 200\\.0"),
                            "max_acceleration = 3000.0");
  return machine::parse_machine(text, "maslow4.toml");
}

TEST(CableRobotPlan, PlanarHeavySledIsHeld) {
  const test::TempProgram job(
      read_text(fs::path(PKM_SOURCE_DIR) / "examples" / "jobs" / "first-drawing.ngc"));
  PlanOptions options;
  options.origin << 1459.0, 1000.0, 0.0, 0.0, 0.0, 0.0;
  expect_held_and_binding(heavy_maslow(9.0), heavy_maslow(0.0), job.path(), options);
}

TEST(CableRobotPlan, MaslowWithoutMassPlansNoTensionLimit) {
  EXPECT_FALSE(TensionLimit::of(machine::load_machine(kMachines / "maslow4.toml").kinematics()));
  EXPECT_FALSE(TensionLimit::of(hangprinter(0.0).kinematics()));
  const std::optional<TensionLimit> heavy = TensionLimit::of(hangprinter(6.0).kinematics());
  ASSERT_TRUE(heavy.has_value());
  EXPECT_EQ(heavy->rows_per_point(), 6);  // a facet pair per pair of the four lines
}

TEST(CableRobotPlan, AHeavyEffectorStartingUpwardsAtTheCentreByHand) {
  // At (0, 0, 0) D is straight up (its anchor 2299.83 mm above, 0.01 off in y) and A B C pull
  // down and out. Accelerating straight up, every line's tension grows; D's reaches 70 N first
  // as the lower lines' tensions are small: the headroom ends where the force along the facet
  // normal of the two lower lines that stay free meets it. Check against the distribution: the
  // largest upward acceleration allowed holds, 1 % more does not.
  const machine::Machine heavy = hangprinter(6.0);
  const std::optional<TensionLimit> limit = TensionLimit::of(heavy.kinematics());
  ASSERT_TRUE(limit.has_value());
  const Segment rise = [] {
    Segment s;
    s.start.setZero();
    s.end << 0.0, 0.0, 100.0, 0.0, 0.0, 0.0;
    return s;
  }();
  const TensionBound bound = limit->along(rise, 100.0, 50, 1000.0, 1e5);
  ASSERT_TRUE(bound.acceleration_limited);
  const double a = bound.acceleration_mm_per_s2 / kTensionMoveShare;  // the whole headroom
  // Straight up with D vertical alone: m (g + a) = 70 N at the top of the rise would give
  // a = 70 / 6 - 9.80665 m/s^2 = 1.8600 m/s^2; the lower lines at their 0 N minimum take none.
  EXPECT_NEAR(a, 70000.0 / 6.0 - 9806.65, 0.5);  // 1860.02
  const kinematics::CableTensions& cables = *heavy.kinematics().cable_tensions();
  const auto held = [&](double z, double up_mm_per_s2) {
    geometry::Vector6d pose = geometry::Vector6d::Zero();
    pose.z() = z;
    return cables.tensions(geometry::Pose::from_vector(pose), Eigen::Vector3d(0, 0, up_mm_per_s2))
        ->held();
  };
  for (int k = 0; k <= 50; ++k) EXPECT_TRUE(held(2.0 * k, a * (1.0 - 1e-9)));
  bool some_fails = false;
  for (int k = 0; k <= 50; ++k) some_fails = some_fails || !held(2.0 * k, a * 1.01);
  EXPECT_TRUE(some_fails);
  // The facet: D at its maximum, the lower line off the facet at its minimum.
  const std::string said = limit->describe(bound.excess);
  std::printf("  rising from the centre: %.1f mm/s^2 of headroom, %.1f for the move: %s\n", a,
              bound.acceleration_mm_per_s2, said.c_str());
  EXPECT_NE(said.find("cable 4 at the maximum 70 N"), std::string::npos) << said;
  EXPECT_NE(said.find("at the minimum 0 N"), std::string::npos) << said;
}

}  // namespace
}  // namespace pkm::motion
