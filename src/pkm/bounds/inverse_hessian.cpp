#include "pkm/bounds/inverse_hessian.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "pkm/kinematics/cable_plotter.hpp"
#include "pkm/kinematics/glide.hpp"
#include "pkm/kinematics/hexapod.hpp"
#include "pkm/kinematics/matrix.hpp"
#include "pkm/kinematics/rotary_delta.hpp"

namespace pkm::bounds {

double platform_point_gain(double b_norm_mm, double angle_scale_mm) {
  return std::sqrt(1.0 + 3.0 * (b_norm_mm / angle_scale_mm) * (b_norm_mm / angle_scale_mm));
}

namespace {

using motion::Segment;
using motion::SegmentKind;

// Every second derivative of R(a, b, c) b is a product of rotations and unit skew matrices, so
// |d2(R b)| <= |b| per entry; a 3 x 3 block of them has norm <= 3 |b| (per scaled angle squared).
double rotation_curvature(double b_norm_mm, double angle_scale_mm) {
  return 3.0 * b_norm_mm / (angle_scale_mm * angle_scale_mm);
}

// How far a platform point b (mm from the tool tip) moves for a pose change `position` mm and
// `chord.angle` scaled (each angle's derivative of R b has norm <= |b|).
double platform_point_change(double position, const Chord& chord, double b_norm_mm,
                             double angle_scale_mm) {
  return position + std::sqrt(3.0) * b_norm_mm / angle_scale_mm * chord.angle;
}

void add(HessianBounds& bounds, double norm, double along) {
  bounds.norm.push_back(norm);
  bounds.along.push_back(along);
}

// A cable (or leg) of length l = |p - a|: Hessian (I - n n^T) / l, norm 1 / l; along v,
// |v|^2 sin^2 / l = |v|^2 h^2 / l^3 with h the anchor's distance from the line through p along v.
// Over a pulley of radius r the reading is r phi + s with s the straight span: its gradient is
// still the cable's unit direction u (the tangent point moves along u), so its Hessian is
// (I - u u^T) / s, and u is within asin(r / |p - a|) of the direction from the pulley's centre.
// Models whose cables sag, stretch, build up on a drum or tilt the effector have no such bound
// here.
std::optional<HessianBounds> cable_plotter_bounds(const CablePlotterKinematics& model,
                                                  const Vector6d& centre, double radius_mm,
                                                  const Chord& chord) {
  const CablePlotterGeometry& g = model.geometry();
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
      add(bounds, 1.0 / span, v.squaredNorm() / span * sine * sine);
    } else {
      add(bounds, INFINITY, INFINITY);
    }
  }
  return bounds;
}

// A carriage reading s on a rail (origin o, direction d) whose strut of length L reaches the
// platform point w: s = d.(w - o) -+ f with f = sqrt(L^2 - |u|^2), u the part of w - o across
// the rail. Its Hessian in w has norm L^2 / f^3, its gradient norm <= 1 + |u| / f.
HessianBounds glide_bounds(const GlideKinematics& model, const Vector6d& centre, double radius_mm,
                           double angle_scale_mm, const Chord& chord) {
  const bool rotating = model.dof().any_rotation();
  Eigen::Vector3d tip = Eigen::Vector3d::Zero();
  for (int axis = 0; axis < 3; ++axis) {
    if (model.dof().controls(axis)) tip[axis] = centre[axis];
  }
  const Eigen::Matrix3d rotation =
      rotating ? rotation_from_abc(Eigen::Vector3d(centre.tail<3>())) : Eigen::Matrix3d::Identity();
  HessianBounds bounds;
  for (const GlideRail& rail : model.rails()) {
    const Eigen::Vector3d relative = tip + rotation * rail.attach_mm - rail.origin_mm;
    const Eigen::Vector3d across = relative - rail.direction.dot(relative) * rail.direction;
    const double b = rail.attach_mm.norm();
    const double gain = rotating ? platform_point_gain(b, angle_scale_mm) : 1.0;
    const double widest = across.norm() + gain * radius_mm;
    const double strut = rail.strut_mm;
    if (widest >= strut) {
      add(bounds, INFINITY, INFINITY);
      continue;
    }
    const double f = std::sqrt(strut * strut - widest * widest);
    const double hessian_w = strut * strut / (f * f * f);  // norm, in w
    const double turning = rotating ? (1.0 + widest / f) * rotation_curvature(b, angle_scale_mm)
                                    : 0.0;  // the gradient in w times R b's curvature
    // Only the part x of w's change across the rail bends the reading: |H_w[x, x]| =
    // |x|^2 / f + (u . x)^2 / f^3, and u . x / |x| moves with the ball's radius (translating).
    const Eigen::Vector3d v = chord.position;
    const Eigen::Vector3d x = v - rail.direction.dot(v) * rail.direction;
    double u_along_x = widest;
    if (!rotating && x.norm() > 0.0) {
      u_along_x = std::min(widest, std::abs(across.dot(x.normalized())) + radius_mm);
    }
    const double w_change =
        rotating ? platform_point_change(x.norm(), chord, b, angle_scale_mm) : x.norm();
    add(bounds, gain * gain * hessian_w + turning,
        w_change * w_change * (1.0 / f + u_along_x * u_along_x / (f * f * f)) +
            turning * chord.angle * chord.angle);
  }
  return bounds;
}

