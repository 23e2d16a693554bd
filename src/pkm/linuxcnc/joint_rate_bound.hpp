// How fast the tool may move so that no joint passes its velocity or acceleration limit anywhere
// in a box of poses: upper bounds on |d joint / d pose| and on the inverse kinematics' Hessian
// over the box (cells, each bounded from its centre plus the Hessian bound of post's deviation
// argument times the cell's radius), and the per-axis Cartesian limits that follow (the
// [TRAJ]/[AXIS] limits of an exported LinuxCNC configuration). docs/linuxcnc.md has the argument.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "pkm/machine/machine.hpp"

namespace pkm::linuxcnc {

// The poses the bound covers: a box over the machine's controlled coordinates (mm, rad).
struct EnvelopeBox {
  Dof axes;
  Vector6d min = Vector6d::Zero();
  Vector6d max = Vector6d::Zero();
  Vector6d from_file = Vector6d::Zero();  // 1 where the [cartesian] min/max gave the side
};

// The machine file's work envelope where it gives one, the reachable extent along lines through
// home (reach_box) where it does not. Throws std::runtime_error, naming the axis, when the reach
// is not finite (a kilometre or more) or the box is empty.
EnvelopeBox work_envelope(const Machine& machine);

struct JointRateOptions {
  double relative_slack = 0.05;  // refine a cell while its bound passes the best sample by this
  long max_cells = 60000;        // cells evaluated at most (each: IK, Jacobian, Hessian bound)
  int max_depth = 40;            // halvings of a cell at most
};

// Over the box: for each joint i and pose coordinate j, `slope(i, j)` >= |d q_i / d x_j| (per mm,
// per rad), and `curvature[i]` >= the operator norm of q_i's Hessian in the scaled coordinates
// (angles times `angle_scale_mm`), so |v^T H_i v| <= curvature[i] |v|^2 with |v|^2 = sum of the
// squared linear rates plus (angle_scale_mm times each angular rate)^2.
struct JointRateBound {
  Eigen::MatrixXd slope;
  std::vector<double> curvature;
  double angle_scale_mm = 100.0;
  bool proven = false;     // false: sampled (models without a Hessian bound: formula machines)
  long cells = 0;          // cells evaluated
  long excluded = 0;       // cells proven outside the joint limits (the machine never goes there)
  double uncovered = 0.0;  // share of the box's volume left unbounded: cells at the edge of the
                           // geometric reach, whose centre the machine cannot reach
  // The same, cell by cell: one row per cell and joint (its bounds over that cell). The axis
  // limits hold every row, so a joint's rate is bounded at each place from that place's entries,
  // not from entries largest at different places.
  Eigen::MatrixXd cell_slope;  // rows x 6
  std::vector<int> cell_joint;
  std::vector<double> cell_curvature;
  bool reaches_unbounded = false;  // an unbounded cell's centre is a pose the machine takes
  Vector6d unbounded_pose = Vector6d::Zero();  // that centre (mm, rad)
  Eigen::MatrixXd sampled_slope;               // the largest |d q_i / d x_j| met at a cell centre
};

// The slope and curvature bounds hold over the box except the `uncovered` cells.
JointRateBound bound_joint_rates(const Machine& machine, const EnvelopeBox& box,
                                 const JointRateOptions& options = {});

// The box LinuxCNC gets as its axis limits: the requested one (the file's envelope, or the reach
// box), shrunk about home by the largest factor (found by bisection) over which the bound is
// finite everywhere and no joint's rate per unit of tool motion (summed over the axes, angles
// per angle_scale_mm) passes kMaxSlopeGrowth times its rate at home. Near the edge of a glide's or
// delta's reach a joint's rate grows without bound: giving up that edge is what keeps the speeds
// usable over the rest. Throws std::runtime_error when no box around home qualifies.
inline constexpr double kMaxSlopeGrowth = 3.0;
inline constexpr int kShrinkSteps = 8;
struct FittedEnvelope {
  EnvelopeBox box;
  double shrink = 1.0;  // 1: the requested box as it is
  JointRateBound bound;
};
FittedEnvelope fit_envelope(const Machine& machine, const EnvelopeBox& requested,
                            const JointRateOptions& options = {});

// Per pose coordinate (0..5): the largest rate (mm/s, rad/s) and acceleration (mm/s^2, rad/s^2)
// of each axis on its own, chosen so that with every axis within its own limit no joint passes
// its max_velocity or max_acceleration anywhere in the box.
struct AxisRateLimits {
  Vector6d velocity = Vector6d::Zero();
  Vector6d acceleration = Vector6d::Zero();
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
AxisRateLimits axis_rate_limits(const Machine& machine, const JointRateBound& bound, Dof moved);

// The speed (mm/s) `pkm plan` allows a straight move along the linear axis `axis` at `pose`:
// the machine's max_feed, lowered by the planner's feed rule (motion/feed_rule.hpp).
double plan_speed_along(const Machine& machine, const Pose& pose, int axis);

}  // namespace pkm::linuxcnc
