// A translating glide's assembly-mode bound as the proofs ask it (bounds/assembly_mode.hpp over a
// ball, the model's AssemblyModeBounds over a cell), computed by hand: a biglide whose struts are
// (160, -120) and (-160, -120) mm at the pose (30, -120), both scales, and the rails' plane read
// from the rails (a Z pen pass-through is not a third plane axis).
#include <gtest/gtest.h>

#include <array>

#include "pkm/bounds/assembly_mode.hpp"
#include "pkm/kinematics/glide.hpp"

namespace pkm::bounds {
namespace {

kinematics::GlideKinematics biglide_with_pen() {
  std::vector<kinematics::GlideRail> rails(2);
  rails[0] = {{0, 0, 0}, {1, 0, 0}, 200.0, {-20, 0, 0}, -1};
  rails[1] = {{0, 0, 0}, {1, 0, 0}, 200.0, {20, 0, 0}, 1};
  return kinematics::GlideKinematics(rails, geometry::Dof::planar_xy(),
                                     kinematics::PassThroughAxes({2}, geometry::Dof::planar_xy()));
}

TEST(AssemblyModeBound, BiglideDeterminantAndRateByHand) {
  const kinematics::GlideKinematics biglide = biglide_with_pen();
  kinematics::JointVector joints;
  const geometry::Pose pose =
      geometry::Pose::from_mm_deg(30, -120, 4);  // the pen 4 mm up: not a rail axis
  ASSERT_TRUE(biglide.inverse(pose, joints).ok());
  ASSERT_TRUE(has_assembly_bound(biglide, 1));
  // Carriages at -150 and 210: struts (30 - 20 + 150, -120) and (30 + 20 - 210, -120), whose
  // cross product is 160 (-120) - (-120) (-160) = -38400 mm^2. Carriages moving 1 and 2 per unit
  // move their struts 2 and 3.
  const std::array<double, 3> carriage_speed{1.0, 2.0, 0.0};
  const std::optional<kinematics::ModeBound> absolute =
      assembly_mode_over_ball(biglide, 1, pose.as_vector(), joints, carriage_speed);
  ASSERT_TRUE(absolute.has_value());
  EXPECT_NEAR(absolute->value, -38400.0, 1e-9);
  EXPECT_DOUBLE_EQ(absolute->rate, 2.0 * 200.0 + 200.0 * 3.0);
  // Home on the other side, over a cell of positions within 40 mm: the value changes sign and is
  // over the struts' lengths; each strut, 120 mm across its rail at the centre and at most 160 mm
  // over the cell, moves at most 1 / sqrt(200^2 - 160^2) = 1 / 120 per mm.
  const std::optional<kinematics::ModeBound> relative =
      biglide.mode_over_cell(-1, pose.as_vector(), 40.0);
  ASSERT_TRUE(relative.has_value());
  EXPECT_NEAR(relative->value, 38400.0 / (200.0 * 200.0), 1e-15);
  EXPECT_NEAR(relative->rate, 2.0 / 120.0, 1e-15);
  // A cell whose struts would have to lie along their rails: no bound.
  EXPECT_FALSE(biglide.mode_over_cell(-1, pose.as_vector(), 80.0).has_value());
}

TEST(AssemblyModeBound, OneModeNeedsNoBoundAndATurningGlideHasNone) {
  const kinematics::GlideKinematics biglide = biglide_with_pen();
  kinematics::JointVector joints;
  const geometry::Pose pose = geometry::Pose::from_mm_deg(30, -120, 4);
  ASSERT_TRUE(biglide.inverse(pose, joints).ok());
  const std::array<double, 3> speed{1.0, 2.0, 0.0};
  const std::optional<kinematics::ModeBound> single =
      assembly_mode_over_ball(biglide, 0, pose.as_vector(), joints, speed);
  ASSERT_TRUE(single.has_value());
  EXPECT_EQ(single->value, 1.0);
  EXPECT_EQ(single->rate, 0.0);
  // A hexaglide turns its platform: its mode has no bound over a ball here.
  std::vector<kinematics::GlideRail> rails(6);
  for (int i = 0; i < 6; ++i) {
    const double angle = i * 1.0471975511965976;
    rails[static_cast<std::size_t>(i)] = {{300.0 * std::cos(angle), 300.0 * std::sin(angle), 0},
                                          {0, 0, 1},
                                          250.0,
                                          {60.0 * std::cos(angle), 60.0 * std::sin(angle), 0},
                                          1};
  }
  const kinematics::GlideKinematics hexaglide(rails, geometry::Dof::all());
  EXPECT_EQ(hexaglide.assembly_mode_bounds(), nullptr);
  EXPECT_FALSE(has_assembly_bound(hexaglide, 1));
  EXPECT_TRUE(has_assembly_bound(hexaglide, 0));
}

}  // namespace
}  // namespace pkm::bounds
