// The per-pose constraints a workspace cell is judged by, each bounded over a whole cell of
// poses: g(pose) >= 0 where the machine may stand, and an interval [low, high] that holds g for
// every pose of the cell. A cell is proven inside when every constraint's low is positive,
// proven outside when one constraint's high is negative (docs/workspace.md, "What a cell's
// answer means"). New per-pose limits (joint angles, leg interference, ...) join by adding a
// PoseConstraint that bounds their margin over a cell.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "pkm/machine/machine.hpp"

namespace pkm::workspace {

// An axis-aligned box of poses: every coordinate within centre +- half (mm, rad). Coordinates
// the model does not control have half = 0.
struct PoseCell {
  geometry::Vector6d centre = geometry::Vector6d::Zero();
  geometry::Vector6d half = geometry::Vector6d::Zero();
};

// Bounds on one constraint's value over a cell; infinite where nothing is known.
struct Margin {
  double low = -INFINITY;
  double high = INFINITY;
};

class PoseConstraint {
 public:
  virtual ~PoseConstraint() = default;
  virtual int count() const = 0;
  // Bounds on each of the count() values over every pose of `cell`. Values whose bit is set in
  // `settled` were proven over a cell holding this one and may be left as they are.
  virtual void bound(const PoseCell& cell, std::span<Margin> margins,
                     std::uint64_t settled = 0) const = 0;
  // What a violated value `index` means, as Machine::inverse would say it.
  virtual kinematics::Status failure(int index) const = 0;
  // False where the bound comes from samples of the cell rather than a proof.
  virtual bool proven() const { return true; }
  // True when the bound is as tight over the cell's orientation box as at one orientation (it
  // searches the box itself, or does not depend on orientation): the cell's orientation box need
  // not be split for it.
  virtual bool covers_orientation() const { return false; }
  // True when g = 0 is allowed (a joint at its limit, a coordinate on the envelope) and the
  // bound is exact arithmetic on the cell's corners: low >= 0 then proves the cell.
  virtual bool closed() const { return false; }
};

// Every constraint Machine::inverse applies, for this machine: the work envelope (exact), the
// joint limits (the joints at the centre, the Jacobian's linear part and a second-derivative
// bound from bounds::inverse_hessian_bounds), the model's reach and assembly mode where this file
// has a bound for them, the joint angles and leg clearances of max_joint_angle and leg_diameter
// (their value at the cell's centre +- bounds::mechanism_rate times the cell's scaled radius), and
// for what is not covered (models without derivative bounds, cable machines that tilt, sag or
// weigh) a sampled check of Machine::inverse at the cell's centre
// and corners (proven() false). The machine must outlive the constraints.
std::vector<std::unique_ptr<PoseConstraint>> machine_constraints(const machine::Machine& machine);

}  // namespace pkm::workspace