// A leg l = |t + R b - a| (plus its offset): the cable's 1 / l through the platform point's map,
// and the rotation's own curvature (the leg's gradient in w is a unit vector).
HessianBounds hexapod_bounds(const HexapodKinematics& model, const Vector6d& centre,
                             double radius_mm, double angle_scale_mm, const Chord& chord) {
  HessianBounds bounds;
  JointVector legs;
  if (!model.inverse_without_leg_limits(Pose::from_vector(centre), legs).ok()) {
    for (int i = 0; i < 6; ++i) add(bounds, INFINITY, INFINITY);
    return bounds;
  }
  const HexapodGeometry& geometry = model.geometry();
  for (int i = 0; i < 6; ++i) {
    const std::size_t k = static_cast<std::size_t>(i);
    const double b = geometry.platform_from_tip_mm(k).norm();
    const double gain = platform_point_gain(b, angle_scale_mm);
    const double shortest = legs[i] - geometry.leg_offset_mm[k] - gain * radius_mm;
    if (!(shortest > 0.0)) {
      add(bounds, INFINITY, INFINITY);
      continue;
    }
    const double turning = rotation_curvature(b, angle_scale_mm);
    const double w_change = platform_point_change(chord.position.norm(), chord, b, angle_scale_mm);
    const double w_curve = turning * chord.angle * chord.angle;
    add(bounds, gain * gain / shortest + turning, w_change * w_change / shortest + w_curve);
    // l''' = D3|w|[w', w', w'] + 3 D2|w|[w', w''] + n . w''', with |D3|w|| <= 3 / l^2,
    // |D2|w|| <= 1 / l and every third derivative of R b of norm <= |b| per entry.
    const double w_third = 3.0 * std::sqrt(3.0) * b * std::pow(chord.angle / angle_scale_mm, 3);
    bounds.third.push_back(3.0 * std::pow(w_change, 3) / (shortest * shortest) +
                           3.0 * w_change * w_curve / shortest + w_third);
  }
  return bounds;
}

// An arm angle q of a rotary delta, where the platform joint w is forearm S from the elbow
// k(q) on a circle of radius T (|k'| = |k''| = T): its gradient is g = f / L, f the forearm and
// L = f . k' the lever, and implicit differentiation of |w - k(q)|^2 = S^2 gives the Hessian
// (I - k' g^T - g k'^T + (T^2 - f . k'') g g^T) / L, of norm at most
// (1 + 2 T S / L + (T^2 + T S) S^2 / L^2) / L. The lever changes by at most
// T + (T^2 + T S) S / L per mm of w: while it stays above half its value L0 at the centre, by at
// most G = T + 2 (T^2 + T S) S / L0, so over the ball L >= L0 - G r if that is above L0 / 2.
HessianBounds rotary_delta_bounds(const RotaryDeltaKinematics& model, const Vector6d& centre,
                                  double radius_mm, const Chord& chord) {
  HessianBounds bounds;
  JointVector joints;
  JointJacobian jacobian;
  if (!model.inverse_and_jacobian(Pose::from_vector(centre), joints, jacobian).ok()) {
    for (int arm = 0; arm < RotaryDeltaKinematics::kArms; ++arm) add(bounds, INFINITY, INFINITY);
    return bounds;
  }
  const double t = model.geometry().arm_length_mm;
  const double s = model.geometry().forearm_length_mm;
  for (int arm = 0; arm < RotaryDeltaKinematics::kArms; ++arm) {
    const double lever_at_centre = s / jacobian.block<1, 3>(arm, 0).norm();
    const double lever_rate = t + 2.0 * (t * t + t * s) * s / lever_at_centre;
    const double lever = lever_at_centre - lever_rate * radius_mm;
    if (!(lever > 0.5 * lever_at_centre)) {
      add(bounds, INFINITY, INFINITY);
      continue;
    }
    const double norm =
        (1.0 + 2.0 * t * s / lever + (t * t + t * s) * s * s / (lever * lever)) / lever;
    add(bounds, norm, norm * chord.position.squaredNorm());
  }
  return bounds;
}

}  // namespace

