// A piece's grid (internal to motion/): points equally spaced along the path, and at each what the
// time-optimal planner (time_optimal.hpp) needs to bound the speed and acceleration there: the
// highest speed the feed and the joints' velocities allow, the tool path's curvature, each
// joint's first and second derivative along the path, and on a hanging effector each cable's
// tension as a linear function of the effector's acceleration.
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

#include "pkm/kinematics/kinematics.hpp"

namespace pkm::motion {

// A cable's lowest or highest tension at a point, T0 + along * u + across * x with u the path
// acceleration (mm/s^2) and x the speed squared (mm^2/s^2): the effector's acceleration is the
// tangent times u plus the curvature vector times x. Within [low_N, high_N], the tension limits
// narrowed by how far the tension strays from that line over the accelerations a move can have.
struct TensionRow {
  double rest_N = 0.0;
  double along = 0.0;   // N per mm/s^2
  double across = 0.0;  // N per mm^2/s^2
  double low_N = 0.0, high_N = 0.0;
};

// The plotter's rows: two per cable, its lowest and its highest tension. n cables (a cable_robot)
// have a row per facet pair of the forces they can exert (cable_force_polytope.hpp): the force
// along the facet's normal, exactly linear in the acceleration, within the facet's two bounds.
inline constexpr int kTensionRowsPerPoint = 4;
inline constexpr int kMaxTensionRowsPerPoint =
    kinematics::kMaxJoints * (kinematics::kMaxJoints - 1) / 2;

struct PathGrid {
  bool ready = false;  // built for the piece's segment as it is now
  int intervals = 0;   // points 0..intervals
  double step_mm = 0.0;
  int joint_count = 0;
  std::vector<double> speed_squared_cap;  // (mm/s)^2: the feed, each joint's velocity
  std::vector<double> curvature_per_mm;   // of the tool tip's path, 0 on lines
  // The tool tip's d position / ds and d2 position / ds2 (x y z; z 0 where the machine does not
  // move Z): its acceleration is the first times u plus the second times x. Of unit length and
  // square to it on a line, an arc or a blend drawn evenly; not quite on an arc whose radius
  // drifts from start to end, which LinuxCNC accepts. A move of the angles alone has a unit
  // first and no second: its path acceleration is held to max_acceleration (per degree).
  std::vector<Eigen::Vector3d> tool_rate, tool_bend;
  // Per point and joint: dq/ds (per mm), then d2q/ds2 (per mm^2); mm or rad as the joint.
  std::vector<double> joint_derivatives;
  std::vector<TensionRow> tension_rows;  // rows_per_point per point, or none
  int rows_per_point = 0;
  // The rows are exact (n cables' facets): no tangential range bound, nothing to tighten.
  bool exact_tension_rows = false;
  // With tension rows: the path acceleration the tensions allow at each point at rest speed,
  // exactly (the rows are lines through the tensions, which bend at large accelerations), and
  // the row of the cable that sets each end (-1: the tool's acceleration does, not a cable).
  std::vector<std::array<double, 2>> tangential_range;
  std::vector<std::array<int, 2>> tangential_row;
  // With tension rows: the effector's acceleration per u (the tangent, x y) and per x (the
  // curvature vector, x y) at each point.
  std::vector<Eigen::Vector2d> tangent_xy, curvature_xy;
  // The planner's answer: the speed squared at each point, and the backward pass's bound.
  std::vector<double> speed_squared;
  std::vector<double> reachable_bound;
  // Per interval, up to two places (mm into it, 0: none) where the speed changes from
  // accelerating to cruising or braking inside it, and the speed squared there.
  std::vector<std::array<double, 2>> split_mm, split_speed_squared;

  double slope(int point, int joint) const {
    return joint_derivatives[static_cast<std::size_t>((point * joint_count + joint) * 2)];
  }
  double bend(int point, int joint) const {
    return joint_derivatives[static_cast<std::size_t>((point * joint_count + joint) * 2 + 1)];
  }
  const TensionRow* tensions(int point) const {
    return tension_rows.empty() ? nullptr
                                : &tension_rows[static_cast<std::size_t>(point * rows_per_point)];
  }
  double s_mm(int point) const { return point * step_mm; }
  double length_mm() const { return intervals * step_mm; }

  // `tension_rows_per_point`: 0 without tension rows.
  void resize(int interval_count, int joints, int tension_rows_per_point) {
    const bool with_tensions = tension_rows_per_point > 0;
    rows_per_point = tension_rows_per_point;
    exact_tension_rows = false;
    intervals = interval_count;
    joint_count = joints;
    const std::size_t points = static_cast<std::size_t>(interval_count) + 1;
    speed_squared_cap.assign(points, 0.0);
    curvature_per_mm.assign(points, 0.0);
    tool_rate.assign(points, Eigen::Vector3d::UnitX());
    tool_bend.assign(points, Eigen::Vector3d::Zero());
    joint_derivatives.assign(points * static_cast<std::size_t>(joints) * 2, 0.0);
    tension_rows.assign(points * static_cast<std::size_t>(tension_rows_per_point), TensionRow{});
    tangential_range.assign(with_tensions ? points : 0, {0.0, 0.0});
    tangential_row.assign(with_tensions ? points : 0, {-1, -1});
    tangent_xy.assign(with_tensions ? points : 0, Eigen::Vector2d::Zero());
    curvature_xy.assign(with_tensions ? points : 0, Eigen::Vector2d::Zero());
    speed_squared.assign(points, 0.0);
    reachable_bound.assign(points, 0.0);
    split_mm.assign(points - 1, {0.0, 0.0});
    split_speed_squared.assign(points - 1, {0.0, 0.0});
  }
};

}  // namespace pkm::motion
