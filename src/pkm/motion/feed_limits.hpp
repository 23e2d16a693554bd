// What bounds each move's feed and acceleration (internal to motion/): the joints' velocity and
// acceleration limits along it (feed_rule.hpp), the bend of an arc or a corner blend, a hanging
// effector's cable tensions, and the change of the joints' rates at a junction. Each lowered
// feed goes into the plan report with its numbers.
#pragma once

#include <optional>
#include <string>

#include "pkm/motion/plan_piece.hpp"
#include "pkm/motion/planner.hpp"
#include "pkm/motion/tension_limit.hpp"

namespace pkm::motion {

class FeedLimits {
 public:
  FeedLimits(const machine::Machine& machine, const PlanOptions& options, const std::string& file,
             PlanReport& report)
      : machine_(machine),
        options_(options),
        file_(file),
        report_(report),
        tension_(TensionLimit::of(machine.kinematics())) {}

  // `segment` (of `length` mm, > 0) as a piece at the fastest feed and acceleration the machine
  // allows along it.
  Piece piece(const Segment& segment, double length);

  // Everything that bounds a piece's feed and acceleration along it: its joints, its cables.
  void limit_by_machine(Piece& piece);

  // On a curve of radius r the tool's acceleration is the tangential one plus v^2/r across:
  // v^2/r <= a/2 and a tangential of 0.866 a keep the sum within a.
  static void limit_by_curvature(Piece& piece, double radius);

  // A joint whose rate along the path (dq/ds) differs across a junction would change its
  // velocity in one servo period: the junction speed keeps that change within what its
  // acceleration allows in a period. So does the effector's velocity, which a hanging effector's
  // cables feel (TensionLimit::junction_speed).
  void limit_junction(Piece& before, const Segment& after, double after_length);

  // Where a move leaves the reach, and on a cable machine how far its tensions go beyond their
  // limits along it.
  [[noreturn]] void leaves_reach(const Segment& segment) const;

 private:
  void limit_by_joints(Piece& piece);
  // The largest |dq/ds| (`slope`) and |d2q/ds2| (`curvature`) of every joint along the piece,
  // sampled every kJointSampleStepMm; an estimate widens the joint ranges with the samples.
  void joint_derivatives(const Piece& piece, kinematics::JointVector& slope,
                         kinematics::JointVector& curvature);
  void limit_by_tensions(Piece& piece);
  // The report's entry for a move whose feed `joint` (or cable) lowered to `speed`, with the
  // curve it is, if any.
  FeedLimit feed_limit(const Piece& piece, int joint, double speed, LimitCause cause) const;
  double programmed_feed(const Segment& segment) const {
    return segment.rapid ? machine_.cartesian().max_feed_mm_per_s() : segment.feed_mm_per_s;
  }

  const machine::Machine& machine_;
  const PlanOptions& options_;
  const std::string& file_;
  PlanReport& report_;
  // A cable machine whose effector has a mass: its cables' tensions bound the moves.
  std::optional<TensionLimit> tension_;
};

}  // namespace pkm::motion
