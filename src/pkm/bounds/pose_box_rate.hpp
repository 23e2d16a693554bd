// How fast each joint can change per unit of tool motion anywhere in a box of poses: upper bounds
// on |d joint / d pose| and on the inverse kinematics' Hessian over the box (cells, each bounded
// from its centre plus the Hessian bound of inverse_hessian.hpp times the cell's radius), the
// box itself (the machine file's envelope or the reach from home) and the largest box about home
// over which those rates stay usable. The LinuxCNC export (linuxcnc/joint_rate_bound.hpp) turns
// them into per-axis limits; docs/linuxcnc.md has the argument.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "pkm/machine/machine.hpp"

namespace pkm::bounds {

// The poses the bound covers, and where each side came from.
struct EnvelopeBox {
  machine::PoseBox box;     // over the machine's controlled coordinates (mm, rad)
  geometry::Dof from_file;  // the axes whose [cartesian] min and max both gave the sides
};

// The machine file's work envelope where it gives one, the reachable extent along lines through
// home (reach_box) where it does not. Throws std::runtime_error, naming the axis, when the reach
// is not finite (a kilometre or more) or the box is empty.
EnvelopeBox work_envelope(const machine::Machine& machine);

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
  geometry::Vector6d unbounded_pose = geometry::Vector6d::Zero();  // that centre (mm, rad)
  Eigen::MatrixXd sampled_slope;  // the largest |d q_i / d x_j| met at a cell centre
};

// The slope and curvature bounds hold over the box except the `uncovered` cells.
JointRateBound bound_joint_rates(const machine::Machine& machine, const machine::PoseBox& box,
                                 const JointRateOptions& options = {});

// The box limits built on the bound hold over (the LinuxCNC export's axis limits): the requested
// one (the file's envelope, or the reach box), shrunk about home by the largest factor (found by
// bisection) over which the bound is finite everywhere and no joint's rate per unit of tool motion
// (summed over the axes, angles per angle_scale_mm) passes kMaxSlopeGrowth times its rate at home.
// Near the edge of a glide's or delta's reach a joint's rate grows without bound: giving up that
// edge is what keeps the speeds usable over the rest. Throws std::runtime_error when no box around
// home qualifies.
inline constexpr double kMaxSlopeGrowth = 3.0;
inline constexpr int kShrinkSteps = 8;
struct FittedEnvelope {
  EnvelopeBox box;
  double shrink = 1.0;  // 1: the requested box as it is
  JointRateBound bound;
};
FittedEnvelope fit_envelope(const machine::Machine& machine, const EnvelopeBox& requested,
                            const JointRateOptions& options = {});

}  // namespace pkm::bounds
