#include "pkm/bounds/inverse_hessian.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace pkm::bounds {

namespace {

using motion::Segment;
using motion::SegmentKind;

}  // namespace

PieceMotion piece_motion(const Segment& segment, double u0, double u1, const std::vector<int>& axes,
                         double angle_scale_mm) {
  double position_speed = 0.0, position_acceleration = 0.0, angle_speed = 0.0;
  const geometry::Vector6d change = segment.end - segment.start;
  for (const int axis : axes) {
    if (axis >= 3) {
      angle_speed += std::pow(change[axis] * angle_scale_mm, 2);
    } else if (segment.kind == SegmentKind::line) {
      position_speed += change[axis] * change[axis];
    }
  }
  position_speed = std::sqrt(position_speed);
  if (segment.kind == SegmentKind::arc) {
    const auto radius = [&](const geometry::Vector6d& p) {
      return std::hypot(p[segment.first_axis] - segment.centre[segment.first_axis],
                        p[segment.second_axis] - segment.centre[segment.second_axis]);
    };
    const double r0 = radius(segment.start), r1 = radius(segment.end);
    const double widest = std::max(r0, r1), sweep = std::abs(segment.sweep_rad);
    position_speed = std::sqrt((r1 - r0) * (r1 - r0) + widest * widest * sweep * sweep +
                               change[segment.normal_axis] * change[segment.normal_axis]);
    position_acceleration = 2.0 * std::abs(r1 - r0) * sweep + widest * sweep * sweep;
  } else if (segment.kind == SegmentKind::blend) {
    const double sweep = std::abs(segment.sweep_rad);
    position_speed = segment.radius_mm * sweep;
    position_acceleration = segment.radius_mm * sweep * sweep;
  }
  const double du = u1 - u0;
  const geometry::Vector6d change_of_piece = segment.at(u1) - segment.at(u0);
  kinematics::Chord chord;
  for (const int axis : axes) {
    if (axis < 3) chord.position[axis] = change_of_piece[axis];
  }
  chord.angle = std::sqrt(angle_speed) * du;
  return {segment.at(0.5 * (u0 + u1)), std::hypot(position_speed, std::sqrt(angle_speed)) * du,
          position_acceleration * du * du, chord};
}

// The model's own joints first; its pass-through joints (a plotter's Z, a glide's pen) equal an
// axis, so their second and third derivatives are zero.
std::optional<kinematics::HessianBounds> inverse_hessian_bounds(const kinematics::Kinematics& model,
                                                                const geometry::Vector6d& centre,
                                                                double radius_mm,
                                                                double angle_scale_mm,
                                                                const kinematics::Chord& chord) {
  const kinematics::DerivativeBounds* own = model.derivative_bounds();
  if (own == nullptr) return std::nullopt;
  std::optional<kinematics::HessianBounds> bounds =
      own->own_hessian_bounds(centre, radius_mm, angle_scale_mm, chord);
  if (!bounds) return bounds;
  const bool with_third = !bounds->third.empty();
  for (int joint = static_cast<int>(bounds->norm.size()); joint < model.joint_count(); ++joint) {
    if (model.passthrough_axis(joint) < 0) return std::nullopt;
    bounds->add(0.0, 0.0);
    if (with_third) bounds->third.push_back(0.0);
  }
  return bounds;
}

// Rotations weigh as the arc they swing the farthest platform point through (twice, which
// keeps the rotation's own curvature small against the legs').
double pose_angle_scale_mm(const kinematics::Kinematics& model) {
  const kinematics::DerivativeBounds* own = model.derivative_bounds();
  const std::optional<double> farthest =
      own != nullptr ? own->farthest_platform_point_mm() : std::nullopt;
  if (!farthest) return 100.0;
  return 2.0 * std::max(*farthest, 1.0);
}

}  // namespace pkm::bounds
