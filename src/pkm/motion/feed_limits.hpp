// What bounds each move's feed and acceleration (internal to motion/): the joints' velocity and
// acceleration limits along it (feed_rule.hpp), the bend of an arc or a corner blend, a hanging
// effector's cable tensions, and the change of the joints' rates at a junction. Each lowered
// feed goes into the plan report with its numbers.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "pkm/motion/feed_rule.hpp"
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
        tension_(TensionLimit::of(machine.kinematics())),
        jerk_limited_(options.jerk_mm_per_s3 > 0.0 || has_joint_jerk(machine)) {}

  // `segment` (of `length` mm, > 0) as a piece at the fastest feed and acceleration the machine
  // allows along it.
  Piece piece(const Segment& segment, double length);

  // Everything that bounds a piece's feed and acceleration along it: its joints, its cables.
  void limit_by_machine(Piece& piece);

  // On a curve of radius r the tool's acceleration is the tangential one plus v^2/r across. The
  // jerk-limited planner keeps one tangential acceleration along the move: v^2/r <= a/2 and a
  // tangential of 0.866 a keep the sum within a. The time-optimal one shares the budget point
  // by point (time_optimal.hpp): this only records the curve for the report.
  void limit_by_curvature(Piece& piece, double radius) const;

  // The time-optimal planner's grid over the piece as it now is (path_grid.hpp).
  void build_grid(Piece& piece);
  // The report's entries for what lowers a piece's speed along its grid: once per piece, as it
  // is sampled (a blend may cut it, and its grid be built again, before).
  void report_grid_limits(const Piece& piece);

  // Plans without a jerk limit (no --jerk, no joint's max_jerk): on grids, time-optimally
  // (time_optimal.hpp).
  bool time_optimal() const { return !jerk_limited_; }
  // Whether any of the machine's joints has a max_jerk: its jobs plan jerk-limited.
  static bool has_joint_jerk(const machine::Machine& machine);
  const machine::Machine& machine() const { return machine_; }
  const TensionLimit* tension() const { return tension_ ? &*tension_ : nullptr; }

  // A joint whose rate along the path (dq/ds) differs across a junction would change its
  // velocity in one servo period (or once a chord, where chords come closer): the junction speed
  // keeps that change within a share of what its acceleration allows (20 %; time-optimally, no
  // more than the fastest passing needs), and the pieces keep that share near the junction. So
  // does the tool's change of direction (time-optimally), and the effector's velocity, which a
  // hanging effector's cables feel (TensionLimit::junction_speed).
  void limit_junction(Piece& before, Piece& after);
  double passing_speed(const Piece& before, const Piece& after) const;
  // A segment's programmed feed capped at max_feed (rapids: max_feed), mm/s.
  double feed_cap(const Segment& segment) const;

  // Where a joint has a max_jerk: the junction speed that keeps the jump of its velocity and
  // acceleration there (which the samples see within a period) within a share of it.
  void limit_junction_jerk(Piece& before, const Piece& after) const;

  // Where a move leaves the reach, and on a cable machine how far its tensions go beyond their
  // limits along it.
  [[noreturn]] void leaves_reach(const Segment& segment) const;

 private:
  void limit_by_joints(Piece& piece);
  // The joints at fraction u of `segment` into `q`, as a plan takes them: a pose out of reach or
  // joints that are no number stop the plan at the move's line; an estimate widens its ranges.
  void joints_along(const Segment& segment, double u, kinematics::JointVector& q);
  // The joints `step_mm` ahead of and behind `pose` along `direction` (pose per mm of path);
  // false where the inverse kinematics finds none.
  bool joints_either_side(const geometry::Vector6d& pose, const geometry::Vector6d& direction,
                          double step_mm, kinematics::JointVector& ahead,
                          kinematics::JointVector& behind) const;
  // The largest |dq/ds| (`slope`), |d2q/ds2| (`curvature`) and |d3q/ds3| (`third`) of every
  // joint along the piece, from differences of its values every kJointSampleStepMm (at least 8
  // steps); an estimate widens the joint ranges with them.
  void joint_derivatives(const Piece& piece, kinematics::JointVector& slope,
                         kinematics::JointVector& curvature, kinematics::JointVector& third);
  // The piece's jerk (and where a joint's jerk needs it, a lower speed or acceleration) that
  // keeps every joint with a max_jerk within it along the piece.
  void limit_jerk_by_joints(Piece& piece, const kinematics::JointVector& slope,
                            const kinematics::JointVector& curvature,
                            const kinematics::JointVector& third) const;
  // Each joint's dq/ds and d2q/ds2 where the piece starts or ends.
  void rates_at_end(const Piece& piece, bool at_end, kinematics::JointVector& rate,
                    kinematics::JointVector& bend) const;
  void limit_by_tensions(Piece& piece);
  // The report's entry for a move whose feed `rule`'s joint lowered, with the shares of its
  // limits the planner gives a move.
  void report_joint_limit(const Piece& piece, const JointFeedLimit& rule, double velocity_share,
                          double bend_share);
  // The grid's parts (grid_limits.cpp).
  void grid_joint_terms(PathGrid& grid) const;
  void fine_joint_terms(Piece& piece);
  void grid_curvature(Piece& piece) const;
  void grid_tension_rows(Piece& piece);
  void tangential_range(PathGrid& grid, int k, const geometry::Vector6d& pose,
                        const Eigen::Vector2d& tangent, double acceleration) const;
  void grid_force_rows(Piece& piece);
  TensionExcess row_cable(const Piece& piece, int point, int row) const;
  JointFeedLimit slowest_cruise(const Piece& piece, int& tension_row, int& tension_point) const;
  struct TensionSlope {
    std::array<double, 2> lowest{}, highest{};  // N per mm/s^2, each cable
    double stray_N = 0.0;
  };
  TensionSlope tension_slope(const geometry::Pose& pose, const Eigen::Vector2d& direction,
                             double probe, const kinematics::CableStatics& rest, int line) const;
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
  // A cable machine whose effector has a mass: its cables' tensions bound the moves (a plotter's
  // two, or a cable robot's n through the forces they can exert).
  std::optional<TensionLimit> tension_;
  bool jerk_limited_ = false;  // --jerk, or a joint's max_jerk
  // Scratch of build_grid, kept to spare an allocation per piece.
  std::vector<kinematics::JointVector> joints_at_points_;
};

}  // namespace pkm::motion
