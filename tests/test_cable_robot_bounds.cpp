// The cable robot's derivative bounds and reach (kinematics/cable_robot_bounds.cpp): the Hessian
// bound by hand for a straight cable and a swivel arm, a property test against second differences
// over random balls (and how tight it is), the wrench-feasibility margin's bracket over random
// cells against inverse() at samples, the Hangprinter's certified workspace against a Monte Carlo
// estimate and inverse() at samples of its cells, and the certified check of a square at z 100 mm
// (proven) and of a line that leaves the wrench-feasible workspace (not proven).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "pkm/bounds/pose_box_rate.hpp"
#include "pkm/certify/job_check.hpp"
#include "pkm/certify/move_proof.hpp"
#include "pkm/kinematics/cable_robot.hpp"
#include "pkm/workspace/workspace.hpp"
#include "test_support.hpp"

namespace pkm {
namespace {

using kinematics::CableRobotKinematics;
using kinematics::Chord;
using kinematics::HessianBounds;
using kinematics::JointVector;

const CableRobotKinematics& robot(const machine::Machine& m) {
  const auto* model = dynamic_cast<const CableRobotKinematics*>(&m.kinematics());
  if (model == nullptr) throw std::logic_error("not a cable robot");
  return *model;
}

geometry::Vector6d pose_at(double x, double y, double z) {
  geometry::Vector6d pose = geometry::Vector6d::Zero();
  pose << x, y, z, 0.0, 0.0, 0.0;
  return pose;
}

// The Hangprinter with no tension limits: inverse() gives every cable's length.
machine::Machine free_hangprinter() {
  return test::load_example_changed("hangprinter-v4.toml", "tension_limits = [0.0, 70.0]", "");
}

TEST(CableRobotBounds, HessianBoundOfAStraightCableByHand) {
  const machine::Machine m = test::load_example("hangprinter-v4.toml");
  // Cable D from the origin: l = |(0, 0.01, 2299.83)| = 2299.83000002 mm; over a ball of 100 mm
  // l >= 2199.83, so |H| <= 1 / 2199.83.
  Chord across;
  across.position = Eigen::Vector3d(10.0, 0.0, 0.0);
  const std::optional<HessianBounds> bounds =
      robot(m).own_hessian_bounds(pose_at(0, 0, 0), 100.0, 100.0, across);
  ASSERT_TRUE(bounds);
  ASSERT_EQ(bounds->norm.size(), 4u);
  EXPECT_NEAR(bounds->norm[3], 1.0 / 2199.83, 1e-12);
  // Across the (vertical) cable the sine is 1: |H[v, v]| <= |v|^2 / l_min = 100 / 2199.83.
  EXPECT_NEAR(bounds->along[3], 100.0 / 2199.83, 1e-9);
  // Along it: the sine at the centre is 0.01 / 2299.83, plus 100 / 2199.83 the cable's turn.
  Chord along;
  along.position = Eigen::Vector3d(0.0, 0.0, 10.0);
  const double sine = 0.01 / 2299.83 + 100.0 / 2199.83;
  EXPECT_NEAR(robot(m).own_hessian_bounds(pose_at(0, 0, 0), 100.0, 100.0, along)->along[3],
              100.0 * sine * sine / 2199.83, 1e-12);
  // A ball reaching the anchor: no bound.
  EXPECT_TRUE(
      std::isinf(robot(m).own_hessian_bounds(pose_at(0, 0, 2200), 100.0, 100.0, along)->norm[3]));
}

TEST(CableRobotBounds, HessianBoundOfASwivelArmByHand) {
  const machine::Machine m = test::load_example("maslow4.toml");
  // Bottom-left belt (anchor 0 0 0, attach z 34, arm 153.4) with the router at x 1000 y 0 z 0:
  // the arm's end at (846.6, 0, 34), the belt sqrt(846.6^2 + 34^2) = 847.28246 mm; over a ball of
  // 50 mm |H| <= 1 / (847.28246 - 50).
  const std::optional<HessianBounds> bounds =
      robot(m).own_hessian_bounds(pose_at(1000, 0, 0), 50.0, 100.0, Chord{});
  ASSERT_TRUE(bounds);
  ASSERT_EQ(bounds->norm.size(), 4u);
  EXPECT_NEAR(bounds->norm[2], 1.0 / (std::hypot(846.6, 34.0) - 50.0), 1e-12);
  // The arm's axis within 153.4 mm of the anchor in plan somewhere in the ball: no bound.
  EXPECT_TRUE(
      std::isinf(robot(m).own_hessian_bounds(pose_at(180, 0, 0), 30.0, 100.0, Chord{})->norm[2]));
}

// Over random balls: the second difference of every cable's length along random directions
// (and along the chord) never exceeds the bound; the largest found is a good share of it.
void expect_hessian_bounds_hold(const machine::Machine& m, std::mt19937_64& rng,
                                double& tightest_ratio) {
  const CableRobotKinematics& model = robot(m);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), share(0.0, 1.0);
  const std::vector<geometry::Pose> centres = test::sample_reachable_poses(m, 40, rng);
  const int cables = model.cable_count();
  double ratio_sum = 0.0;
  int balls = 0;
  for (const geometry::Pose& centre : centres) {
    const double radius = 1.0 + 150.0 * share(rng);
    Chord chord;
    for (int axis = 0; axis < 3; ++axis) {
      if (model.dof().controls(axis)) chord.position[axis] = radius * unit(rng);
    }
    const auto bounds = model.own_hessian_bounds(centre.as_vector(), radius, 100.0, chord);
    ASSERT_TRUE(bounds);
    std::vector<double> largest(static_cast<std::size_t>(cables), 0.0);
    for (int sample = 0; sample < 60; ++sample) {
      Eigen::Vector3d offset, direction;
      for (int axis = 0; axis < 3; ++axis) {
        const bool moves = model.dof().controls(axis);
        offset[axis] = moves ? unit(rng) : 0.0;
        direction[axis] = moves ? unit(rng) : 0.0;
      }
      const bool along_chord = sample % 3 == 0 && chord.position.norm() > 0.0;
      if (along_chord) direction = chord.position;
      const double h = 1e-2;
      const double spare = radius - h * direction.norm();
      if (spare <= 0.0) continue;
      geometry::Pose p = centre;
      p.position_mm += spare * share(rng) * offset.normalized();
      JointVector q0, q_plus, q_minus;
      geometry::Pose plus = p, minus = p;
      plus.position_mm += h * direction;
      minus.position_mm -= h * direction;
      if (!model.inverse(p, q0).ok() || !model.inverse(plus, q_plus).ok() ||
          !model.inverse(minus, q_minus).ok()) {
        continue;
      }
      for (int i = 0; i < cables; ++i) {
        const auto k = static_cast<std::size_t>(i);
        const double second = std::abs(q_plus[i] - 2.0 * q0[i] + q_minus[i]) / (h * h);
        const double bound =
            along_chord ? bounds->along[k] : bounds->norm[k] * direction.squaredNorm();
        // The difference's rounding: 4 eps |q| / h^2.
        EXPECT_LE(second, bound * (1.0 + 1e-6) + 4e-16 * 4.0e3 / (h * h))
            << "cable " << i + 1 << " at " << p.position_mm.transpose() << " radius " << radius;
        if (!along_chord) largest[k] = std::max(largest[k], second / bound);
      }
    }
    for (const double ratio : largest) ratio_sum += ratio;
    balls += cables;
  }
  tightest_ratio = ratio_sum / balls;
}

TEST(CableRobotBounds, HessianBoundsHoldOverRandomBallsAndAreTight) {
  std::mt19937_64 rng(31);
  double hangprinter_ratio = 0.0, maslow_ratio = 0.0;
  expect_hessian_bounds_hold(free_hangprinter(), rng, hangprinter_ratio);
  expect_hessian_bounds_hold(test::load_example("maslow4.toml"), rng, maslow_ratio);
  // The largest second difference found in a ball over the bound, averaged over balls and
  // cables: random directions find sin^2 of a random angle, so about a half where tight.
  EXPECT_GT(hangprinter_ratio, 0.3);
  EXPECT_GT(maslow_ratio, 0.3);
  std::printf("mean largest sampled |H[v, v]| / bound: hangprinter %.3f, maslow %.3f\n",
              hangprinter_ratio, maslow_ratio);
}

// The wrench-feasibility margin over random cells: where its low is positive inverse() holds
// every sample of the cell, where its high is negative it refuses every one, and the bracket
// holds the margin at the samples (wrench_margin).
TEST(CableRobotBounds, WrenchMarginBracketAgreesWithInverseOverRandomCells) {
  const machine::Machine m = test::load_example("hangprinter-v4.toml");
  const CableRobotKinematics& model = robot(m);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), share(0.0, 1.0);
  int inside = 0, outside = 0;
  for (int cell = 0; cell < 300; ++cell) {
    const geometry::Vector6d centre =
        pose_at(900.0 * unit(rng), 900.0 * unit(rng), 1000.0 + 1000.0 * unit(rng));
    const double radius = 2.0 + 60.0 * share(rng);
    std::array<std::array<double, 2>, 5> margins;
    model.reach_over_cell(centre, radius, radius, 100.0, margins);
    const auto [low, high] = margins[4];
    ASSERT_LE(low, high);
    inside += low > 0.0;
    outside += high < 0.0;
    for (int sample = 0; sample < 40; ++sample) {
      geometry::Pose p = geometry::Pose::from_vector(centre);
      const Eigen::Vector3d offset(unit(rng), unit(rng), unit(rng));
      p.position_mm += radius * share(rng) * offset.normalized();
      JointVector joints;
      const kinematics::Status status = model.inverse(p, joints);
      if (low > 0.0) {
        EXPECT_TRUE(status.ok()) << p.position_mm.transpose();
      }
      if (high < 0.0) {
        EXPECT_EQ(status.code, kinematics::StatusCode::tension);
      }
      const auto at = model.wrench_margin(p);
      ASSERT_TRUE(at);
      EXPECT_GE(at->margin_N, low - 1e-9);
      EXPECT_LE(at->margin_N, high + 1e-9);
      // The margin's sign is inverse()'s verdict.
      if (at->margin_N > 1e-6) {
        EXPECT_TRUE(status.ok());
      }
      if (at->margin_N < -1e-6) {
        EXPECT_FALSE(status.ok());
      }
    }
  }
  EXPECT_GT(inside, 30);
  EXPECT_GT(outside, 30);
}

