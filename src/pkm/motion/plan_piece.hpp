// A move as the planner holds it for look-ahead (internal to motion/): its segment, the limits
// on its speed and acceleration, and the speeds look-ahead gives its ends.
#pragma once

#include "pkm/kinematics/kinematics.hpp"
#include "pkm/motion/path_grid.hpp"
#include "pkm/motion/planner_profiles.hpp"
#include "pkm/motion/segment.hpp"

namespace pkm::motion {

struct Piece {
  Segment segment;
  double length = 0.0;
  double max_speed = 0.0;
  double acceleration = 0.0;
  // The jerk-limited planner's jerk along the piece (mm/s^3, 0: none): the job's --jerk and
  // what each joint's max_jerk allows along it (FeedLimits::limit_by_joints).
  double jerk = 0.0;
  bool stop_after = false;
  double max_exit_speed = 1e300;  // where the joints' rates jump at the junction to the next
  double entry_speed = 0.0, exit_speed = 0.0;
  kinematics::JointVector joint_slope;  // largest |dq/ds| of each joint along the piece (per mm)
  // On an arc or a corner blend: its radius, and the speed and acceleration v^2/r may take
  // (limit_by_curvature); the line before a blend's corner.
  double curve_radius_mm = 0.0;
  double curve_speed_mm_per_s = 0.0;
  double curve_acceleration_mm_per_s2 = 0.0;
  int previous_line = 0;
  // The grid the time-optimal planner plans over (without a jerk limit).
  PathGrid grid;
  // Near a junction where a joint's rate dq/ds jumps, the sampled joint changes its velocity
  // within one servo period: the share of each joint's acceleration kept for that (empty: none)
  // within the distance (mm) of the piece's start or end where a sample can see the jump (a grid
  // interval that reaches into it keeps the share along all of it); so the tool's acceleration
  // for its change of direction; on a hanging effector whose direction changes there, the
  // tensions keep kTensionMoveShare of their headroom there.
  kinematics::JointVector entry_reserve, exit_reserve;
  double entry_tool_reserve = 0.0, exit_tool_reserve = 0.0;  // of the tool's acceleration
  double entry_reserve_mm = 0.0, exit_reserve_mm = 0.0;
  bool entry_tension_reserve = false, exit_tension_reserve = false;
};

// The unit direction of travel at fraction u of a segment (in XY where the machine does not move
// Z), from its own numbers: zero for a move of the angles alone.
inline Eigen::Vector3d heading(const Segment& segment, double u) {
  Eigen::Vector3d d = segment.velocity_at(u).head<3>();
  if (segment.z_free) d.z() = 0.0;
  const double n = d.norm();
  return n > 0.0 ? Eigen::Vector3d(d / n) : Eigen::Vector3d::Zero();
}

// How the piece changes speed: its acceleration and its jerk (mm/s^3, 0: none).
inline Ramp ramp_for(const Piece& piece) {
  return Ramp{piece.acceleration, piece.jerk};
}

}  // namespace pkm::motion
