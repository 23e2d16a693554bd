// Maps over the plane z = home's z (the plane itself for a planar machine), at the middle of the
// orientation range: dexterity (the Jacobian's inverse condition number, angle columns scaled by
// the machine's characteristic length) and the worst joint speed per unit tool speed.
#pragma once

#include <vector>

#include "pkm/workspace/workspace.hpp"

namespace pkm::workspace {

// Smallest over largest singular value of d joints / d pose over the controlled coordinates,
// angle columns divided by `length_mm` (mm per rad); 0 where singular.
double dexterity(const kinematics::JointJacobian& jacobian, geometry::Dof dof, double length_mm);
// The largest |d joint / d position| over the joints of the mechanism and every tool direction
// (mm per mm, or deg per mm for a rotary joint): the joint speed a tool speed of 1 asks for.
double joint_speed_per_tool_speed(const machine::Machine& machine,
                                  const kinematics::JointJacobian& jacobian);
// The characteristic length of the dexterity map (mm): half of post's pose angle scale, the
// farthest platform point from the tool tip (100 mm for models without a platform).
double characteristic_length_mm(const kinematics::Kinematics& model);

// "dexterity" and "joint_speed_per_tool_speed", about `points` along the extent's longer side,
// NaN where Machine::inverse refuses the point.
std::vector<PlaneMap> plane_maps(const machine::Machine& machine, const Workspace& ws, int points);

}  // namespace pkm::workspace