TEST(CableRobotBounds, HangprinterWorkspaceIsCertifiedAndHoldsAMonteCarloEstimate) {
  const machine::Machine m = test::load_example("hangprinter-v4.toml");
  workspace::WorkspaceOptions options = workspace::default_options(m);
  options.resolution_mm = 100.0;
  const workspace::Workspace ws = workspace::compute_workspace(m, options);
  EXPECT_TRUE(ws.guaranteed);
  EXPECT_EQ(ws.unbounded_refusals, 0);
  ASSERT_GT(ws.inside_measure, 0.0);
  // What limits the cells is the tensions (and the envelope): the joints' lines stay within 100
  // .. 3500 mm wherever the effector is held. The joints are bounded by the geometry alone, also
  // where the tensions refuse a cell's middle (they were counted as joint_limit).
  EXPECT_EQ(ws.limited_by.count("joint_limit"), 0u);
  EXPECT_GT(ws.limited_by.at("tension"), 3000);
  // Each finest cell of the grid: 0 outside, 1 inside, 2 undecided.
  const std::array<int, 3> dims = ws.dims;
  std::vector<char> state(static_cast<std::size_t>(dims[0]) * dims[1] * dims[2], 0);
  const auto index = [&](int i, int j, int k) {
    return (static_cast<std::size_t>(k) * dims[1] + j) * dims[0] + i;
  };
  for (const auto& [cells, value] : {std::pair{&ws.inside, 1}, std::pair{&ws.boundary, 2}}) {
    for (const workspace::CellIndex& cell : *cells) {
      const int side = 1 << cell.level;
      for (int k = cell.at[2]; k < std::min(cell.at[2] + side, dims[2]); ++k)
        for (int j = cell.at[1]; j < std::min(cell.at[1] + side, dims[1]); ++j)
          for (int i = cell.at[0]; i < std::min(cell.at[0] + side, dims[0]); ++i)
            state[index(i, j, k)] = static_cast<char>(value);
    }
  }
  // Monte Carlo over the envelope box: Machine::inverse (envelope, joints, tensions) accepts.
  const Eigen::Vector3d low(-1000.0, -1000.0, -10.0), high(1000.0, 1000.0, 2000.0);
  const double box = (high - low).prod();
  constexpr int kSamples = 40000;
  std::mt19937_64 rng(2026);
  std::uniform_real_distribution<double> share(0.0, 1.0);
  int accepted = 0, refused_inside = 0, accepted_outside = 0;
  for (int n = 0; n < kSamples; ++n) {
    geometry::Pose p = m.home();
    for (int axis = 0; axis < 3; ++axis)
      p.position_mm[axis] = low[axis] + (high[axis] - low[axis]) * share(rng);
    JointVector joints;
    const bool ok = m.inverse(p, joints).ok();
    accepted += ok;
    int cell_state = 0;
    std::array<int, 3> at{};
    bool on_grid = true;
    for (int axis = 0; axis < 3; ++axis) {
      at[axis] = static_cast<int>(
          std::floor((p.position_mm[axis] - ws.origin_mm[axis]) / ws.resolution_mm));
      on_grid = on_grid && at[axis] >= 0 && at[axis] < dims[axis];
    }
    if (on_grid) cell_state = state[index(at[0], at[1], at[2])];
    refused_inside += cell_state == 1 && !ok;
    accepted_outside += cell_state == 0 && ok;
  }
  EXPECT_EQ(refused_inside, 0);
  EXPECT_EQ(accepted_outside, 0);
  const double p = static_cast<double>(accepted) / kSamples;
  const double estimate = p * box, standard_error = box * std::sqrt(p * (1.0 - p) / kSamples);
  EXPECT_LE(ws.inside_measure, estimate + 4.0 * standard_error);
  EXPECT_GE(ws.inside_measure + ws.boundary_measure, estimate - 4.0 * standard_error);
  std::printf(
      "hangprinter at %.0f mm: inside %.4g mm^3 (%zu cells), undecided %.4g mm^3 (%zu cells); "
      "Monte Carlo %.4g +- %.2g mm^3 (%d samples)\n",
      ws.resolution_mm, ws.inside_measure, ws.inside.size(), ws.boundary_measure,
      ws.boundary.size(), estimate, standard_error, kSamples);
}

