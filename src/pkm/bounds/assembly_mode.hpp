// A translating glide's assembly mode over a ball of poses: home's mode times the determinant of
// its strut vectors (the 2-D cross product with two rails), which keeps its sign within a mode,
// and how fast it can change given how fast each strut moves. One bound for what the certified
// job check (a ball around a piece of a move) and the workspace (a cell) both prove with.
#pragma once

#include <span>

#include "pkm/kinematics/glide.hpp"

namespace pkm::bounds {

// The mode value at the ball's centre (positive in home's mode) and an upper bound on how fast it
// changes per unit of the ball's radius: value - rate * radius > 0 proves the mode over the ball.
struct ModeBound {
  double value = 0.0;
  double rate = 0.0;
};

// `absolute`: the determinant itself (mm^3, mm^2 with two rails), each strut's speed in mm per
// unit of the ball's radius (the certified check's, from the carriages' rates). `per_length`: the
// determinant over the product of the struts' lengths, each strut's speed per mm of its own
// length (the workspace's). The same sign either way; both kept so that each caller's arithmetic,
// and with it every proof's outcome, stays as it was.
enum class ModeScale { absolute, per_length };

// Over a ball about the pose `centre` (mm, rad; the coordinates the rails move) whose carriages
// read `joints`, each strut vector (tip + attach - origin - reading * direction, of fixed length)
// moving at most `strut_speed[i]` per unit of radius: |d det| <= sum over the struts of its speed
// times the other struts' lengths. A translating glide only (two or three rails).
ModeBound glide_mode_bound(const GlideKinematics& glide, int home_mode, const Vector6d& centre,
                           const JointVector& joints, std::span<const double> strut_speed,
                           ModeScale scale);

}  // namespace pkm::bounds
