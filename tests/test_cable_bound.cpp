// Proven bounds on a hanging effector's balance over a box of pen positions
// (bounds/cable_bound.hpp): hand-computed tensions of a symmetric gondola, the pull region's edge
// under a pulley at x = r, and a soundness property on Makelangelo-size geometry with straight
// cables: every tension, tilt and joint the statics solve at thousands of random points of
// random boxes lies within the box's bounds.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "pkm/bounds/cable_bound.hpp"
#include "pkm/kinematics/cable_plotter.hpp"
#include "test_support.hpp"

namespace pkm::bounds {
namespace {

constexpr double kG = kinematics::kStandardGravity_mm_per_s2 * 1e-3;  // N per kg

kinematics::CablePlotterGeometry gondola(double mass_kg) {
  kinematics::CablePlotterGeometry g = kinematics::CablePlotterGeometry::level(600.0);
  g.anchors_mm = {Eigen::Vector2d(-300.0, 0.0), Eigen::Vector2d(300.0, 0.0)};
  g.effector_mass_kg = mass_kg;
  return g;
}

// Makelangelo-size (examples/machines/makelangelo.toml) with straight cables: no sag; its
// stretch kept where `stretch`.
kinematics::CablePlotterGeometry straight_makelangelo(bool stretch) {
  const machine::Machine machine = test::load_example("makelangelo.toml");
  kinematics::CablePlotterGeometry g =
      dynamic_cast<const kinematics::CablePlotterKinematics&>(machine.kinematics()).geometry();
  g.cable_density_kg_per_m = 0.0;
  if (!stretch) g.cable_stretch_mm_per_m_per_N = 0.0;
  return g;
}

bool holds(const Range& range, double value) {
  return range.lo <= value && value <= range.hi;
}

TEST(CableBound, SymmetricGondolaBelowTheMiddleCarriesHalfItsWeightOverTheCosine) {
  // A point gondola 400 mm below the middle: each cable 500 mm long at cos = 400 / 500 = 0.8
  // from the vertical, T = W / (2 * 0.8) = 2 kg * g / 1.6 = 12.258 N.
  const kinematics::CablePlotterGeometry g = gondola(2.0);
  const double expected = 2.0 * kG / 1.6;
  EXPECT_NEAR(expected, 12.2583125, 1e-6);
  const CableBoxBound at = cable_box_bound(g, {0.0, -400.0}, {0.0, 0.0});
  ASSERT_TRUE(at.known);
  for (const Range& t : at.tension_N) {
    EXPECT_NEAR(t.lo, expected, 1e-8);
    EXPECT_NEAR(t.hi, expected, 1e-8);
  }
  // A 1 mm box about it: T within W / (2 cos) at its corners, which differ by O(1 mm / 500 mm).
  const CableBoxBound box = cable_box_bound(g, {0.0, -400.0}, {1.0, 1.0});
  ASSERT_TRUE(box.known);
  for (const Range& t : box.tension_N) {
    EXPECT_TRUE(holds(t, expected));
    EXPECT_LT(t.hi - t.lo, 0.1);
  }
  // Joints: the cables' lengths, 500 mm.
  EXPECT_NEAR(at.joint_mm[0].lo, 500.0, 1e-7);
  EXPECT_NEAR(at.joint_mm[1].hi, 500.0, 1e-7);
}

TEST(CableBound, SymmetricTiltingGondolaStaysLevelAndCarriesHalfItsWeight) {
  // Tied 20 mm either side and 10 mm above the pen, the centre of mass 15 mm below it: straight
  // below the middle the ends are at (-+20, -390), each cable leans 280 / 390 off the vertical
  // from its end to its anchor (at +-300): cos = 390 / hypot(280, 390); T = W / (2 cos).
  kinematics::CablePlotterGeometry g = gondola(0.3);
  g.attach_mm = {Eigen::Vector2d(-20.0, 10.0), Eigen::Vector2d(20.0, 10.0)};
  g.center_of_mass_mm = {0.0, -15.0};
  const double cosine = 390.0 / std::hypot(280.0, 390.0);
  const double expected = 0.3 * kG / (2.0 * cosine);
  const CableBoxBound box = cable_box_bound(g, {0.0, -400.0}, {0.01, 0.01});
  ASSERT_TRUE(box.known);
  EXPECT_TRUE(holds(box.tilt_rad, 0.0));
  EXPECT_LT(box.tilt_rad.hi - box.tilt_rad.lo, 1e-3);
  for (const Range& t : box.tension_N) {
    EXPECT_TRUE(holds(t, expected)) << t.lo << " " << t.hi << " " << expected;
    EXPECT_LT(t.hi - t.lo, 1e-2 * expected);
  }
}

TEST(CableBound, UnderAPulleyTheLeftCablePullsOnlyRightOfItsVerticalTangent) {
  // hektor-pulleys.toml: pulleys of r = 6.366 mm at x = 0 and 100. The left cable hangs
  // straight down from the pulley's rightmost point when the pen is at x = r: there the right
  // cable's tension (under a unit load) falls to 0; left of it the right cable would push.
  const machine::Machine machine = test::load_example("hektor-pulleys.toml");
  const kinematics::CablePlotterGeometry& g =
      dynamic_cast<const kinematics::CablePlotterKinematics&>(machine.kinematics()).geometry();
  const double r = g.pulley_radius_mm;
  const CableBoxBound clear = cable_box_bound(g, {r + 0.2, -50.0}, {0.1, 5.0});
  ASSERT_TRUE(clear.known);
  EXPECT_GT(clear.tension_N[0].lo, 0.0);
  EXPECT_GT(clear.tension_N[1].lo, 0.0);
  EXPECT_GT(clear.apart.lo, 0.0);
  const CableBoxBound past = cable_box_bound(g, {r - 0.2, -50.0}, {0.1, 5.0});
  ASSERT_TRUE(past.known);
  EXPECT_LT(past.tension_N[1].hi, 0.0);  // refused everywhere in the box
  const CableBoxBound across = cable_box_bound(g, {r, -50.0}, {0.1, 5.0});
  ASSERT_TRUE(across.known);
  EXPECT_LT(across.tension_N[1].lo, 0.0);
  EXPECT_GT(across.tension_N[1].hi, 0.0);
  // And the machine agrees on either side.
  kinematics::JointVector joints;
  EXPECT_TRUE(
      machine.inverse(geometry::Pose::from_mm_deg(r + 1e-6, -50.0, 0.0, 0, 0, 0), joints).ok());
  EXPECT_FALSE(
      machine.inverse(geometry::Pose::from_mm_deg(r - 1e-6, -50.0, 0.0, 0, 0, 0), joints).ok());
}

// Random boxes over (and past) the board, random points inside each: wherever the statics find
// a balance, its tilt, tensions and joints lie within the box's bounds. Counts what was
// compared, so that the test cannot pass on nothing.
void expect_sound(const kinematics::CablePlotterGeometry& g, const Eigen::Vector2d& lo,
                  const Eigen::Vector2d& hi, int boxes, int points_per_box) {
  const kinematics::CablePlotterKinematics model(g);
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int compared = 0, known = 0, tight = 0;
  for (int b = 0; b < boxes; ++b) {
    const Eigen::Vector2d centre(lo.x() + (hi.x() - lo.x()) * unit(rng),
                                 lo.y() + (hi.y() - lo.y()) * unit(rng));
    const double size = std::pow(10.0, -2.0 + 3.7 * unit(rng));  // 0.01 to 50 mm
    const Eigen::Vector2d half(size * unit(rng), size * unit(rng));
    const CableBoxBound bound = cable_box_bound(g, centre, half);
    if (!bound.known) continue;
    ++known;
    for (int p = 0; p < points_per_box; ++p) {
      // Corners and edges too: a third of the points on the box's boundary.
      Eigen::Vector2d at(centre.x() + half.x() * (2.0 * unit(rng) - 1.0),
                         centre.y() + half.y() * (2.0 * unit(rng) - 1.0));
      if (p % 3 == 0) at.x() = centre.x() + (unit(rng) < 0.5 ? -half.x() : half.x());
      kinematics::CableBalance balance;
      const Eigen::Vector2d gravity(0.0, -kinematics::kStandardGravity_mm_per_s2);
      if (!kinematics::solve_cable_balance(g, at, gravity, balance).ok()) continue;
      ++compared;
      ASSERT_TRUE(holds(bound.tilt_rad, balance.statics.tilt_rad))
          << "tilt " << balance.statics.tilt_rad << " at " << at.transpose();
      const double scale = g.effector_mass_kg > 0.0 ? 1.0 : 0.0;
      for (int c = 0; c < 2; ++c) {
        const auto k = static_cast<std::size_t>(c);
        if (scale > 0.0) {
          ASSERT_TRUE(holds(bound.tension_N[k], balance.statics.tension_N[k]))
              << "cable " << c << " tension " << balance.statics.tension_N[k] << " not in ["
              << bound.tension_N[k].lo << ", " << bound.tension_N[k].hi << "] at " << at.transpose()
              << " box " << centre.transpose() << " +- " << half.transpose();
        }
        const double w = g.effector_mass_kg > 0.0 ? g.effector_mass_kg * kG : 1.0;
        const double unit_tension = balance.statics.tension_N[k] / (scale > 0.0 ? 1.0 : 0.0);
        if (scale > 0.0) {
          ASSERT_TRUE(holds(bound.inverse_tension_per_N[k], 1.0 / unit_tension))
              << "1 / tension " << 1.0 / unit_tension << " not in ["
              << bound.inverse_tension_per_N[k].lo << ", " << bound.inverse_tension_per_N[k].hi
              << "] (w " << w << ")";
        }
        if (bound.tension_N[k].lo > 0.0) {
          ASSERT_TRUE(balance.pulls[k]);
        }
        if (bound.tension_N[k].hi < 0.0) {
          ASSERT_FALSE(balance.pulls[k]);
        }
        const double joint =
            kinematics::cable_joint(g, kinematics::cable_past_top(g, balance, c), c);
        ASSERT_TRUE(holds(bound.joint_mm[k], joint))
            << "joint " << joint << " not in [" << bound.joint_mm[k].lo << ", "
            << bound.joint_mm[k].hi << "]";
      }
      if (bound.tension_N[0].lo > 0.0 && bound.tension_N[1].lo > 0.0) ++tight;
    }
  }
  std::printf("%d boxes bounded of %d, %d points compared, %d in proven-pulling boxes\n", known,
              boxes, compared, tight);
  // Segments: the box's diagonal, either way; points on it only (the mean-value form along it).
  int on_segments = 0;
  for (int b = 0; b < boxes; ++b) {
    const Eigen::Vector2d centre(lo.x() + (hi.x() - lo.x()) * unit(rng),
                                 lo.y() + (hi.y() - lo.y()) * unit(rng));
    const double size = std::pow(10.0, -2.0 + 3.7 * unit(rng));
    Eigen::Vector2d half_chord(size * (2.0 * unit(rng) - 1.0), size * (2.0 * unit(rng) - 1.0));
    const CableBoxBound bound = cable_box_bound(g, centre, half_chord.cwiseAbs(), &half_chord);
    if (!bound.known) continue;
    for (int p = 0; p < points_per_box; ++p) {
      const double s = p == 0 ? -1.0 : (p == 1 ? 1.0 : 2.0 * unit(rng) - 1.0);
      kinematics::CableBalance balance;
      const Eigen::Vector2d at = centre + s * half_chord;
      if (!kinematics::solve_cable_balance(g, at, {0.0, -kinematics::kStandardGravity_mm_per_s2},
                                           balance)
               .ok())
        continue;
      ++on_segments;
      for (std::size_t k = 0; k < 2 && g.effector_mass_kg > 0.0; ++k) {
        ASSERT_TRUE(holds(bound.tension_N[k], balance.statics.tension_N[k]))
            << "segment: cable " << k << " tension " << balance.statics.tension_N[k] << " not in ["
            << bound.tension_N[k].lo << ", " << bound.tension_N[k].hi << "]";
      }
    }
  }
  std::printf("%d points compared on segments\n", on_segments);
  EXPECT_GT(on_segments, boxes * points_per_box / 3);
  EXPECT_GT(known, boxes / 2);
  EXPECT_GT(compared, boxes * points_per_box / 3);
}

TEST(CableBound, MakelangeloStraightCablesTensionsTiltAndJointsLieWithinTheBounds) {
  expect_sound(straight_makelangelo(false), {-400.0, -600.0}, {400.0, 450.0}, 400, 12);
}

TEST(CableBound, MakelangeloStretchingCablesJointsLieWithinTheBounds) {
  expect_sound(straight_makelangelo(true), {-400.0, -600.0}, {400.0, 450.0}, 200, 12);
}

TEST(CableBound, MaslowSledOnStraightChainsLiesWithinTheBounds) {
  // maslow-frame.toml without its chain's weight: a 9 kg sled tied 155 mm either side of the bit
  // and 139 mm above it, 10.275 mm sprockets 2978.4 mm apart, stretching chains.
  const machine::Machine machine = test::load_example("maslow-frame.toml");
  kinematics::CablePlotterGeometry g =
      dynamic_cast<const kinematics::CablePlotterKinematics&>(machine.kinematics()).geometry();
  g.cable_density_kg_per_m = 0.0;
  expect_sound(g, {-200.0, -2200.0}, {3200.0, 100.0}, 200, 12);
}

TEST(CableBound, PulleysWithoutMassPullWithinTheBounds) {
  const machine::Machine machine = test::load_example("hektor-pulleys.toml");
  const kinematics::CablePlotterGeometry& g =
      dynamic_cast<const kinematics::CablePlotterKinematics&>(machine.kinematics()).geometry();
  expect_sound(g, {-20.0, -180.0}, {120.0, 10.0}, 300, 12);
}

TEST(CableBound, SaggingCablesAreNotBounded) {
  const machine::Machine machine = test::load_example("makelangelo.toml");
  const kinematics::CablePlotterGeometry& g =
      dynamic_cast<const kinematics::CablePlotterKinematics&>(machine.kinematics()).geometry();
  EXPECT_NE(cable_bound_unavailable(g).find("sag"), std::string::npos);
  EXPECT_FALSE(cable_box_bound(g, {0.0, 0.0}, {1.0, 1.0}).known);
}

}  // namespace
}  // namespace pkm::bounds
