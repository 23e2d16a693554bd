// Bounds on the inverse kinematics' second (and, for hexapods, third) derivatives over a ball of
// poses in a scaled pose norm (angles weighed in mm per rad), and the motion of a programmed
// piece of a move in that norm: what post's deviation bound (post/deviation_bound.hpp), the
// certified job check, the workspace and the pose-box joint-rate bound (pose_box_rate.hpp) all
// prove with (the argument is in docs/post.md, "The bound").
#pragma once

#include <optional>
#include <vector>

#include "pkm/kinematics/derivative_bounds.hpp"
#include "pkm/kinematics/kinematics.hpp"
#include "pkm/motion/segment.hpp"

namespace pkm::bounds {

// Upper bounds on the programmed piece [u0, u1] of a move per unit of the piece's own fraction
// (angles are linear in u, so only the position curves): its length and the acceleration of its
// position, in the scaled pose norm below over the coordinates `axes`.
struct PieceMotion {
  geometry::Vector6d centre;  // the pose at the piece's middle fraction (mm, rad)
  double length = 0.0;        // of the piece (scaled pose norm), at most
  double acceleration = 0.0;
  kinematics::Chord chord;  // from the piece's start to its end
};
PieceMotion piece_motion(const motion::Segment& segment, double u0, double u1,
                         const std::vector<int>& axes, double angle_scale_mm);

// Per joint, over every pose within `radius_mm` of `centre` (mm, rad) in the model's controlled
// coordinates with rotations scaled by `angle_scale_mm` (mm per rad, so that one norm serves
// lengths and angles): HessianBounds for v = `chord`, the model's own joints by its
// DerivativeBounds, its pass-through joints zero.
// Nothing for models with no such bound here (formula machines).
std::optional<kinematics::HessianBounds> inverse_hessian_bounds(const kinematics::Kinematics& model,
                                                                const geometry::Vector6d& centre,
                                                                double radius_mm,
                                                                double angle_scale_mm,
                                                                const kinematics::Chord& chord);

// The scale (mm per rad) that makes angles comparable with lengths in the bounds above: twice
// the distance of the model's farthest platform point from the tool tip (hexapods, glides:
// DerivativeBounds::farthest_platform_point_mm), else 100 mm.
double pose_angle_scale_mm(const kinematics::Kinematics& model);

}  // namespace pkm::bounds
