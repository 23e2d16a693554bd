#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "pkm/geometry/pose.hpp"

namespace pkm {
namespace {

TEST(Rotation, ComposesAsRzRyRx) {
  const Eigen::Vector3d abc(0.3, -0.7, 1.9);
  const Eigen::Matrix3d expected = (Eigen::AngleAxisd(abc.z(), Eigen::Vector3d::UnitZ()) *
                                    Eigen::AngleAxisd(abc.y(), Eigen::Vector3d::UnitY()) *
                                    Eigen::AngleAxisd(abc.x(), Eigen::Vector3d::UnitX()))
                                       .toRotationMatrix();
  EXPECT_TRUE(geometry::rotation_from_abc(abc).isApprox(expected, 1e-15));
}

TEST(Rotation, HandComputedQuarterTurns) {
  // A = 90 deg turns +Y into +Z; C = 90 deg turns +X into +Y.
  const Eigen::Vector3d y_turned =
      geometry::rotation_from_abc({M_PI / 2, 0, 0}) * Eigen::Vector3d::UnitY();
  EXPECT_NEAR((y_turned - Eigen::Vector3d::UnitZ()).norm(), 0.0, 1e-15);
  const Eigen::Vector3d x_turned =
      geometry::rotation_from_abc({0, 0, M_PI / 2}) * Eigen::Vector3d::UnitX();
  EXPECT_NEAR((x_turned - Eigen::Vector3d::UnitY()).norm(), 0.0, 1e-15);
  // B = 90 deg turns +Z into +X.
  const Eigen::Vector3d z_turned =
      geometry::rotation_from_abc({0, M_PI / 2, 0}) * Eigen::Vector3d::UnitZ();
  EXPECT_NEAR((z_turned - Eigen::Vector3d::UnitX()).norm(), 0.0, 1e-15);
}

TEST(Rotation, DerivativesMatchFiniteDifferences) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> angle(-3.0, 3.0);
  for (int trial = 0; trial < 100; ++trial) {
    const Eigen::Vector3d abc(angle(rng), angle(rng), angle(rng));
    Eigen::Matrix3d rotation;
    std::array<Eigen::Matrix3d, 3> derivatives;
    geometry::rotation_and_derivatives_abc(abc, rotation, derivatives);
    EXPECT_EQ(rotation,
              geometry::rotation_from_abc(abc));  // the same sines and cosines, the same bits
    for (int k = 0; k < 3; ++k) {
      const double step = 1e-6;
      Eigen::Vector3d plus = abc, minus = abc;
      plus[k] += step;
      minus[k] -= step;
      const Eigen::Matrix3d numeric =
          (geometry::rotation_from_abc(plus) - geometry::rotation_from_abc(minus)) / (2 * step);
      EXPECT_LT((numeric - derivatives[k]).cwiseAbs().maxCoeff(), 1e-9) << "angle " << k;
    }
  }
}

TEST(Pose, InterfaceUnitsAreMillimetresAndDegrees) {
  const geometry::Pose pose = geometry::Pose::from_mm_deg(1, 2, 3, 90, 180, -45);
  EXPECT_DOUBLE_EQ(pose.orientation_rad.x(), M_PI / 2);
  EXPECT_DOUBLE_EQ(pose.orientation_rad.y(), M_PI);
  EXPECT_DOUBLE_EQ(pose.orientation_rad.z(), -M_PI / 4);
  EXPECT_EQ(geometry::Pose::from_vector(pose.as_vector()).position_mm, pose.position_mm);
  EXPECT_EQ(geometry::axis_index("B"), 4);
  EXPECT_EQ(geometry::axis_index("q"), -1);
}

}  // namespace
}  // namespace pkm