TEST(CableRobotBounds, MaslowWorkspaceIsCertified) {
  const machine::Machine m = test::load_example("maslow4.toml");
  workspace::WorkspaceOptions options = workspace::default_options(m);
  options.resolution_mm = 20.0;
  const workspace::Workspace ws = workspace::compute_workspace(m, options);
  EXPECT_TRUE(ws.guaranteed);
  EXPECT_EQ(ws.unbounded_refusals, 0);
  // The whole 2440 x 1220 mm sheet by 60 mm of Z: the belts reach all of it.
  EXPECT_NEAR(ws.inside_measure, 2440.0 * 1220.0 * 60.0, 1e-6 * 2440.0 * 1220.0 * 60.0);
}

std::filesystem::path job_file(const std::string& name) {
  return std::filesystem::path(PKM_SOURCE_DIR) / "tests" / "data" / name;
}

// The joint-rate bound the LinuxCNC export's axis limits stand on bounds the lines by their
// geometry (a line's rate is at most 1 mm per mm wherever it reaches), also where the tensions
// refuse a cell's middle: the whole envelope is covered (where the tensions first refused a
// cell's middle its bound was infinite, and the export shrank the envelope to 36.3 %; 90.2 % now,
// by the rate rule alone).
TEST(CableRobotBounds, JointRatesAreBoundedByTheGeometryWhereTheTensionsRefuse) {
  const machine::Machine m = test::load_example("hangprinter-v4.toml");
  bounds::JointRateOptions options;
  options.max_cells = 4000;
  const bounds::JointRateBound bound =
      bounds::bound_joint_rates(m, bounds::work_envelope(m).box, options);
  EXPECT_TRUE(bound.proven);
  EXPECT_EQ(bound.uncovered, 0.0);
  // Each entry: |d line / d x| <= 1, plus what the cells' curvature allows (4000 cells: coarse).
  EXPECT_LE(bound.slope.leftCols(3).maxCoeff(), 2.0);
  EXPECT_GE(bound.slope.leftCols(3).maxCoeff(), 0.99);
}

