// An upper bound on how far the tool tip of a joint-linear block strays from the piece of the
// programmed path it stands for, from bounds on the inverse kinematics' second (and, for
// hexapods, third) derivatives over a ball (bounds/inverse_hessian.hpp), the joints at the
// piece's middle, and each joint's error weighed by how far it moves the tool (the argument is in
// docs/post.md, "The bound").
#pragma once

#include <vector>

#include "pkm/bounds/inverse_hessian.hpp"
#include "pkm/machine/machine.hpp"
#include "pkm/motion/segment.hpp"

namespace pkm::post {

// The ends of a joint-linear block: the joints as written (rounded) and as the inverse kinematics
// gives them at the programmed ends of the piece.
struct BlockEnds {
  kinematics::JointVector written0, exact0;
  kinematics::JointVector written1, exact1;
};

class DeviationBound {
 public:
  // For blocks held to `tolerance_mm`: the argument looks for the pose within a reach of 3
  // times it (at most 1.5 mm, so that a large tolerance does not reach past a small machine's
  // anchors) from the programmed chord, the same for every block, so that consecutive blocks
  // agree on which pose the machine is in. The reach is in the scaled pose norm: a hexapod's
  // joint error moves its attitude (scaled) about twice as far as its tool tip, and at 1.5 times
  // the tolerance the reach, not the deviation, ended the sphere's blocks.
  DeviationBound(const machine::Machine& machine, double tolerance_mm);

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
  const machine::Machine& machine_;
  double reach_mm_;
  std::vector<int> axes_;  // the pose coordinates the model controls
  double angle_scale_mm_ = 100.0;
  bool available_ = false;
};

}  // namespace pkm::post
