// A rigid cable plotter's derivative bounds (derivative_bounds.hpp).
#include <algorithm>
#include <cmath>

#include "pkm/kinematics/cable_plotter.hpp"

namespace pkm::kinematics {

// A cable (or leg) of length l = |p - a|: Hessian (I - n n^T) / l, norm 1 / l; along v,
// |v|^2 sin^2 / l = |v|^2 h^2 / l^3 with h the anchor's distance from the line through p along v.
// Over a pulley of radius r the reading is r phi + s with s the straight span: its gradient is
// still the cable's unit direction u (the tangent point moves along u), so its Hessian is
// (I - u u^T) / s, and u is within asin(r / |p - a|) of the direction from the pulley's centre.
// Models whose cables sag, stretch, build up on a drum or tilt the effector have no such bound
// here.
std::optional<HessianBounds> CablePlotterKinematics::own_hessian_bounds(
    const geometry::Vector6d& centre, double radius_mm, double /*angle_scale_mm*/,
    const Chord& chord) const {
  const CablePlotterGeometry& g = geometry();
  if (!g.rigid()) return std::nullopt;
  const Eigen::Vector2d p(centre[0], centre[1]);
  const double r = g.pulley_radius_mm;
  HessianBounds bounds;
  for (const Eigen::Vector2d& anchor : g.anchors_mm) {
    const double nearest = (p - anchor).norm() - radius_mm;
    const Eigen::Vector2d v = chord.position.head<2>();
    const double across =
        v.norm() > 0.0
            ? std::abs(v.x() * (p - anchor).y() - v.y() * (p - anchor).x()) / v.norm() + radius_mm
            : 0.0;
    if (nearest > r) {
      const double span = std::sqrt(nearest * nearest - r * r);
      const double sine = std::min(1.0, (across + r) / nearest);
      bounds.add(1.0 / span, v.squaredNorm() / span * sine * sine);
    } else {
      bounds.add(INFINITY, INFINITY);
    }
  }
  return bounds;
}

}  // namespace pkm::kinematics