TEST(CableRobotBounds, HangprinterSquareAtZ100IsProven) {
  const machine::Machine m = test::load_example("hangprinter-v4.toml");
  const test::TempProgram job(
      "G21 G90\nG1 X0 Y0 Z100 F6000\nG1 X200 Y0\nG1 X200 Y200\nG1 X0 Y200\nG1 X0 Y0\nM2\n");
  const certify::JobCheck check = certify::check_job(m, job.path(), {});
  EXPECT_TRUE(check.unavailable.empty()) << check.unavailable;
  EXPECT_EQ(check.moves, 5);
  EXPECT_EQ(check.proven, 5);
}

// With flex compensation a joint is its line less the stretch under RRF's forces: the straight
// cable's Hessian bound does not hold for it, so the check proves nothing (it would otherwise
// certify joints the stretch moves by up to 5 mm).
TEST(CableRobotBounds, FlexCompensationHasNoHessianBound) {
  const machine::Machine m = test::load_example("hangprinter-v4-flex.toml");
  Chord chord;
  chord.position = Eigen::Vector3d(10.0, 0.0, 0.0);
  EXPECT_FALSE(robot(m).own_hessian_bounds(pose_at(0, 0, 100), 5.0, 100.0, chord));
  const test::TempProgram job("G21 G90\nG1 X0 Y0 Z100 F6000\nG1 X200 Y0\nM2\n");
  const certify::JobCheck check = certify::check_job(m, job.path(), {});
  EXPECT_EQ(check.proven, 0);
  EXPECT_FALSE(check.unavailable.empty());
}

