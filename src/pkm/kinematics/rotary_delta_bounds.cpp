// A rotary delta's derivative bounds and assembly-mode bound (derivative_bounds.hpp,
// assembly_mode_bounds.hpp).
#include <array>
#include <cmath>

#include "pkm/kinematics/rotary_delta.hpp"

namespace pkm::kinematics {

// An arm angle q of a rotary delta, where the platform joint w is forearm S from the elbow
// k(q) on a circle of radius T (|k'| = |k''| = T): its gradient is g = f / L, f the forearm and
// L = f . k' the lever, and implicit differentiation of |w - k(q)|^2 = S^2 gives the Hessian
// (I - k' g^T - g k'^T + (T^2 - f . k'') g g^T) / L, of norm at most
// (1 + 2 T S / L + (T^2 + T S) S^2 / L^2) / L. The lever changes by at most
// T + (T^2 + T S) S / L per mm of w: while it stays above half its value L0 at the centre, by at
// most G = T + 2 (T^2 + T S) S / L0, so over the ball L >= L0 - G r if that is above L0 / 2.
std::optional<HessianBounds> RotaryDeltaKinematics::own_hessian_bounds(
    const geometry::Vector6d& centre, double radius_mm, double /*angle_scale_mm*/,
    const Chord& chord) const {
  HessianBounds bounds;
  JointVector joints;
  JointJacobian jacobian;
  if (!inverse_and_jacobian(geometry::Pose::from_vector(centre), joints, jacobian).ok()) {
    for (int arm = 0; arm < kArms; ++arm) bounds.add(INFINITY, INFINITY);
    return bounds;
  }
  const double t = geometry().arm_length_mm;
  const double s = geometry().forearm_length_mm;
  for (int arm = 0; arm < kArms; ++arm) {
    const double lever_at_centre = s / jacobian.block<1, 3>(arm, 0).norm();
    const double lever_rate = t + 2.0 * (t * t + t * s) * s / lever_at_centre;
    const double lever = lever_at_centre - lever_rate * radius_mm;
    if (!(lever > 0.5 * lever_at_centre)) {
      bounds.add(INFINITY, INFINITY);
      continue;
    }
    const double norm =
        (1.0 + 2.0 * t * s / lever + (t * t + t * s) * s * s / (lever * lever)) / lever;
    bounds.add(norm, norm * chord.position.squaredNorm());
  }
  return bounds;
}

// No legs to check; each arm's turn per mm over the ball, for the assembly mode's bound.
LegMotion RotaryDeltaKinematics::leg_motion(const JointVector& /*joints*/,
                                            const JointJacobian& jacobian,
                                            const HessianBounds& hessians, double radius,
                                            double /*scale*/) const {
  LegMotion motion;
  for (int arm = 0; arm < kArms; ++arm) {
    motion.inner_speed.push_back(jacobian.block<1, 3>(arm, 0).norm() +
                                 hessians.norm[static_cast<std::size_t>(arm)] * radius);
  }
  return motion;
}

// The mode is the sign of det(forearms), -1 times it on the usual side (rotary_delta.hpp). Each
// forearm f = tip - shifted elbow keeps its length S; its elbow moves by the arm's length T times
// the arm's turn, so f moves by at most 1 + T times the arm's rate per mm (`joint_speed`: the
// arms' turns per mm over the ball, leg_motion's inner_speed).
std::optional<ModeBound> RotaryDeltaKinematics::mode_over_ball(
    int home_mode, const geometry::Vector6d& centre, const JointVector& joints,
    std::span<const double> joint_speed) const {
  std::array<Eigen::Vector3d, 3> forearm;
  for (int arm = 0; arm < 3; ++arm) {
    forearm[static_cast<std::size_t>(arm)] =
        Eigen::Vector3d(centre.head<3>()) - shifted_elbow(arm, joints[arm]);
  }
  const double t = geometry().arm_length_mm, s = geometry().forearm_length_mm;
  double rate = 0.0;
  for (std::size_t arm = 0; arm < 3; ++arm) {
    rate += (1.0 + t * joint_speed[arm]) * s * s;
  }
  return ModeBound{-home_mode * forearm[0].dot(forearm[1].cross(forearm[2])), rate};
}

}  // namespace pkm::kinematics
