// How fast the leg limits' values can change over a ball of poses (mechanism_rate.hpp).
#include "pkm/post/mechanism_rate.hpp"

#include <algorithm>
#include <cmath>

#include "pkm/kinematics/glide.hpp"
#include "pkm/kinematics/hexapod.hpp"
#include "pkm/kinematics/leg_limits.hpp"
#include "pkm/kinematics/rotary_delta.hpp"

namespace pkm::post {

LegMotion leg_motion(const Kinematics& model, const JointVector& joints,
                     const JointJacobian& jacobian, const HessianBounds& hessians, double radius,
                     double scale) {
  LegMotion motion;
  if (const auto* hexapod = dynamic_cast<const HexapodKinematics*>(&model)) {
    const HexapodGeometry& g = hexapod->geometry();
    for (std::size_t i = 0; i < 6; ++i) {
      const double b = (g.platform_mm[i] + Eigen::Vector3d(0.0, 0.0, g.tool_length_mm)).norm();
      const double gain = platform_point_gain(b, scale);
      motion.inner_speed.push_back(0.0);
      motion.platform_speed.push_back(gain);
      motion.shortest_mm.push_back(joints[static_cast<int>(i)] - g.leg_offset_mm[i] -
                                   gain * radius);
    }
    motion.platform_turn = std::sqrt(3.0) / scale;
  } else if (const auto* glide = dynamic_cast<const GlideKinematics*>(&model)) {
    const bool rotating = glide->dof().any_rotation();
    for (std::size_t i = 0; i < glide->rails().size(); ++i) {
      const GlideRail& rail = glide->rails()[i];
      // The carriage moves as its reading: the gradient at the centre plus its drift.
      Eigen::VectorXd gradient = jacobian.row(static_cast<int>(i)).transpose();
      gradient.tail<3>() /= scale;
      motion.inner_speed.push_back(gradient.norm() + hessians.norm[i] * radius);
      motion.platform_speed.push_back(rotating ? platform_point_gain(rail.attach_mm.norm(), scale)
                                               : 1.0);
      motion.shortest_mm.push_back(rail.strut_mm);
    }
    motion.platform_turn = rotating ? std::sqrt(3.0) / scale : 0.0;
  } else if (dynamic_cast<const RotaryDeltaKinematics*>(&model) != nullptr) {
    // No legs to check; each arm's turn per mm over the ball, for the assembly mode's bound.
    for (int arm = 0; arm < RotaryDeltaKinematics::kArms; ++arm) {
      motion.inner_speed.push_back(jacobian.block<1, 3>(arm, 0).norm() +
                                   hessians.norm[static_cast<std::size_t>(arm)] * radius);
    }
  }
  return motion;
}

// How fast (per scaled unit) a joint-angle or clearance value can change over the ball.
double mechanism_rate(const MechanismLimit& limit, const LegMotion& motion) {
  const auto k = static_cast<std::size_t>(limit.leg);
  if (limit.code == StatusCode::joint_angle) {
    if (!(motion.shortest_mm[k] > 0.0)) return INFINITY;
    const double turn = (motion.inner_speed[k] + motion.platform_speed[k]) / motion.shortest_mm[k];
    return turn + (limit.other == kPlatformEnd ? motion.platform_turn : 0.0);
  }
  // Each point of a leg is a mix of its ends: it moves no faster than the faster end.
  const auto j = static_cast<std::size_t>(limit.other);
  return std::max(motion.inner_speed[k], motion.platform_speed[k]) +
         std::max(motion.inner_speed[j], motion.platform_speed[j]);
}

}  // namespace pkm::post
