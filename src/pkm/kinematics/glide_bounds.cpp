// A glide's derivative bounds, legs, reach over a cell and assembly-mode bounds
// (derivative_bounds.hpp, assembly_mode_bounds.hpp).
#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "pkm/kinematics/glide.hpp"

namespace pkm::kinematics {

// A carriage reading s on a rail (origin o, direction d) whose strut of length L reaches the
// platform point w: s = d.(w - o) -+ f with f = sqrt(L^2 - |u|^2), u the part of w - o across
// the rail. Its Hessian in w has norm L^2 / f^3, its gradient norm <= 1 + |u| / f.
std::optional<HessianBounds> GlideKinematics::own_hessian_bounds(const geometry::Vector6d& centre,
                                                                 double radius_mm,
                                                                 double angle_scale_mm,
                                                                 const Chord& chord) const {
  const bool rotating = dof().any_rotation();
  Eigen::Vector3d tip = Eigen::Vector3d::Zero();
  for (int axis = 0; axis < 3; ++axis) {
    if (dof().controls(axis)) tip[axis] = centre[axis];
  }
  const Eigen::Matrix3d rotation =
      rotating ? geometry::rotation_from_abc(Eigen::Vector3d(centre.tail<3>()))
               : Eigen::Matrix3d::Identity();
  HessianBounds bounds;
  for (const GlideRail& rail : rails()) {
    const Eigen::Vector3d relative = tip + rotation * rail.attach_mm - rail.origin_mm;
    const Eigen::Vector3d across = relative - rail.direction.dot(relative) * rail.direction;
    const double b = rail.attach_mm.norm();
    const double gain = rotating ? platform_point_gain(b, angle_scale_mm) : 1.0;
    const double widest = across.norm() + gain * radius_mm;
    const double strut = rail.strut_mm;
    if (widest >= strut) {
      bounds.add(INFINITY, INFINITY);
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
    bounds.add(gain * gain * hessian_w + turning,
               w_change * w_change * (1.0 / f + u_along_x * u_along_x / (f * f * f)) +
                   turning * chord.angle * chord.angle);
  }
  return bounds;
}

std::optional<double> GlideKinematics::farthest_platform_point_mm() const {
  double farthest = 0.0;
  for (const GlideRail& rail : rails()) farthest = std::max(farthest, rail.attach_mm.norm());
  return farthest;
}

LegMotion GlideKinematics::leg_motion(const JointVector& /*joints*/, const JointJacobian& jacobian,
                                      const HessianBounds& hessians, double radius,
                                      double scale) const {
  LegMotion motion;
  const bool rotating = dof().any_rotation();
  for (std::size_t i = 0; i < rails().size(); ++i) {
    const GlideRail& rail = rails()[i];
    // The carriage moves as its reading: the gradient at the centre plus its drift.
    Eigen::VectorXd gradient = jacobian.row(static_cast<int>(i)).transpose();
    gradient.tail<3>() /= scale;
    motion.inner_speed.push_back(gradient.norm() + hessians.norm[i] * radius);
    motion.platform_speed.push_back(rotating ? platform_point_gain(rail.attach_mm.norm(), scale)
                                             : 1.0);
    motion.platform_arm_mm.push_back(rail.attach_mm.norm());
    motion.shortest_mm.push_back(rail.strut_mm);
  }
  motion.platform_turn = rotating ? std::sqrt(3.0) / scale : 0.0;
  return motion;
}

std::optional<LegEnds> GlideKinematics::legs_at(const geometry::Pose& pose,
                                                const JointVector& joints) const {
  return leg_ends(pose, joints);
}

// A strut reaches its rail: g = L - |u|, u the part of the platform point w - o across the rail.
// |u| is 1-Lipschitz in w, and w moves at most `platform_point_gain` times the scaled pose change
// (the identity for a translating platform).
void GlideKinematics::reach_over_cell(const geometry::Vector6d& centre, double scaled_radius,
                                      double position_radius_mm, double angle_scale_mm,
                                      std::span<std::array<double, 2>> margins) const {
  const bool rotating = rail_dof().any_rotation();
  const Eigen::Matrix3d rotation =
      rotating ? geometry::rotation_from_abc(Eigen::Vector3d(centre.tail<3>()))
               : Eigen::Matrix3d::Identity();
  Eigen::Vector3d tip = Eigen::Vector3d::Zero();
  for (int axis = 0; axis < 3; ++axis) {
    if (rail_dof().controls(axis)) tip[axis] = centre[axis];
  }
  for (std::size_t i = 0; i < rails().size(); ++i) {
    const GlideRail& rail = rails()[i];
    const Eigen::Vector3d relative = tip + rotation * rail.attach_mm - rail.origin_mm;
    const double across = (relative - rail.direction.dot(relative) * rail.direction).norm();
    const double gain =
        rotating ? std::sqrt(1.0 + 3.0 * std::pow(rail.attach_mm.norm() / angle_scale_mm, 2)) : 1.0;
    const double change = rotating ? gain * scaled_radius : position_radius_mm;
    margins[i] = {rail.strut_mm - across - change, rail.strut_mm - across + change};
  }
}

ReachMargin GlideKinematics::reach_margin(int index) const {
  return {"strut " + std::to_string(index + 1) + "'s reach of its rail (mm)", false,
          Status::failure(StatusCode::unreachable, index)};
}

namespace {

// Its rails' plane with two rails, its space with three: det[strut vectors].
double strut_determinant(const GlideKinematics& glide, const std::array<Eigen::Vector3d, 3>& strut,
                         int rails) {
  if (rails == 3) return strut[0].dot(strut[1].cross(strut[2]));
  int plane[2] = {0, 1};
  for (int axis = 0, k = 0; axis < 3 && k < 2; ++axis) {
    if (glide.rail_dof().controls(axis)) plane[k++] = axis;
  }
  return strut[0][plane[0]] * strut[1][plane[1]] - strut[0][plane[1]] * strut[1][plane[0]];
}

// `absolute`: the determinant itself (mm^3, mm^2 with two rails), each strut's speed in mm per
// unit of the ball's radius (the certified check's). `per_length`: the determinant over the
// product of the struts' lengths, each strut's speed per mm of its own length (the workspace's).
// The same sign either way; both kept so that each caller's arithmetic, and with it every proof's
// outcome, stays as it was.
enum class ModeScale { absolute, per_length };

// Over a ball about the pose `centre` whose carriages read `joints`, each strut vector (tip +
// attach - origin - reading * direction, of fixed length) moving at most `strut_speed[i]` per
// unit of radius: |d det| <= sum over the struts of its speed times the other struts' lengths.
ModeBound glide_mode_bound(const GlideKinematics& glide, int home_mode,
                           const geometry::Vector6d& centre, const JointVector& joints,
                           std::span<const double> strut_speed, ModeScale scale) {
  const int rails = static_cast<int>(glide.rails().size());
  Eigen::Vector3d tip = Eigen::Vector3d::Zero();
  for (int axis = 0; axis < 3; ++axis) {
    if (glide.rail_dof().controls(axis)) tip[axis] = centre[axis];
  }
  std::array<Eigen::Vector3d, 3> strut;
  for (int i = 0; i < rails; ++i) {
    const GlideRail& rail = glide.rails()[static_cast<std::size_t>(i)];
    strut[static_cast<std::size_t>(i)] =
        tip + rail.attach_mm - rail.origin_mm - joints[i] * rail.direction;
  }
  const double determinant = strut_determinant(glide, strut, rails);
  const auto speed = [&](int i) { return strut_speed[static_cast<std::size_t>(i)]; };
  const auto length = [&](int i) { return glide.rails()[static_cast<std::size_t>(i)].strut_mm; };
  if (scale == ModeScale::per_length) {
    double lengths = 1.0, rate = 0.0;
    for (int i = 0; i < rails; ++i) {
      rate += speed(i);
      lengths *= length(i);
    }
    return {home_mode * determinant / lengths, rate};
  }
  if (rails == 3) {
    return {home_mode * determinant, speed(0) * length(1) * length(2) +
                                         length(0) * speed(1) * length(2) +
                                         length(0) * length(1) * speed(2)};
  }
  return {home_mode * determinant, speed(0) * length(1) + length(0) * speed(1)};
}

}  // namespace

// A translating glide's mode: home's mode times det[strut vectors] (the 2-D cross product with two
// rails), which keeps its sign within a mode. Each strut keeps its length and moves its vector by
// at most (1 + its carriage's speed) per unit of the ball's radius.
std::optional<ModeBound> GlideKinematics::mode_over_ball(
    int home_mode, const geometry::Vector6d& centre, const JointVector& joints,
    std::span<const double> joint_speed) const {
  std::array<double, 3> strut_speed{};
  const std::size_t count = rails().size();
  for (std::size_t i = 0; i < count; ++i) strut_speed[i] = 1.0 + joint_speed[i];
  return glide_mode_bound(*this, home_mode, centre, joints, std::span(strut_speed.data(), count),
                          ModeScale::absolute);
}

// g = mode * det[struts] / (L1 L2 L3) (the 2-D cross product for two rails). Each strut vector
// s_i = w - o_i - q_i d_i keeps its length L_i and moves at most L_i / f_i per mm of the tip,
// f_i = sqrt(L_i^2 - |u_i|^2) its part along the rail, so the normalised determinant moves at
// most sum 1 / f_i,min per mm.
std::optional<ModeBound> GlideKinematics::mode_over_cell(int home_mode,
                                                         const geometry::Vector6d& centre,
                                                         double radius_mm) const {
  Eigen::Vector3d tip = Eigen::Vector3d::Zero();
  for (int axis = 0; axis < 3; ++axis) {
    if (rail_dof().controls(axis)) tip[axis] = centre[axis];
  }
  JointVector joints;
  if (!inverse(geometry::Pose::from_vector(centre), joints).ok()) return std::nullopt;
  std::array<double, 3> strut_speed{};  // per mm of the tip, per mm of the strut's length
  const std::size_t count = rails().size();
  for (std::size_t i = 0; i < count; ++i) {
    const GlideRail& rail = rails()[i];
    const Eigen::Vector3d relative = tip + rail.attach_mm - rail.origin_mm;
    const double widest =
        (relative - rail.direction.dot(relative) * rail.direction).norm() + radius_mm;
    if (!(widest < rail.strut_mm)) return std::nullopt;
    strut_speed[i] = 1.0 / std::sqrt(rail.strut_mm * rail.strut_mm - widest * widest);
  }
  return glide_mode_bound(*this, home_mode, centre, joints, std::span(strut_speed.data(), count),
                          ModeScale::per_length);
}

}  // namespace pkm::kinematics
