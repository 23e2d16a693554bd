// Bounds on the inverse kinematics' second (and, for hexapods, third) derivatives over a ball of
// poses in a scaled pose norm (angles weighed in mm per rad), and the motion of a programmed
// piece of a move in that norm: what post's deviation bound (post/deviation_bound.hpp), the
// certified job check, the workspace and the pose-box joint-rate bound (pose_box_rate.hpp) all
// prove with (the argument is in docs/post.md, "The bound").
#pragma once

#include <optional>
#include <vector>

#include "pkm/kinematics/kinematics.hpp"
#include "pkm/motion/segment.hpp"

namespace pkm::bounds {

// A straight move in pose space: its position change (mm, zero in the coordinates the model
// does not control) and the norm of its angle change (scaled, see below).
struct Chord {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  double angle = 0.0;
};

// The operator norm, over the scaled pose ball, of the map from pose to a platform point b (mm
// from the tool tip): the identity on the position and at most |b| / scale per scaled angle.
double platform_point_gain(double b_norm_mm, double angle_scale_mm);

// Upper bounds on the programmed piece [u0, u1] of a move per unit of the piece's own fraction
// (angles are linear in u, so only the position curves): its length and the acceleration of its
// position, in the scaled pose norm below over the coordinates `axes`.
struct PieceMotion {
  Vector6d centre;      // the pose at the piece's middle fraction (mm, rad)
  double length = 0.0;  // of the piece (scaled pose norm), at most
  double acceleration = 0.0;
  Chord chord;  // from the piece's start to its end
};
PieceMotion piece_motion(const motion::Segment& segment, double u0, double u1,
                         const std::vector<int>& axes, double angle_scale_mm);

// Per joint, over every pose within `radius_mm` of `centre` (mm, rad) in the model's controlled
// coordinates with rotations scaled by `angle_scale_mm` (mm per rad, so that one norm serves
// lengths and angles): `norm`, an upper bound on the operator norm of the Hessian of the joint's
// inverse kinematics, and `along`, on |H[v, v]| for v = `chord`. Infinity where the ball reaches
// a singularity of the model. `third`, where the model gives one, bounds |D3 IK_i[v, v, v]| on
// the ball (empty otherwise).
struct HessianBounds {
  std::vector<double> norm, along, third;
};
// Nothing for models with no such bound here (formula machines).
std::optional<HessianBounds> inverse_hessian_bounds(const Kinematics& model, const Vector6d& centre,
                                                    double radius_mm, double angle_scale_mm,
                                                    const Chord& chord);

// The scale (mm per rad) that makes angles comparable with lengths in the bounds above: twice
// the distance of the model's farthest platform point from the tool tip (hexapods, glides), else
// 100 mm.
double pose_angle_scale_mm(const Kinematics& model);

}  // namespace pkm::bounds
