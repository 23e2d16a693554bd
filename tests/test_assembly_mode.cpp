// A translating glide's assembly-mode bound (bounds/assembly_mode.hpp), computed by hand: a
// biglide whose struts are (160, -120) and (-160, -120) mm at the pose (30, -120), both scales,
// and the rails' plane read from the rails (a Z pen pass-through is not a third plane axis).
#include <gtest/gtest.h>

#include <array>

#include "pkm/bounds/assembly_mode.hpp"

namespace pkm::bounds {
namespace {

GlideKinematics biglide_with_pen() {
  std::vector<GlideRail> rails(2);
  rails[0] = {{0, 0, 0}, {1, 0, 0}, 200.0, {-20, 0, 0}, -1};
  rails[1] = {{0, 0, 0}, {1, 0, 0}, 200.0, {20, 0, 0}, 1};
  return GlideKinematics(rails, Dof::planar_xy(), PassThroughAxes({2}, Dof::planar_xy()));
}

TEST(AssemblyModeBound, BiglideDeterminantAndRateByHand) {
  const GlideKinematics biglide = biglide_with_pen();
  JointVector joints;
  const Pose pose = Pose::from_mm_deg(30, -120, 4);  // the pen 4 mm up: not a rail axis
  ASSERT_TRUE(biglide.inverse(pose, joints).ok());
  // Carriages at -150 and 210: struts (30 - 20 + 150, -120) and (30 + 20 - 210, -120), whose
  // cross product is 160 (-120) - (-120) (-160) = -38400 mm^2.
  const std::array<double, 2> speed{2.0, 3.0};
  const ModeBound absolute =
      glide_mode_bound(biglide, 1, pose.as_vector(), joints, speed, ModeScale::absolute);
  EXPECT_NEAR(absolute.value, -38400.0, 1e-9);
  EXPECT_DOUBLE_EQ(absolute.rate, 2.0 * 200.0 + 200.0 * 3.0);
  // Home on the other side: the value changes sign, the rate does not.
  const std::array<double, 2> per_mm{0.01, 0.02};
  const ModeBound relative =
      glide_mode_bound(biglide, -1, pose.as_vector(), joints, per_mm, ModeScale::per_length);
  EXPECT_NEAR(relative.value, 38400.0 / (200.0 * 200.0), 1e-15);
  EXPECT_DOUBLE_EQ(relative.rate, 0.03);
}

}  // namespace
}  // namespace pkm::bounds
