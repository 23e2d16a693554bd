// The planner's rule for the feed the joints allow along a path, written once: `pkm plan` applies
// it to the derivatives it samples along every move (feed_limits.cpp), the LinuxCNC export to a
// straight move at a pose (linuxcnc/joint_rate_bound.cpp's plan_speed_along).
#pragma once

#include <vector>

#include "pkm/machine/machine.hpp"
#include "pkm/motion/planner.hpp"

namespace pkm::motion {

// The part of a joint's max_velocity a move may use: the rest covers the sampling of its rate.
inline constexpr double kJointVelocityMargin = 0.99;
// Share of a joint's acceleration limit the moves may use; the rest absorbs the change of its
// rate at junctions passed without stopping, which happens within one servo period.
inline constexpr double kMoveAccelerationShare = 0.8;
// The planner samples the joints along a move this often (mm of path).
inline constexpr double kJointSampleStepMm = 0.5;

struct JointFeedLimit {
  double speed_mm_per_s = 0.0;
  int joint = -1;  // the joint that lowered the speed, or -1 when none did
  JointBound bound = JointBound::velocity;
  double derivative = 0.0;  // that joint's |q'| (velocity) or |q''| (acceleration) there
};

// The share of a joint's acceleration a bend may take in the jerk-limited planner, whose ramps
// keep one acceleration along each move: half of the moves' share, the rest for the ramps.
inline constexpr double kJerkBendShare = 0.5 * kMoveAccelerationShare;

// With q(s) a joint along the path, `slope` bounding |q'| (per mm) and `curvature` bounding |q''|
// (per mm^2) over it: the highest speed up to `speed` (mm/s) at which every joint's rate q' v
// stays within `velocity_share` of its max_velocity and its q'' v^2 within `bend_share` of its
// max_acceleration; the joint that bound last, and how. The jerk-limited planner's shares are
// the defaults (the time-optimal one's are kGridLimitShare for both: time_optimal.hpp).
JointFeedLimit joint_feed_limit(const std::vector<machine::JointSpec>& joints,
                                const kinematics::JointVector& slope,
                                const kinematics::JointVector& curvature, double speed,
                                double velocity_share = kJointVelocityMargin,
                                double bend_share = kJerkBendShare);

}  // namespace pkm::motion
