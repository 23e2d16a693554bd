// An upper bound on how far the tool tip of a joint-linear block strays from the piece of the
// programmed path it stands for, from bounds on the inverse kinematics' second (and, for
// hexapods, third) derivatives over a ball, the joints at the piece's middle, and each joint's
// error weighed by how far it moves the tool (the argument is in docs/post.md, "The bound").
#pragma once

#include <optional>
#include <vector>

#include "pkm/machine/machine.hpp"
#include "pkm/motion/segment.hpp"

namespace pkm::post {

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

// The ends of a joint-linear block: the joints as written (rounded) and as the inverse kinematics
// gives them at the programmed ends of the piece.
struct BlockEnds {
  JointVector written0, exact0;
  JointVector written1, exact1;
};

class DeviationBound {
 public:
  // For blocks held to `tolerance_mm`: the argument looks for the pose within a reach of 3
  // times it (at most 1.5 mm, so that a large tolerance does not reach past a small machine's
  // anchors) from the programmed chord, the same for every block, so that consecutive blocks
  // agree on which pose the machine is in. The reach is in the scaled pose norm: a hexapod's
  // joint error moves its attitude (scaled) about twice as far as its tool tip, and at 1.5 times
  // the tolerance the reach, not the deviation, ended the sphere's blocks.
  DeviationBound(const Machine& machine, double tolerance_mm);

  // False for models without a second-derivative bound: their deviation is sampled instead.
  bool available() const { return available_; }
  // The pose coordinates the model controls, and the scale of its angles (mm per rad).
  const std::vector<int>& axes() const { return axes_; }
  double angle_scale_mm() const { return angle_scale_mm_; }

  // An upper bound (mm) on the distance between the tool tip of the joint-linear block and the
  // programmed point at the same fraction of the piece [u0, u1] of `segment`, over the whole
  // block (so also on its distance to the path), in the coordinates the machine controls.
  // Infinity when none is found (a long piece over strongly bent kinematics, a singularity).
  double operator()(const motion::Segment& segment, double u0, double u1,
                    const BlockEnds& ends) const;

 private:
  const Machine& machine_;
  double reach_mm_;
  std::vector<int> axes_;  // the pose coordinates the model controls
  double angle_scale_mm_ = 100.0;
  bool available_ = false;
};

}  // namespace pkm::post
