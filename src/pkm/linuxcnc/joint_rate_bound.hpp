// The per-axis Cartesian limits of an exported LinuxCNC configuration ([TRAJ]/[AXIS]): each
// joint's velocity and acceleration budget split between the axes over the cells of the pose-box
// joint-rate bound (bounds/pose_box_rate.hpp), less the planner's overshoot LinuxCNC was measured
// to take, and the speed `pkm plan` allows along an axis. docs/linuxcnc.md has the argument.
#pragma once

#include <vector>

#include "pkm/bounds/pose_box_rate.hpp"
#include "pkm/machine/machine.hpp"

namespace pkm::linuxcnc {

// Per pose coordinate (0..5): the largest rate (mm/s, rad/s) and acceleration (mm/s^2, rad/s^2)
// of each axis on its own, chosen so that with every axis within its own limit no joint passes
// its max_velocity or max_acceleration anywhere in the box.
struct AxisRateLimits {
  geometry::Vector6d velocity = geometry::Vector6d::Zero();
  geometry::Vector6d acceleration = geometry::Vector6d::Zero();
  double linear_velocity = 0.0;        // the tool's speed cap, mm/s ([TRAJ] MAX_LINEAR_VELOCITY)
  double linear_acceleration = 0.0;    // mm/s^2
  std::vector<int> velocity_limiting;  // per axis: the joint that set its velocity, -1: none
  std::vector<int> acceleration_limiting;  // per axis: the joint that set its acceleration
};

// How far LinuxCNC 2.9's planner takes an axis past its [AXIS_x] MAX_ACCELERATION, measured
// headless with the exported configurations (tests/linuxcnc/run-exported; docs/linuxcnc.md,
// "Tested with the real controller"): a parabolic blend, which LinuxCNC uses where it cannot blend
// with an arc (any move of A, B or C), starts the next move at its full acceleration while the
// move before still slows at half of its own: 1.5 times MAX_ACCELERATION (450 deg/s^2 against 300
// on the 5-axis table's C). The exported accelerations are the bound's divided by it.
inline constexpr double kPlannerAccelerationOvershoot = 1.5;

// The split of each joint's budget between the axes (docs/linuxcnc.md): every axis gets the same
// share of what it could have alone (every other axis still); all grow together until a joint's
// budget over some cell is spent, the axes that joint moves stop there, the others go on
// (progressive filling). Linear axes stop at the machine's max_feed and max_acceleration. Before
// the accelerations, the speeds are lowered (all together) until the Hessian term takes at most
// half of every joint's acceleration limit. `moved` says which coordinates LinuxCNC moves (the
// controlled ones, and Z on a plotter): those no joint follows take the machine's limits. The
// accelerations returned are for LinuxCNC: the split's divided by the planner's overshoot (above).
AxisRateLimits axis_rate_limits(const machine::Machine& machine,
                                const bounds::JointRateBound& bound, geometry::Dof moved);

// The speed (mm/s) `pkm plan` allows a straight move along the linear axis `axis` at `pose`:
// the machine's max_feed, lowered by the planner's feed rule (motion/feed_rule.hpp).
double plan_speed_along(const machine::Machine& machine, const geometry::Pose& pose, int axis);

}  // namespace pkm::linuxcnc
