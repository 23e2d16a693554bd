// Bounds on how fast the leg limits' values (MechanismLimit: a joint end's angle, two legs'
// clearance) can change over a ball of poses in the scaled pose norm of inverse_hessian_bounds.
// One place for what the certified job check (a ball around a piece of a move) and the workspace
// (a ball around a cell of poses) both prove with: value at the centre +- rate * radius.
#pragma once

#include <vector>

#include "pkm/kinematics/kinematics.hpp"
#include "pkm/post/deviation_bound.hpp"

namespace pkm::post {

// How each leg's ends move per unit of the scaled pose norm over a ball, and how short the leg
// can get there: what the joint-angle and clearance bounds take. Empty for models without legs.
struct LegMotion {
  std::vector<double> inner_speed, platform_speed, shortest_mm;
  double platform_turn = 0.0;  // rad per scaled unit: how fast a platform-fixed axis turns
};

// Over the ball of `radius` (scaled, angles weighing `scale` mm per rad) about the pose whose
// joints and Jacobian are given, `hessians` the bounds inverse_hessian_bounds gives on that ball.
// Rotary deltas: only inner_speed (each arm's turn per mm), for their assembly-mode bound.
LegMotion leg_motion(const Kinematics& model, const JointVector& joints,
                     const JointJacobian& jacobian, const HessianBounds& hessians, double radius,
                     double scale);

// How fast (per scaled unit) a joint-angle or clearance value can change over the ball.
double mechanism_rate(const MechanismLimit& limit, const LegMotion& motion);

}  // namespace pkm::post
