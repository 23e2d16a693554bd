#include "pkm/view/machine_drawing.hpp"

#include <cmath>

#include "pkm/kinematics/hanging_cables.hpp"

namespace pkm::view {

namespace {

// The work envelope's box over the coordinates it bounds (a planar machine's rectangle at z 0).
void add_envelope(std::vector<Segment>& out, const machine::Machine& machine) {
  const machine::CartesianLimits& limits = machine.cartesian();
  Eigen::Vector3d low, high;
  for (int axis = 0; axis < 3; ++axis) {
    low[axis] = limits.envelope_min[axis];
    high[axis] = limits.envelope_max[axis];
    if (!std::isfinite(low[axis]) || !std::isfinite(high[axis])) low[axis] = high[axis] = 0.0;
  }
  if (low.x() == high.x() || low.y() == high.y()) return;
  for (double z : {low.z(), high.z()}) {
    kinematics::sketch_loop(out, Part::envelope,
                            {{low.x(), low.y(), z},
                             {high.x(), low.y(), z},
                             {high.x(), high.y(), z},
                             {low.x(), high.y(), z}});
    if (low.z() == high.z()) return;
  }
  for (double x : {low.x(), high.x()}) {
    for (double y : {low.y(), high.y()}) {
      out.push_back({Part::envelope, {x, y, low.z()}, {x, y, high.z()}});
    }
  }
}

}  // namespace

bool drawn_planar(const machine::Machine& machine) {
  const geometry::Dof dof = machine.kinematics().dof();
  return machine.kinematics().hanging_cables() != nullptr ||
         (!dof.controls(2) && !dof.any_rotation());
}

std::vector<Segment> fixed_parts(const machine::Machine& machine) {
  std::vector<Segment> out;
  if (const kinematics::MechanismSketch* sketch = machine.kinematics().sketch()) {
    std::vector<kinematics::JointTravel> travel;
    for (const machine::JointSpec& joint : machine.joints())
      travel.push_back({joint.min, joint.max});
    sketch->fixed_parts(travel, out);
  }
  add_envelope(out, machine);
  return out;
}

std::vector<Segment> moving_parts(const machine::Machine& machine, const geometry::Pose& pose,
                                  const kinematics::JointVector& joints) {
  std::vector<Segment> out;
  if (const kinematics::MechanismSketch* sketch = machine.kinematics().sketch()) {
    sketch->moving_parts(pose, joints, out);
  }
  return out;
}

}  // namespace pkm::view
