// The workspace's search for a hexapod leg's extreme over an orientation range: its bracket
// holds the true largest value (dense samples of the range), its lower end is attained, and it
// decides what it is asked to decide.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "pkm/geometry/pose.hpp"
#include "pkm/workspace/orientation_search.hpp"

namespace pkm::workspace {
namespace {

// The largest of value(R) over a grid of n^3 orientations of the box (a lower bound of the truth).
template <class Value>
double largest_on_grid(const Eigen::Vector3d& centre, const Eigen::Vector3d& half, int n,
                       Value&& value) {
  double best = -INFINITY;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const Eigen::Vector3d step(i, j, k);
        const Eigen::Vector3d abc =
            centre - half + 2.0 * half.cwiseProduct(step / static_cast<double>(n - 1));
        best = std::max(best, value(geometry::rotation_from_abc(abc)));
      }
  return best;
}

// s = v . R p, sampled on a grid of the range.
double sampled_largest(const Eigen::Vector3d& v, const Eigen::Vector3d& p,
                       const Eigen::Vector3d& centre, const Eigen::Vector3d& half, int n) {
  return largest_on_grid(centre, half, n,
                         [&](const Eigen::Matrix3d& rotation) { return v.dot(rotation * p); });
}

TEST(OrientationSearch, BracketHoldsTheSampledLargestAndIsTight) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), angle(0.0, 0.6);
  OrientationSearch search;
  for (int trial = 0; trial < 300; ++trial) {
    const Eigen::Vector3d v(800.0 * unit(rng), 800.0 * unit(rng), 600.0 + 400.0 * unit(rng));
    const Eigen::Vector3d p(200.0 * unit(rng), 200.0 * unit(rng), 50.0 * unit(rng));
    const Eigen::Vector3d centre(0.3 * unit(rng), 0.3 * unit(rng), 0.5 * unit(rng));
    const Eigen::Vector3d half(angle(rng), angle(rng), trial % 5 == 0 ? 0.0 : angle(rng));
    const double tolerance = 1.0;  // of values near 1e5: a search well within its box budget
    const Bracket found = search.largest(v, p, centre, half, {INFINITY, -INFINITY, tolerance});
    const double sampled = sampled_largest(v, p, centre, half, 25);
    ASSERT_LE(sampled, found.hi + 1e-9) << "trial " << trial;
    ASSERT_LE(found.lo, found.hi);
    ASSERT_GE(found.lo, sampled - tolerance - 1e-9) << "trial " << trial;
    ASSERT_LE(found.hi - found.lo, tolerance + 1e-9) << "trial " << trial;
  }
}

// One angle: the closed form over c against the peak of a hand-made sinusoid. v along x, p along
// x, only c turns: s = |v||p| cos c, largest at c = 0 when the range holds it, else at its end.
TEST(OrientationSearch, ClosedFormOverCMatchesTheHandComputedPeak) {
  OrientationSearch search;
  const Eigen::Vector3d v(1000.0, 0.0, 0.0), p(200.0, 0.0, 0.0);
  const Bracket across_zero =
      search.largest(v, p, Eigen::Vector3d(0.0, 0.0, 0.1), Eigen::Vector3d(0.0, 0.0, 0.3),
                     {INFINITY, -INFINITY, 0.0});
  EXPECT_NEAR(across_zero.lo, 200000.0, 1e-9);
  EXPECT_NEAR(across_zero.hi, 200000.0, 1e-9);
  const Bracket beside = search.largest(v, p, Eigen::Vector3d(0.0, 0.0, 0.5),
                                        Eigen::Vector3d(0.0, 0.0, 0.2), {INFINITY, -INFINITY, 0.0});
  EXPECT_NEAR(beside.lo, 200000.0 * std::cos(0.3), 1e-9);
  EXPECT_NEAR(beside.hi, 200000.0 * std::cos(0.3), 1e-9);
}

