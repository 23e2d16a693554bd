// The tension distribution of n cables (issue 31): hand-computed cases (two cables holding a
// weight, four cables in a plane, a met preference, rank-deficient and one-row structures),
// random problems against a brute-force reference that enumerates every active set, the KKT
// conditions as an optimality certificate at n = 26, refusals naming the right cable with the
// least largest violation, and continuity along a finely sampled path.
#include "pkm/kinematics/tension_distribution.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <set>
#include <stdexcept>

namespace {

using pkm::kinematics::distribute_tensions;
using pkm::kinematics::TensionDistribution;
using pkm::kinematics::TensionOutcome;
using pkm::kinematics::TensionTargets;

constexpr double kGravity_N_per_kg = 9.80665;

std::string scientific(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3e", value);
  return text;
}

// The answer's contract: balance within 1e-9 N, limits within 1e-9 N.
void expect_held(const Eigen::MatrixXd& a, const Eigen::VectorXd& w, const TensionTargets& targets,
                 const TensionDistribution& result) {
  ASSERT_TRUE(result.held()) << pkm::kinematics::describe_refusal(result);
  EXPECT_LT((a * result.tension_N + w).norm(), 1e-9);
  EXPECT_LT(result.equilibrium_residual_N, 1e-9);
  for (Eigen::Index i = 0; i < a.cols(); ++i) {
    EXPECT_GE(result.tension_N[i], targets.min_N[i] - 1e-9) << "cable " << i;
    EXPECT_LE(result.tension_N[i], targets.max_N[i] + 1e-9) << "cable " << i;
  }
}

// Cable directions from an effector at `effector` to plane anchors.
Eigen::MatrixXd planar_structure(const Eigen::Vector2d& effector,
                                 const std::vector<Eigen::Vector2d>& anchors) {
  Eigen::MatrixXd a(2, static_cast<Eigen::Index>(anchors.size()));
  for (std::size_t i = 0; i < anchors.size(); ++i) {
    a.col(static_cast<Eigen::Index>(i)) = (anchors[i] - effector).normalized();
  }
  return a;
}

TEST(TensionDistribution, TwoCablesHoldAWeightWithTheirOnlyTensions) {
  // 2 kg at (500, -375) below anchors 1000 mm apart: 3-4-5 cables, 0.6 (t0 + t1) = 2 g.
  const Eigen::MatrixXd a = planar_structure({500, -375}, {{0, 0}, {1000, 0}});
  const Eigen::Vector2d w(0.0, -2.0 * kGravity_N_per_kg);
  const TensionTargets targets = TensionTargets::uniform(2, 0.0, 100.0, 50.0);
  const TensionDistribution result = distribute_tensions(a, w, targets);
  expect_held(a, w, targets, result);
  EXPECT_NEAR(result.tension_N[0], 2.0 * kGravity_N_per_kg / 1.2, 1e-12);
  EXPECT_NEAR(result.tension_N[1], 2.0 * kGravity_N_per_kg / 1.2, 1e-12);
}

// Anchors at (+-500, 0) and (+-500, -1000), effector at (0, -500): every cable at 45 degrees.
const std::vector<Eigen::Vector2d> kSquareAnchors = {
    {-500, 0}, {500, 0}, {-500, -1000}, {500, -1000}};

TEST(TensionDistribution, FourCablesInAPlaneShareASymmetricWeightSymmetrically) {
  const Eigen::MatrixXd a = planar_structure({0, -500}, kSquareAnchors);
  const Eigen::Vector2d w(0.0, -10.0);
  const TensionTargets targets = TensionTargets::uniform(4, 1.0, 100.0, 20.0);
  const TensionDistribution result = distribute_tensions(a, w, targets);
  expect_held(a, w, targets, result);
  // Rows (-1, 1, -1, 1)/sqrt2 and (1, 1, -1, -1)/sqrt2 are orthogonal, |row|^2 = 2, A p = 0:
  // t = p + A^T (A A^T)^-1 (-w) = 20 + (1, 1, -1, -1) 5 / sqrt2.
  const double shift = 5.0 / std::sqrt(2.0);
  EXPECT_NEAR(result.tension_N[0], 20.0 + shift, 1e-12);
  EXPECT_NEAR(result.tension_N[1], 20.0 + shift, 1e-12);
  EXPECT_NEAR(result.tension_N[2], 20.0 - shift, 1e-12);
  EXPECT_NEAR(result.tension_N[3], 20.0 - shift, 1e-12);
}

TEST(TensionDistribution, FourCablesWithTheLowerOnesAtTheirMin) {
  // min 18 N: the lower cables (16.46 N unconstrained) rest at 18 N; the upper ones then carry
  // (t0 + t1 - 36) / sqrt2 = 10 with t0 = t1: 18 + 5 sqrt2 each.
  const Eigen::MatrixXd a = planar_structure({0, -500}, kSquareAnchors);
  const Eigen::Vector2d w(0.0, -10.0);
  const TensionTargets targets = TensionTargets::uniform(4, 18.0, 100.0, 20.0);
  const TensionDistribution result = distribute_tensions(a, w, targets);
  expect_held(a, w, targets, result);
  EXPECT_NEAR(result.tension_N[0], 18.0 + 5.0 * std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(result.tension_N[1], 18.0 + 5.0 * std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(result.tension_N[2], 18.0, 1e-12);
  EXPECT_NEAR(result.tension_N[3], 18.0, 1e-12);
  EXPECT_GT(result.iterations, 0);
}

TEST(TensionDistribution, APreferenceThatHoldsTheEffectorIsTheAnswer) {
  const Eigen::MatrixXd a = planar_structure({0, -500}, kSquareAnchors);
  const Eigen::Vector2d w(0.0, -10.0);
  const double lower = 25.0 - 5.0 * std::sqrt(2.0);
  TensionTargets targets = TensionTargets::uniform(4, 1.0, 100.0, 0.0);
  targets.preferred_N << 25.0, 25.0, lower, lower;
  const TensionDistribution result = distribute_tensions(a, w, targets);
  expect_held(a, w, targets, result);
  EXPECT_LT((result.tension_N - targets.preferred_N).norm(), 1e-12);
  EXPECT_EQ(result.iterations, 0);
}

TEST(TensionDistribution, RankDeficientStructureWithAnActiveMin) {
  // Three vertical cables: one balance row. Preferred (2, 10, 30) sums to 42, the weight is 30:
  // each would drop 4 and cable 0 would go to -2, so it rests at 0 and the other two share
  // 30 closest to (10, 30): (5, 25).
  Eigen::MatrixXd a(2, 3);
  a << 0, 0, 0, 1, 1, 1;
  const Eigen::Vector2d w(0.0, -30.0);
  TensionTargets targets = TensionTargets::uniform(3, 0.0, 100.0, 0.0);
  targets.preferred_N << 2.0, 10.0, 30.0;
  const TensionDistribution result = distribute_tensions(a, w, targets);
  expect_held(a, w, targets, result);
  EXPECT_NEAR(result.tension_N[0], 0.0, 1e-12);
  EXPECT_NEAR(result.tension_N[1], 5.0, 1e-12);
  EXPECT_NEAR(result.tension_N[2], 25.0, 1e-12);
}

TEST(TensionDistribution, AForcedSlackCableIsNamedWithItsTension) {
  // Cable 2 runs along +x and must push 2 N against a load pushing it (n = d: no freedom).
  Eigen::MatrixXd a(2, 2);
  a << 0, 1, 1, 0;
  const Eigen::Vector2d w(2.0, -10.0);
  const TensionDistribution result =
      distribute_tensions(a, w, TensionTargets::uniform(2, 5.0, 50.0, 20.0));
  EXPECT_EQ(result.outcome, TensionOutcome::out_of_limits);
  ASSERT_EQ(result.violations.size(), 1u);
  EXPECT_EQ(result.violations[0].cable, 1);
  EXPECT_TRUE(result.violations[0].below_min);
  EXPECT_NEAR(result.violations[0].tension_N, -2.0, 1e-9);
  EXPECT_NEAR(result.violations[0].excess_N, 7.0, 1e-9);
  EXPECT_NEAR(result.largest_violation_N, 7.0, 1e-9);
  EXPECT_NEAR(result.tension_N[0], 10.0, 1e-9);
  EXPECT_LT(result.equilibrium_residual_N, 1e-9);
  EXPECT_EQ(pkm::kinematics::describe_refusal(result),
            "cable 2 would need -2.000 N (its min 5.000 N)");
}

TEST(TensionDistribution, OnlyTheSlackCableIsNamedWhenTheOthersCanStayWithin) {
  // Cables 1 and 2 pull up, cable 3 along +x; the load pushes +x by 3 N, so cable 3 needs
  // -3 N whatever the others do; they share the 20 N weight within their limits.
  Eigen::MatrixXd a(2, 3);
  a << 0, 0, 1, 1, 1, 0;
  const Eigen::Vector2d w(3.0, -20.0);
  const TensionDistribution result =
      distribute_tensions(a, w, TensionTargets::uniform(3, 1.0, 50.0, 15.0));
  EXPECT_EQ(result.outcome, TensionOutcome::out_of_limits);
  ASSERT_EQ(result.violations.size(), 1u);
  EXPECT_EQ(result.violations[0].cable, 2);
  EXPECT_NEAR(result.largest_violation_N, 4.0, 1e-9);
  EXPECT_NEAR(result.tension_N[0], 10.0, 1e-9);
  EXPECT_NEAR(result.tension_N[1], 10.0, 1e-9);
  EXPECT_EQ(pkm::kinematics::describe_refusal(result),
            "cable 3 would need -3.000 N (its min 1.000 N)");
}

TEST(TensionDistribution, TooHeavyALoadSpreadsTheExcessEvenly) {
  // One row: three cables with max (5, 6, 8) N hold 30 N. The largest excess is least with all
  // three past their max by s: 19 + 3 s = 30, s = 11/3.
  Eigen::MatrixXd a(1, 3);
  a << 1, 1, 1;
  Eigen::VectorXd w(1);
  w << -30.0;
  TensionTargets targets = TensionTargets::uniform(3, 0.0, 0.0, 1.0);
  targets.max_N << 5.0, 6.0, 8.0;
  const TensionDistribution result = distribute_tensions(a, w, targets);
  EXPECT_EQ(result.outcome, TensionOutcome::out_of_limits);
  EXPECT_NEAR(result.largest_violation_N, 11.0 / 3.0, 1e-9);
  ASSERT_EQ(result.violations.size(), 3u);
  EXPECT_NEAR(result.tension_N[0], 5.0 + 11.0 / 3.0, 1e-9);
  EXPECT_NEAR(result.tension_N[1], 6.0 + 11.0 / 3.0, 1e-9);
  EXPECT_NEAR(result.tension_N[2], 8.0 + 11.0 / 3.0, 1e-9);
  EXPECT_FALSE(result.violations[0].below_min);
  EXPECT_LT(result.equilibrium_residual_N, 1e-9);
}

TEST(TensionDistribution, ALoadNoTensionsBalanceIsUnbalanced) {
  // Two vertical cables cannot take a sideways 2 N.
  Eigen::MatrixXd a(2, 2);
  a << 0, 0, 1, 1;
  const Eigen::Vector2d w(2.0, -10.0);
  const TensionDistribution result =
      distribute_tensions(a, w, TensionTargets::uniform(2, 0.0, 50.0, 20.0));
  EXPECT_EQ(result.outcome, TensionOutcome::unbalanced);
  EXPECT_NEAR(result.equilibrium_residual_N, 2.0, 1e-12);
  EXPECT_NEAR(result.tension_N[0], 5.0, 1e-12);
  EXPECT_NEAR(result.tension_N[1], 5.0, 1e-12);
  EXPECT_EQ(pkm::kinematics::describe_refusal(result),
            "no cable tensions balance the load: 2.000 N of it is outside what the cables can "
            "pull");
}

TEST(TensionDistribution, BadInputIsRefusedWithItsSizes) {
  Eigen::MatrixXd a(2, 2);
  a << 0, 1, 1, 0;
  EXPECT_THROW(
      distribute_tensions(a, Eigen::Vector3d(0, 0, 0), TensionTargets::uniform(2, 0, 1, 0.5)),
      std::invalid_argument);
  EXPECT_THROW(distribute_tensions(a, Eigen::Vector2d(0, 0), TensionTargets::uniform(3, 0, 1, 0.5)),
               std::invalid_argument);
  EXPECT_THROW(distribute_tensions(a, Eigen::Vector2d(0, std::nan("")),
                                   TensionTargets::uniform(2, 0, 1, 0.5)),
               std::invalid_argument);
  EXPECT_THROW(distribute_tensions(a, Eigen::Vector2d(0, 0), TensionTargets::uniform(2, 2, 1, 0.5)),
               std::invalid_argument);
  EXPECT_THROW(TensionTargets::middle(2, 0, std::numeric_limits<double>::infinity()),
               std::invalid_argument);
  // An unbounded max is allowed with a given preference.
  const TensionDistribution result = distribute_tensions(
      a, Eigen::Vector2d(-1, -1),
      TensionTargets::uniform(2, 0, std::numeric_limits<double>::infinity(), 0.5));
  EXPECT_TRUE(result.held());
}

// The fixed capacity (allocation-free in the servo thread): 26 cables and 6 wrench rows at most.
TEST(TensionDistribution, MoreThan26CablesOr6RowsAreRefused) {
  EXPECT_THROW(TensionTargets::uniform(27, 0, 1, 0.5), std::invalid_argument);
  const TensionTargets targets = TensionTargets::uniform(26, 0, 100, 50);
  Eigen::MatrixXd wide = Eigen::MatrixXd::Zero(3, 27);
  wide.row(2).setOnes();
  try {
    distribute_tensions(wide, Eigen::Vector3d(0, 0, -10), targets);
    ADD_FAILURE() << "27 cables accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_STREQ(error.what(),
                 "tension distribution: a 3 x 27 structure matrix; at most 6 wrench rows and 26 "
                 "cables");
  }
  Eigen::MatrixXd tall = Eigen::MatrixXd::Zero(7, 26);
  tall.row(2).setOnes();
  EXPECT_THROW(distribute_tensions(tall, Eigen::VectorXd::Zero(7), targets), std::invalid_argument);
  Eigen::MatrixXd full = Eigen::MatrixXd::Zero(6, 26);
  full.row(2).setOnes();
  Eigen::VectorXd w = Eigen::VectorXd::Zero(6);
  w[2] = -260.0;
  const TensionDistribution at_capacity = distribute_tensions(full, w, targets);
  EXPECT_TRUE(at_capacity.held());
  EXPECT_NEAR(at_capacity.tension_N[25], 10.0, 1e-12);  // 50 N each less 1300 - 260 N shared
}

// A random structure: d = 2 or 3 (cable directions) or 6 (with moments about the effector's
// origin of cables tied at random points on it).
Eigen::MatrixXd random_structure(int rows, int cables, std::mt19937& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> attach(-50.0, 50.0);
  Eigen::MatrixXd a(rows, cables);
  for (int i = 0; i < cables; ++i) {
    const int translating = rows == 6 ? 3 : rows;
    Eigen::VectorXd u(translating);
    for (int k = 0; k < translating; ++k) u[k] = normal(rng);
    u.normalize();
    a.col(i).head(translating) = u;
    if (rows == 6) {
      const Eigen::Vector3d point(attach(rng), attach(rng), attach(rng));
      a.col(i).tail(3) = point.cross(Eigen::Vector3d(u[0], u[1], u[2]));
    }
  }
  return a;
}

// The reference: every assignment of each cable to free, at its min or at its max; free
// tensions closest to preferred on the balance (SVD pseudo-inverse of A's free columns); the
// feasible candidate nearest the preference is the optimum (the optimum's active set is one of
// them). Returns false when no candidate is feasible.
bool brute_force(const Eigen::MatrixXd& a, const Eigen::VectorXd& w, const TensionTargets& targets,
                 Eigen::VectorXd& best) {
  const int n = static_cast<int>(a.cols());
  int assignments = 1;
  for (int i = 0; i < n; ++i) assignments *= 3;
  double best_distance = std::numeric_limits<double>::infinity();
  for (int code = 0; code < assignments; ++code) {
    Eigen::VectorXd t = targets.preferred_N;
    std::vector<int> free;
    for (int i = 0, c = code; i < n; ++i, c /= 3) {
      if (c % 3 == 1) t[i] = targets.min_N[i];
      if (c % 3 == 2) t[i] = targets.max_N[i];
      if (c % 3 == 0) free.push_back(i);
    }
    Eigen::MatrixXd free_columns(a.rows(), static_cast<Eigen::Index>(free.size()));
    for (std::size_t k = 0; k < free.size(); ++k) free_columns.col(k) = a.col(free[k]);
    const Eigen::VectorXd rhs = -w - a * t;
    if (!free.empty()) {
      const Eigen::VectorXd step =
          free_columns.jacobiSvd(Eigen::ComputeThinU | Eigen::ComputeThinV).solve(rhs);
      for (std::size_t k = 0; k < free.size(); ++k) t[free[k]] += step[k];
    }
    if ((a * t + w).norm() > 1e-9) continue;
    if (((targets.min_N - t).array() > 1e-9).any() || ((t - targets.max_N).array() > 1e-9).any()) {
      continue;
    }
    const double distance = (t - targets.preferred_N).norm();
    if (distance < best_distance) {
      best_distance = distance;
      best = t;
    }
  }
  return std::isfinite(best_distance);
}

TEST(TensionDistribution, RandomProblemsAgreeWithEnumeratingEveryActiveSet) {
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> preferred(-5.0, 70.0), load(-40.0, 40.0);
  const std::vector<std::pair<int, int>> shapes = {{2, 3}, {2, 4}, {2, 6}, {3, 4}, {3, 5},
                                                   {3, 7}, {6, 7}, {6, 8}, {1, 4}};
  int held = 0, refused = 0;
  double worst_difference = 0.0, worst_residual = 0.0;
  for (const auto& [rows, cables] : shapes) {
    for (int trial = 0; trial < 40; ++trial) {
      const Eigen::MatrixXd a = random_structure(rows, cables, rng);
      Eigen::VectorXd w(rows);
      for (int k = 0; k < rows; ++k) w[k] = load(rng);
      TensionTargets targets = TensionTargets::uniform(cables, 2.0, 60.0, 0.0);
      for (int i = 0; i < cables; ++i) targets.preferred_N[i] = preferred(rng);
      const TensionDistribution result = distribute_tensions(a, w, targets);
      Eigen::VectorXd reference;
      if (brute_force(a, w, targets, reference)) {
        expect_held(a, w, targets, result);
        ++held;
        worst_difference =
            std::max(worst_difference, (result.tension_N - reference).lpNorm<Eigen::Infinity>());
        worst_residual = std::max(worst_residual, result.equilibrium_residual_N);
      } else {
        EXPECT_FALSE(result.held()) << rows << " x " << cables << " trial " << trial;
        ++refused;
      }
    }
  }
  EXPECT_GT(held, 100);
  EXPECT_GT(refused, 20);
  EXPECT_LT(worst_difference, 1e-6);
  RecordProperty("held", held);
  RecordProperty("refused", refused);
  RecordProperty("worst_difference_N", scientific(worst_difference));
  RecordProperty("worst_residual_N", scientific(worst_residual));
}

// The KKT conditions of min |t - p|^2 / 2 subject to A t = -w, min <= t <= max: for some
// multipliers l, t - p - A^T l is 0 on cables strictly within their limits, >= 0 at their min
// and <= 0 at their max. l from the free cables by least squares; returns the worst breach.
double kkt_breach(const Eigen::MatrixXd& a, const TensionTargets& targets,
                  const Eigen::VectorXd& t) {
  std::vector<int> free;
  for (int i = 0; i < t.size(); ++i) {
    if (t[i] > targets.min_N[i] + 1e-9 && t[i] < targets.max_N[i] - 1e-9) free.push_back(i);
  }
  Eigen::MatrixXd free_rows(static_cast<Eigen::Index>(free.size()), a.rows());
  Eigen::VectorXd free_gradient(static_cast<Eigen::Index>(free.size()));
  for (std::size_t k = 0; k < free.size(); ++k) {
    free_rows.row(k) = a.col(free[k]).transpose();
    free_gradient[k] = t[free[k]] - targets.preferred_N[free[k]];
  }
  const Eigen::VectorXd multipliers =
      free_rows.jacobiSvd(Eigen::ComputeThinU | Eigen::ComputeThinV).solve(free_gradient);
  const Eigen::VectorXd reduced = t - targets.preferred_N - a.transpose() * multipliers;
  double breach = 0.0;
  for (int i = 0; i < t.size(); ++i) {
    if (t[i] <= targets.min_N[i] + 1e-9) {
      breach = std::max(breach, -reduced[i]);
    } else if (t[i] >= targets.max_N[i] - 1e-9) {
      breach = std::max(breach, reduced[i]);
    } else {
      breach = std::max(breach, std::abs(reduced[i]));
    }
  }
  return breach;
}

TEST(TensionDistribution, TwentySixCablesMeetTheOptimalityConditions) {
  // Klipper's winch maximum: 26 anchors around the effector, d = 3 and d = 6; 5 kg held, and
  // 400 kg, which 26 cables of 80 N cannot hold (a refusal through the bisection).
  std::mt19937 rng(26);
  std::uniform_real_distribution<double> preferred(0.0, 90.0);
  int held = 0, refused = 0, most_iterations = 0, most_refusal_iterations = 0;
  double worst_residual = 0.0;
  for (const int rows : {3, 6}) {
    for (int trial = 0; trial < 20; ++trial) {
      const Eigen::MatrixXd a = random_structure(rows, 26, rng);
      TensionTargets targets = TensionTargets::uniform(26, 5.0, 80.0, 0.0);
      for (int i = 0; i < 26; ++i) targets.preferred_N[i] = preferred(rng);
      for (const double mass_kg : {5.0, 400.0}) {
        Eigen::VectorXd w = Eigen::VectorXd::Zero(rows);
        w[rows == 6 ? 2 : rows - 1] = -mass_kg * kGravity_N_per_kg;
        const TensionDistribution result = distribute_tensions(a, w, targets);
        if (!result.held()) {
          EXPECT_EQ(result.outcome, TensionOutcome::out_of_limits);
          EXPECT_LT(result.equilibrium_residual_N, 1e-9);
          EXPECT_FALSE(result.violations.empty());
          most_refusal_iterations = std::max(most_refusal_iterations, result.iterations);
          ++refused;
          continue;
        }
        expect_held(a, w, targets, result);
        EXPECT_LT(kkt_breach(a, targets, result.tension_N), 1e-9) << rows << " rows, " << trial;
        most_iterations = std::max(most_iterations, result.iterations);
        worst_residual = std::max(worst_residual, result.equilibrium_residual_N);
        ++held;
      }
    }
  }
  EXPECT_GT(held, 30);
  EXPECT_GE(refused, 40);
  RecordProperty("held", held);
  RecordProperty("most_iterations", most_iterations);
  RecordProperty("most_refusal_iterations", most_refusal_iterations);
  RecordProperty("worst_residual_N", scientific(worst_residual));
}

TEST(TensionDistribution, TheLeastViolationCannotShrink) {
  // Refusals: widening every limit by the reported violation (plus 1e-7 N) makes the tensions
  // hold; by 1e-6 N less it does not.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> load(-150.0, 150.0);
  int refusals = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const int rows = trial % 2 == 0 ? 2 : 3, cables = rows + 1 + trial % 3;
    const Eigen::MatrixXd a = random_structure(rows, cables, rng);
    Eigen::VectorXd w(rows);
    for (int k = 0; k < rows; ++k) w[k] = load(rng);
    const TensionTargets targets = TensionTargets::middle(cables, 2.0, 40.0);
    const TensionDistribution result = distribute_tensions(a, w, targets);
    if (result.outcome != TensionOutcome::out_of_limits) continue;
    ++refusals;
    const double s = result.largest_violation_N;
    ASSERT_FALSE(result.violations.empty());
    EXPECT_NEAR(result.violations.front().excess_N, s, 1e-12);
    auto widened = [&](double by) {
      TensionTargets wide = targets;
      wide.min_N.array() -= by;
      wide.max_N.array() += by;
      return distribute_tensions(a, w, wide);
    };
    EXPECT_TRUE(widened(s + 1e-7).held()) << trial;
    EXPECT_FALSE(widened(s - 1e-6).held()) << trial;
  }
  EXPECT_GT(refusals, 10);
}

// A four-cable spatial machine (three low anchors, one high, as a Hangprinter): the effector
// moves 312 mm along a line through the workspace, where cable 2 leaves its min and cable 1
// comes to it (at 25 N); the tensions change by at most a constant
// times the step, and halving the step halves the largest change (Lipschitz, no jumps), also
// where a cable comes to rest at its min.
double largest_jump(int samples, std::set<std::vector<bool>>& active_patterns) {
  const std::vector<Eigen::Vector3d> anchors = {
      {0.0, -1600.0, 0.0}, {1400.0, 800.0, 0.0}, {-1400.0, 800.0, 0.0}, {0.0, 0.0, 2500.0}};
  const Eigen::Vector3d start(-150.0, -50.0, 450.0), end(30.0, 130.0, 630.0);
  const TensionTargets targets = TensionTargets::uniform(4, 25.0, 400.0, 30.0);
  const Eigen::Vector3d w(0.0, 0.0, -3.0 * kGravity_N_per_kg);  // 3 kg
  Eigen::VectorXd previous;
  double jump = 0.0;
  for (int k = 0; k <= samples; ++k) {
    const Eigen::Vector3d p = start + (end - start) * (static_cast<double>(k) / samples);
    Eigen::MatrixXd a(3, 4);
    for (int i = 0; i < 4; ++i) a.col(i) = (anchors[i] - p).normalized();
    const TensionDistribution result = distribute_tensions(a, w, targets);
    EXPECT_TRUE(result.held()) << "sample " << k;
    std::vector<bool> pattern;
    for (int i = 0; i < 4; ++i) pattern.push_back(result.tension_N[i] <= targets.min_N[i] + 1e-9);
    active_patterns.insert(pattern);
    if (k > 0) jump = std::max(jump, (result.tension_N - previous).lpNorm<Eigen::Infinity>());
    previous = result.tension_N;
  }
  return jump;
}

TEST(TensionDistribution, TensionsChangeContinuouslyAlongAPath) {
  std::set<std::vector<bool>> patterns;
  const double coarse = largest_jump(1000, patterns);  // 0.31 mm steps
  const double fine = largest_jump(2000, patterns);
  EXPECT_GE(patterns.size(), 2u);  // the path crosses a change of the active set
  // The tensions change by about 0.15 N/mm here (by hand from 20 samples: cable 1 from 33.8 to
  // 25 N over the first half).
  EXPECT_LT(coarse, 0.1);  // N per 0.31 mm
  EXPECT_NEAR(fine / coarse, 0.5, 0.05);
  RecordProperty("largest_jump_N", scientific(coarse));
  RecordProperty("halved_step_ratio", scientific(fine / coarse));
}

}  // namespace
