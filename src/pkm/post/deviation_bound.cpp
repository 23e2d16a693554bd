#include "pkm/post/deviation_bound.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "pkm/kinematics/cable_plotter.hpp"
#include "pkm/kinematics/glide.hpp"
#include "pkm/kinematics/hexapod.hpp"
#include "pkm/kinematics/matrix.hpp"

namespace pkm::post {

namespace {

using motion::Segment;
using motion::SegmentKind;

// The operator norm, over the scaled pose ball, of the map from pose to a platform point b (mm
// from the tool tip): the identity on the position and at most |b| / scale per scaled angle.
double platform_point_gain(double b_norm_mm, double angle_scale_mm) {
  return std::sqrt(1.0 + 3.0 * (b_norm_mm / angle_scale_mm) * (b_norm_mm / angle_scale_mm));
}

// Every second derivative of R(a, b, c) b is a product of rotations and unit skew matrices, so
// |d2(R b)| <= |b| per entry; a 3 x 3 block of them has norm <= 3 |b| (per scaled angle squared).
double rotation_curvature(double b_norm_mm, double angle_scale_mm) {
  return 3.0 * b_norm_mm / (angle_scale_mm * angle_scale_mm);
}

// A cable (or leg) of length l = |p - a|: Hessian (I - n n^T) / l, norm 1 / l.
std::vector<double> cable_plotter_bounds(const CablePlotterKinematics& model,
                                         const Vector6d& centre, double radius_mm) {
  const Eigen::Vector2d p(centre[0], centre[1]);
  const double d = model.geometry().anchor_distance_mm;
  std::vector<double> bounds;
  for (const Eigen::Vector2d& anchor : {Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(d, 0.0)}) {
    const double nearest = (p - anchor).norm() - radius_mm;
    bounds.push_back(nearest > 0.0 ? 1.0 / nearest : INFINITY);
  }
  return bounds;
}

// A carriage reading s on a rail (origin o, direction d) whose strut of length L reaches the
// platform point w: s = d.(w - o) -+ f with f = sqrt(L^2 - |u|^2), u the part of w - o across
// the rail. Its Hessian in w has norm L^2 / f^3, its gradient norm <= 1 + |u| / f.
std::vector<double> glide_bounds(const GlideKinematics& model, const Vector6d& centre,
                                 double radius_mm, double angle_scale_mm) {
  const bool rotating = model.dof().any_rotation();
  Eigen::Vector3d tip = Eigen::Vector3d::Zero();
  for (int axis = 0; axis < 3; ++axis) {
    if (model.dof().controls(axis)) tip[axis] = centre[axis];
  }
  const Eigen::Matrix3d rotation =
      rotating ? rotation_from_abc(Eigen::Vector3d(centre.tail<3>())) : Eigen::Matrix3d::Identity();
  std::vector<double> bounds;
  for (const GlideRail& rail : model.rails()) {
    const Eigen::Vector3d relative = tip + rotation * rail.attach_mm - rail.origin_mm;
    const Eigen::Vector3d across = relative - rail.direction.dot(relative) * rail.direction;
    const double b = rail.attach_mm.norm();
    const double gain = rotating ? platform_point_gain(b, angle_scale_mm) : 1.0;
    const double widest = across.norm() + gain * radius_mm;
    const double strut = rail.strut_mm;
    if (widest >= strut) {
      bounds.push_back(INFINITY);
      continue;
    }
    const double f = std::sqrt(strut * strut - widest * widest);
    const double hessian_w = strut * strut / (f * f * f);
    const double gradient_w = 1.0 + widest / f;
    bounds.push_back(gain * gain * hessian_w +
                     (rotating ? gradient_w * rotation_curvature(b, angle_scale_mm) : 0.0));
  }
  return bounds;
}

// A leg l = |t + R b - a| (plus its offset): the cable's 1 / l through the platform point's map,
// and the rotation's own curvature (the leg's gradient in w is a unit vector).
std::vector<double> hexapod_bounds(const HexapodKinematics& model, const Vector6d& centre,
                                   double radius_mm, double angle_scale_mm) {
  JointVector legs;
  if (!model.inverse(Pose::from_vector(centre), legs).ok()) return std::vector<double>(6, INFINITY);
  const HexapodGeometry& geometry = model.geometry();
  std::vector<double> bounds;
  for (int i = 0; i < 6; ++i) {
    const std::size_t k = static_cast<std::size_t>(i);
    const double b =
        (geometry.platform_mm[k] + Eigen::Vector3d(0.0, 0.0, geometry.tool_length_mm)).norm();
    const double gain = platform_point_gain(b, angle_scale_mm);
    const double shortest = legs[i] - geometry.leg_offset_mm[k] - gain * radius_mm;
    bounds.push_back(shortest > 0.0 ? gain * gain / shortest + rotation_curvature(b, angle_scale_mm)
                                    : INFINITY);
  }
  return bounds;
}

// Upper bounds on the speed and acceleration of the programmed piece per unit of the block's
// fraction (scaled pose norm; angles are linear in u, so only the position curves).
struct PieceMotion {
  Vector6d centre;
  double speed = 0.0;
  double acceleration = 0.0;
};

PieceMotion piece_motion(const Segment& segment, double u0, double u1, const std::vector<int>& axes,
                         double angle_scale_mm) {
  double position_speed = 0.0, position_acceleration = 0.0, angle_speed_squared = 0.0;
  const Vector6d change = segment.end - segment.start;
  for (const int axis : axes) {
    if (axis >= 3) {
      angle_speed_squared += std::pow(change[axis] * angle_scale_mm, 2);
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
  return {segment.at(0.5 * (u0 + u1)),
          std::sqrt(position_speed * position_speed + angle_speed_squared) * du,
          position_acceleration * du * du};
}

double largest_singular_value(const Eigen::MatrixXd& m) {
  if (m.size() == 0) return 0.0;
  return Eigen::JacobiSVD<Eigen::MatrixXd>(m).singularValues()[0];
}

}  // namespace

std::optional<std::vector<double>> inverse_hessian_bounds(const Kinematics& model,
                                                          const Vector6d& centre, double radius_mm,
                                                          double angle_scale_mm) {
  if (const auto* plotter = dynamic_cast<const CablePlotterKinematics*>(&model)) {
    return cable_plotter_bounds(*plotter, centre, radius_mm);
  }
  if (const auto* glide = dynamic_cast<const GlideKinematics*>(&model)) {
    return glide_bounds(*glide, centre, radius_mm, angle_scale_mm);
  }
  if (const auto* hexapod = dynamic_cast<const HexapodKinematics*>(&model)) {
    return hexapod_bounds(*hexapod, centre, radius_mm, angle_scale_mm);
  }
  if (dynamic_cast<const MatrixKinematics*>(&model) != nullptr) {
    return std::vector<double>(static_cast<std::size_t>(model.joint_count()), 0.0);  // linear
  }
  return std::nullopt;
}

DeviationBound::DeviationBound(const Machine& machine, double reach_mm)
    : machine_(machine), reach_mm_(reach_mm) {
  const Kinematics& model = machine.kinematics();
  for (int axis = 0; axis < kPoseSize; ++axis) {
    if (model.dof().controls(axis)) axes_.push_back(axis);
  }
  // Rotations weigh as the arc they swing the farthest platform point through (twice, which
  // keeps the rotation's own curvature small against the legs').
  if (const auto* hexapod = dynamic_cast<const HexapodKinematics*>(&model)) {
    double farthest = 0.0;
    for (const Eigen::Vector3d& b : hexapod->geometry().platform_mm) {
      farthest = std::max(
          farthest, (b + Eigen::Vector3d(0.0, 0.0, hexapod->geometry().tool_length_mm)).norm());
    }
    angle_scale_mm_ = 2.0 * std::max(farthest, 1.0);
  } else if (const auto* glide = dynamic_cast<const GlideKinematics*>(&model)) {
    double farthest = 0.0;
    for (const GlideRail& rail : glide->rails())
      farthest = std::max(farthest, rail.attach_mm.norm());
    angle_scale_mm_ = 2.0 * std::max(farthest, 1.0);
  }
  available_ =
      model.joint_count() == static_cast<int>(axes_.size()) &&
      inverse_hessian_bounds(model, machine.home().as_vector(), 0.0, angle_scale_mm_).has_value();
}

double DeviationBound::operator()(const Segment& segment, double u0, double u1,
                                  const BlockEnds& ends) const {
  if (!available_) return INFINITY;
  const Kinematics& model = machine_.kinematics();
  const PieceMotion piece = piece_motion(segment, u0, u1, axes_, angle_scale_mm_);
  const int n = static_cast<int>(axes_.size());
  JointJacobian full;
  if (!model.jacobian(Pose::from_vector(piece.centre), full).ok()) return INFINITY;
  Eigen::MatrixXd jacobian(n, n);
  std::vector<int> position_rows;
  for (int k = 0; k < n; ++k) {
    const int axis = axes_[static_cast<std::size_t>(k)];
    jacobian.col(k) = full.col(axis) / (axis >= 3 ? angle_scale_mm_ : 1.0);
    if (axis < 3) position_rows.push_back(k);
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(jacobian, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const double smallest = svd.singularValues()[n - 1];
  if (!(smallest > 0.0) || !std::isfinite(smallest)) return INFINITY;
  const Eigen::MatrixXd inverse = svd.solve(Eigen::MatrixXd::Identity(n, n));
  Eigen::MatrixXd position_part(static_cast<int>(position_rows.size()), n);
  for (std::size_t r = 0; r < position_rows.size(); ++r) {
    position_part.row(static_cast<int>(r)) = inverse.row(position_rows[r]);
  }
  const double inverse_norm = 1.0 / smallest;
  const double position_inverse_norm = largest_singular_value(position_part);

  // Every pose the argument visits lies within the piece's half length plus the reach of the
  // programmed point at the same fraction (docs/post.md, "The bound").
  const double radius = 0.5 * piece.speed + reach_mm_;
  const auto hessians = inverse_hessian_bounds(model, piece.centre, radius, angle_scale_mm_);
  if (!hessians) return INFINITY;
  double lipschitz = 0.0;
  for (const double h : *hessians) lipschitz += h * h;
  lipschitz = std::sqrt(lipschitz);  // of the Jacobian, per unit of pose distance
  const double drift = inverse_norm * lipschitz * radius;
  if (!(drift < 1.0)) return INFINITY;
  const double inverse_bound = inverse_norm / (1.0 - drift);
  const double position_inverse_bound =
      position_inverse_norm + inverse_bound * inverse_norm * lipschitz * radius;

  // Per joint: the written ends' rounding, and the chord error of the joint along the
  // programmed piece, |G''| / 8 with G'' = H[S', S'] + grad . S''.
  double joint_error = 0.0;
  for (int i = 0; i < n; ++i) {
    const double h = (*hessians)[static_cast<std::size_t>(i)];
    const double gradient = jacobian.row(i).norm() + h * radius;
    const double rounding = std::max(std::abs(ends.written0[i] - ends.exact0[i]),
                                     std::abs(ends.written1[i] - ends.exact1[i]));
    const double chord = (h * piece.speed * piece.speed + gradient * piece.acceleration) / 8.0;
    joint_error += std::pow(rounding + chord, 2);
  }
  joint_error = std::sqrt(joint_error);
  if (!(inverse_bound * joint_error < reach_mm_)) return INFINITY;
  return position_inverse_bound * joint_error;
}

}  // namespace pkm::post
