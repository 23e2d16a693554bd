// Bounds on how fast the leg limits' values (MechanismLimit: a joint end's angle, two legs'
// clearance) can change over a ball of poses in the scaled pose norm of inverse_hessian_bounds.
// One place for what the certified job check (a ball around a piece of a move) and the workspace
// (a ball around a cell of poses) both prove with: value at the centre +- rate * radius.
#pragma once

#include <optional>
#include <vector>

#include "pkm/bounds/inverse_hessian.hpp"
#include "pkm/kinematics/kinematics.hpp"
#include "pkm/kinematics/leg_limits.hpp"

namespace pkm::bounds {

// Over the ball of `radius` (scaled, angles weighing `scale` mm per rad) about the pose whose
// joints and Jacobian are given, `hessians` the bounds inverse_hessian_bounds gives on that ball.
// The model's own answer (DerivativeBounds::leg_motion); empty for models without legs.
// Rotary deltas: only inner_speed (each arm's turn per mm), for their assembly-mode bound.
kinematics::LegMotion leg_motion(const kinematics::Kinematics& model,
                                 const kinematics::JointVector& joints,
                                 const kinematics::JointJacobian& jacobian,
                                 const kinematics::HessianBounds& hessians, double radius,
                                 double scale);

// How fast (per scaled unit) a joint-angle or clearance value can change over the ball.
double mechanism_rate(const kinematics::MechanismLimit& limit, const kinematics::LegMotion& motion);

// The legs at the ball's centre (DerivativeBounds::legs_at: hexapods and glides; nothing for
// other models).
std::optional<kinematics::LegEnds> legs_at(const kinematics::Kinematics& model,
                                           const geometry::Pose& pose,
                                           const kinematics::JointVector& joints);

// How far a value can fall below (down) and rise above (up) its value at the ball's centre:
// rate * radius both ways for a joint angle, and for a clearance without `ends`. With them, a
// clearance is bounded where the legs are closest: the translation moves the point at s of one
// leg and the point at u of the other alike (parting them by at most radius |s - u|), and a
// leg's own motion (its carriage, the platform's turn) moves its point at s by at most the mix
// of its ends', so the legs stay at least
//   min over (s, u) in [0, 1]^2 of |X(s) - Y(u)| - radius |s - u| - own_i(s) - own_j(u)
// apart (X, Y the legs at the centre: convex on each side of s = u, minimised to 1e-6 mm), and
// at most that minimum's |X(s*) - Y(u*)| plus those moves.
struct Reach {
  double down = 0.0, up = 0.0;
};
Reach mechanism_reach(const kinematics::MechanismLimit& limit, const kinematics::LegMotion& motion,
                      double radius, const kinematics::LegEnds* ends);

}  // namespace pkm::bounds