// Asked only whether the largest passes a threshold, the search answers that, whichever side.
TEST(OrientationSearch, DecidesTheThresholdsItIsGiven) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  OrientationSearch search;
  const Eigen::Vector3d centre(0.0, 0.0, 0.0), half(0.17, 0.17, 0.17);
  for (int trial = 0; trial < 100; ++trial) {
    const Eigen::Vector3d v(500.0 * unit(rng), 500.0 * unit(rng), 900.0);
    const Eigen::Vector3d p(180.0 * unit(rng), 180.0 * unit(rng), 0.0);
    const double truth = sampled_largest(v, p, centre, half, 31);
    const double gap = 0.002 * v.norm() * p.norm();
    const Bracket low = search.largest(v, p, centre, half, {truth - gap, -INFINITY, 0.0});
    EXPECT_GT(low.lo, truth - gap) << "trial " << trial;
    const Bracket high = search.largest(v, p, centre, half, {INFINITY, truth + gap, 0.0});
    EXPECT_LE(high.hi, truth + gap) << "trial " << trial;
  }
}

// -cos of a joint end's angle, sampled on a grid of the range.
double sampled_largest_turn(const LegJointEnd& end, const Eigen::Vector3d& centre,
                            const Eigen::Vector3d& half, int n) {
  return largest_on_grid(centre, half, n, [&](const Eigen::Matrix3d& rotation) {
    const Eigen::Vector3d leg = (end.v + rotation * end.p).normalized();
    const Eigen::Vector3d axis =
        end.turns_with_platform ? Eigen::Vector3d(rotation * end.axis) : end.axis;
    return -axis.dot(leg);
  });
}

TEST(OrientationSearch, JointTurnBracketHoldsTheSampledLargest) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), angle(0.0, 0.4);
  for (int trial = 0; trial < 200; ++trial) {
    LegJointEnd end;
    end.v = Eigen::Vector3d(600.0 * unit(rng), 600.0 * unit(rng), 700.0 + 300.0 * unit(rng));
    end.p = Eigen::Vector3d(250.0 * unit(rng), 250.0 * unit(rng), 30.0 * unit(rng));
    end.axis = Eigen::Vector3d(0.4 * unit(rng), 0.4 * unit(rng), 1.0).normalized();
    end.turns_with_platform = trial % 2 == 1;
    const Eigen::Vector3d centre(0.2 * unit(rng), 0.2 * unit(rng), 0.3 * unit(rng));
    const Eigen::Vector3d half(angle(rng), angle(rng), angle(rng));
    const double tolerance = 1e-2;  // about half a degree: well within the box budget
    const Bracket found = largest_joint_turn(end, centre, half, {INFINITY, -INFINITY, tolerance});
    const double sampled = sampled_largest_turn(end, centre, half, 21);
    ASSERT_LE(sampled, found.hi + 1e-12) << "trial " << trial;
    ASSERT_GE(found.lo, sampled - tolerance - 1e-12) << "trial " << trial;
    ASSERT_LE(found.hi - found.lo, tolerance + 1e-12) << "trial " << trial;
  }
}

// A base joint whose axis is the leg at the range's middle: the leg turns from it by the angle
// the platform point swings through, here about z by c only (p across the leg): at +-0.2 rad
// of c the largest turn is atan(|p| sin 0.2 / ...) computed by hand from the two end poses.
TEST(OrientationSearch, JointTurnOfAHandMadeSwing) {
  LegJointEnd end;
  end.v = Eigen::Vector3d(0.0, 0.0, 1000.0);
  end.p = Eigen::Vector3d(200.0, 0.0, 0.0);
  end.axis = Eigen::Vector3d(200.0, 0.0, 1000.0).normalized();
  const Bracket found = largest_joint_turn(
      end, Eigen::Vector3d::Zero(), Eigen::Vector3d(0.0, 0.0, 0.2), {INFINITY, -INFINITY, 1e-9});
  const Eigen::Vector3d turned(200.0 * std::cos(0.2), 200.0 * std::sin(0.2), 1000.0);
  const double expected = -end.axis.dot(turned.normalized());
  EXPECT_NEAR(found.lo, expected, 1e-9);
  EXPECT_NEAR(found.hi, expected, 2e-9);
}

}  // namespace
}  // namespace pkm::workspace
