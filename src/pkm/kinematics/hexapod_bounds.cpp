// A hexapod's derivative bounds, legs and assembly-mode bound over a box (derivative_bounds.hpp,
// assembly_mode_bounds.hpp).
#include <algorithm>
#include <cmath>

#include "pkm/kinematics/hexapod.hpp"

namespace pkm::kinematics {

// A leg l = |t + R b - a| (plus its offset): the cable's 1 / l through the platform point's map,
// and the rotation's own curvature (the leg's gradient in w is a unit vector).
std::optional<HessianBounds> HexapodKinematics::own_hessian_bounds(const geometry::Vector6d& centre,
                                                                   double radius_mm,
                                                                   double angle_scale_mm,
                                                                   const Chord& chord) const {
  HessianBounds bounds;
  JointVector legs;
  if (!inverse_without_leg_limits(geometry::Pose::from_vector(centre), legs).ok()) {
    for (int i = 0; i < 6; ++i) bounds.add(INFINITY, INFINITY);
    return bounds;
  }
  const HexapodGeometry& g = geometry();
  for (int i = 0; i < 6; ++i) {
    const std::size_t k = static_cast<std::size_t>(i);
    const double b = g.platform_from_tip_mm(k).norm();
    const double gain = platform_point_gain(b, angle_scale_mm);
    const double shortest = legs[i] - g.leg_offset_mm[k] - gain * radius_mm;
    if (!(shortest > 0.0)) {
      bounds.add(INFINITY, INFINITY);
      continue;
    }
    const double turning = rotation_curvature(b, angle_scale_mm);
    const double w_change = platform_point_change(chord.position.norm(), chord, b, angle_scale_mm);
    const double w_curve = turning * chord.angle * chord.angle;
    bounds.add(gain * gain / shortest + turning, w_change * w_change / shortest + w_curve);
    // l''' = D3|w|[w', w', w'] + 3 D2|w|[w', w''] + n . w''', with |D3|w|| <= 3 / l^2,
    // |D2|w|| <= 1 / l and every third derivative of R b of norm <= |b| per entry.
    const double w_third = 3.0 * std::sqrt(3.0) * b * std::pow(chord.angle / angle_scale_mm, 3);
    bounds.third.push_back(3.0 * std::pow(w_change, 3) / (shortest * shortest) +
                           3.0 * w_change * w_curve / shortest + w_third);
  }
  return bounds;
}

std::optional<double> HexapodKinematics::farthest_platform_point_mm() const {
  double farthest = 0.0;
  for (std::size_t leg = 0; leg < 6; ++leg)
    farthest = std::max(farthest, geometry().platform_from_tip_mm(leg).norm());
  return farthest;
}

LegMotion HexapodKinematics::leg_motion(const JointVector& joints,
                                        const JointJacobian& /*jacobian*/,
                                        const HessianBounds& /*hessians*/, double radius,
                                        double scale) const {
  LegMotion motion;
  const HexapodGeometry& g = geometry();
  for (std::size_t i = 0; i < 6; ++i) {
    const double b = g.platform_from_tip_mm(i).norm();
    const double gain = platform_point_gain(b, scale);
    motion.inner_speed.push_back(0.0);
    motion.platform_speed.push_back(gain);
    motion.platform_arm_mm.push_back(b);
    motion.shortest_mm.push_back(joints[static_cast<int>(i)] - g.leg_offset_mm[i] - gain * radius);
  }
  motion.platform_turn = std::sqrt(3.0) / scale;
  return motion;
}

std::optional<LegEnds> HexapodKinematics::legs_at(const geometry::Pose& pose,
                                                  const JointVector& /*joints*/) const {
  return leg_ends(pose);
}

// The platform tilted less than 90 deg (leg -1; a home upside down has no bound here), then each
// platform joint on home's side of the base plane (tilt_low, base_side_bound: the bounds the
// workspace takes over a cell).
std::optional<ModeShortfall> HexapodKinematics::mode_over_box(
    int home_mode, const geometry::Vector6d& centre, const geometry::Vector6d& half) const {
  const double tilt = tilt_low(centre, half);
  if (home_mode < 0 || !(tilt > 0.0)) return ModeShortfall{-1, tilt};
  const BaseSideBound side = base_side_bound(centre, half);
  if (!(side.low > 0.0)) return ModeShortfall{side.leg, side.low};
  return std::nullopt;
}

}  // namespace pkm::kinematics