PieceMotion piece_motion(const Segment& segment, double u0, double u1, const std::vector<int>& axes,
                         double angle_scale_mm) {
  double position_speed = 0.0, position_acceleration = 0.0, angle_speed = 0.0;
  const Vector6d change = segment.end - segment.start;
  for (const int axis : axes) {
    if (axis >= 3) {
      angle_speed += std::pow(change[axis] * angle_scale_mm, 2);
    } else if (segment.kind == SegmentKind::line) {
      position_speed += change[axis] * change[axis];
    }
  }
  position_speed = std::sqrt(position_speed);
  if (segment.kind == SegmentKind::arc) {
    const auto radius = [&](const Vector6d& p) {
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
  const Vector6d change_of_piece = segment.at(u1) - segment.at(u0);
  Chord chord;
  for (const int axis : axes) {
    if (axis < 3) chord.position[axis] = change_of_piece[axis];
  }
  chord.angle = std::sqrt(angle_speed) * du;
  return {segment.at(0.5 * (u0 + u1)), std::hypot(position_speed, std::sqrt(angle_speed)) * du,
          position_acceleration * du * du, chord};
}

namespace {

std::optional<HessianBounds> model_hessian_bounds(const Kinematics& model, const Vector6d& centre,
                                                  double radius_mm, double angle_scale_mm,
                                                  const Chord& chord) {
  if (const auto* plotter = dynamic_cast<const CablePlotterKinematics*>(&model)) {
    return cable_plotter_bounds(*plotter, centre, radius_mm, chord);
  }
  if (const auto* glide = dynamic_cast<const GlideKinematics*>(&model)) {
    return glide_bounds(*glide, centre, radius_mm, angle_scale_mm, chord);
  }
  if (const auto* hexapod = dynamic_cast<const HexapodKinematics*>(&model)) {
    return hexapod_bounds(*hexapod, centre, radius_mm, angle_scale_mm, chord);
  }
  if (const auto* delta = dynamic_cast<const RotaryDeltaKinematics*>(&model)) {
    return rotary_delta_bounds(*delta, centre, radius_mm, chord);
  }
  if (dynamic_cast<const MatrixKinematics*>(&model) != nullptr) {
    const std::vector<double> zero(static_cast<std::size_t>(model.joint_count()), 0.0);
    return HessianBounds{zero, zero, {}};  // linear
  }
  return std::nullopt;
}

}  // namespace

// The model's own joints first; its pass-through joints (a plotter's Z, a glide's pen) equal an
// axis, so their second and third derivatives are zero.
std::optional<HessianBounds> inverse_hessian_bounds(const Kinematics& model, const Vector6d& centre,
                                                    double radius_mm, double angle_scale_mm,
                                                    const Chord& chord) {
  std::optional<HessianBounds> bounds =
      model_hessian_bounds(model, centre, radius_mm, angle_scale_mm, chord);
  if (!bounds) return bounds;
  const bool with_third = !bounds->third.empty();
  for (int joint = static_cast<int>(bounds->norm.size()); joint < model.joint_count(); ++joint) {
    if (model.passthrough_axis(joint) < 0) return std::nullopt;
    add(*bounds, 0.0, 0.0);
    if (with_third) bounds->third.push_back(0.0);
  }
  return bounds;
}

// Rotations weigh as the arc they swing the farthest platform point through (twice, which
// keeps the rotation's own curvature small against the legs').
double pose_angle_scale_mm(const Kinematics& model) {
  double farthest = 0.0;
  if (const auto* hexapod = dynamic_cast<const HexapodKinematics*>(&model)) {
    for (std::size_t leg = 0; leg < 6; ++leg)
      farthest = std::max(farthest, hexapod->geometry().platform_from_tip_mm(leg).norm());
  } else if (const auto* glide = dynamic_cast<const GlideKinematics*>(&model)) {
    for (const GlideRail& rail : glide->rails())
      farthest = std::max(farthest, rail.attach_mm.norm());
  } else {
    return 100.0;
  }
  return 2.0 * std::max(farthest, 1.0);
}

}  // namespace pkm::bounds
