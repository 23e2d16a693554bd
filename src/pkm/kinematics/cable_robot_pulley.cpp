// A cable robot's swivelling pulleys (docs/kinematics.md, "Cable robot: pulleys"). The cable
// arrives along the swivel axis w and first touches the pulley at the anchor A; the pulley turns
// about w so that its plane holds the tie point B. In that plane, with e the unit vector from the
// axis towards B and the pulley's centre M = A + r e, the cable wraps from A by theta and leaves
// at the tangent point towards B: B - M = R(theta) (-r, -s) in (e, w) coordinates, s the straight
// span. The length r theta + s has gradient u = sin(theta) e - cos(theta) w, the span's direction.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "pkm/kinematics/cable_robot.hpp"

namespace pkm::kinematics {

Status pulley_path(const RobotCable& cable, const Eigen::Vector3d& tie_mm, PulleyPath& path) {
  const double r = cable.pulley_radius_mm;
  const Eigen::Vector3d w = cable.pulley_axis.normalized();
  const Eigen::Vector3d d = tie_mm - cable.anchor_mm;
  path.along_axis_mm = d.dot(w);
  const Eigen::Vector3d across = d - path.along_axis_mm * w;
  path.axis_distance_mm = across.norm();
  const double x = path.axis_distance_mm - r, y = path.along_axis_mm;
  path.rim_distance_mm = std::hypot(x, y);
  if (!(path.axis_distance_mm >= kShortestRobotCable_mm) || !(path.rim_distance_mm > r)) {
    return Status::failure(StatusCode::unreachable);
  }
  const Eigen::Vector3d e = across / path.axis_distance_mm;
  path.span_mm = std::sqrt((path.rim_distance_mm - r) * (path.rim_distance_mm + r));
  // atan2(y, x) - atan2(-s, -r) lies in (-pi / 2, 2 pi); below 0 only where x < -r, which the
  // axis distance >= 0 excludes but for rounding.
  path.wrap_rad = std::max(0.0, std::atan2(y, x) - std::atan2(-path.span_mm, -r));
  path.length_mm = r * path.wrap_rad + path.span_mm;
  path.direction = std::sin(path.wrap_rad) * e - std::cos(path.wrap_rad) * w;
  return Status::success();
}

void validate_cable_robot_pulleys(const CableRobotGeometry& g) {
  for (const RobotCable& cable : g.cables) {
    if (!(cable.pulley_radius_mm >= 0.0) || !std::isfinite(cable.pulley_radius_mm)) {
      throw std::invalid_argument("pulley_radius: must be a length of 0 or more (mm)");
    }
    if (cable.pulley_radius_mm == 0.0) continue;
    if (!cable.pulley_axis.allFinite() || !(cable.pulley_axis.norm() > 0.0)) {
      throw std::invalid_argument(
          "pulley_axis: a pulley needs the direction its cable arrives from (a non-zero [x, y, "
          "z] from the anchor towards the winch)");
    }
    if (cable.swivel_arm_mm != 0.0) {
      throw std::invalid_argument(
          "pulley_radius: not with a swivel_arm (the arm points at the anchor, not at the "
          "pulley's tangent point)");
    }
    if (g.flex_compensation) {
      throw std::invalid_argument(
          "flex_compensation: not with pulleys (RepRapFirmware's forces take straight lines from "
          "point anchors; a cable has pulley_radius " +
          formatted_number("%.3f", cable.pulley_radius_mm) + " mm)");
    }
  }
}

}  // namespace pkm::kinematics