TEST(CableRobotBounds, ALineLeavingTheWrenchFeasibleWorkspaceIsNotProven) {
  const machine::Machine m = test::load_example("hangprinter-v4.toml");
  // Along x at z 100 mm no tensions within [0, 70] N hold the 1 kg effector past x 636.96 mm.
  const certify::JobCheck check =
      certify::check_job(m, job_file("hangprinter-past-the-tensions.ngc"), {});
  EXPECT_EQ(check.moves, 2);
  EXPECT_EQ(check.proven, 1);
  EXPECT_EQ(check.violated, 1);
  ASSERT_TRUE(check.first_failure);
  const certify::Finding& finding = check.first_failure->finding;
  EXPECT_NEAR(finding.pose[0], 636.96, 0.01);
  EXPECT_NE(finding.text.find("no tensions within tension_limits [0.000, 70.000] N"),
            std::string::npos)
      << finding.text;
  // Its wrench-feasibility margin (N), 0 at the border, past it the farthest at the move's end.
  EXPECT_EQ(finding.quantity, certify::Quantity::reach);
  EXPECT_EQ(finding.index, 4);
  EXPECT_NEAR(finding.value, 0.0, 1e-6);
  EXPECT_NEAR(finding.worst_u, 1.0, 1e-12);
  EXPECT_LT(finding.worst_value, -1.0);
  EXPECT_NE(finding.text.find(" N at 100.000000 % of the move"), std::string::npos) << finding.text;
  // Stopping 7 mm short of the border, the move is proven; right up to it, not.
  const certify::MoveProver prover(m);
  motion::Segment segment;
  segment.start = pose_at(100, 0, 100);
  segment.end = pose_at(630.0, 0, 100);
  segment.feed_mm_per_s = 100.0;
  EXPECT_EQ(prover.prove(segment).verdict, certify::Verdict::proven);
}

}  // namespace
}  // namespace pkm
