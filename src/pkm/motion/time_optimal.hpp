// The time-optimal speed along the pieces look-ahead holds (internal to motion/): the
// reachability passes of TOPP-RA (Pham & Pham 2018) over each piece's grid (path_grid.hpp). With
// u the path acceleration and x the speed squared at a point, every limit is a bound on u for a
// given x: each joint's acceleration q' u + q'' x, the tool's acceleration as one budget
// u^2 + (kappa x)^2 <= A^2, each cable's tension linear in u and x. An interval's u holds at both
// its ends (x grows by 2 ds u across it), so the limits hold along it and not only at the points.
// The backward pass gives each point the highest x from which the rest of the window can still
// brake in time; the forward pass takes the highest u each point allows within that bound.
#pragma once

#include <array>
#include <deque>
#include <vector>

#include "pkm/machine/machine.hpp"
#include "pkm/motion/plan_piece.hpp"
#include "pkm/motion/tension_limit.hpp"

namespace pkm::motion {

// The part of a joint's velocity and acceleration limits the grid may use: the rest covers what
// they do between its points (the curvature of q' v and of q' u + q'' x within an interval). The
// tool's acceleration needs none: its curvature is constant along a line, an arc or a blend.
inline constexpr double kGridLimitShare = 0.999;

// The admissible path accelerations at one speed: empty where low > high.
struct AccelerationRange {
  double low = -1e300, high = 1e300;
  bool empty() const { return !(low <= high); }
};

// A bound low <= along * u + across * x <= high.
// No initializers: IntervalLimits keeps room for many and fills only the ones it uses.
struct LinearBound {
  double along, across, low, high;
};

// The limits on u over one interval of a grid. Each limit is a bound on the point's derivatives
// (a joint's q' and q'', a tension's lines, the tool's rate and bend) times (u, x), and the
// derivatives vary between the interval's two points: a bound linear in them holds along the
// interval where it holds with both points' values, and one convex in (u, x) holds along a
// stretch of constant u where it holds at the stretch's two states. So: both points' bounds at
// a state (at_state), or over the whole interval from x, at x and at x + 2 ds u (at).
class IntervalLimits {
 public:
  IntervalLimits(const Piece& piece, int interval, const machine::Machine& machine);
  // The u admissible over the whole interval entered at speed squared x.
  AccelerationRange at(double speed_squared) const;
  // The u admissible anywhere in the interval at speed squared x.
  AccelerationRange at_state(double speed_squared) const;
  // The highest speed squared the tool's acceleration across the path admits at all.
  double curve_cap() const;
  double step_mm() const { return step_mm_; }

 private:
  // Whether the interval lies where a sample sees the junction at the piece's entry or exit.
  struct Reserved {
    bool entry = false, exit = false;
  };
  void add_point(const Piece& piece, int point, Reserved reserved, const machine::Machine& machine);
  // The bounds at state x into `range` (x grown by 2 ds u when `far`); how far x misses a bound
  // on x alone into `miss`.
  void bound(double x, bool far, AccelerationRange& range, double& miss) const;

  static constexpr int kMaxBounds = 2 * (kinematics::kMaxJoints + kMaxTensionRowsPerPoint + 1);
  std::array<LinearBound, kMaxBounds> bounds_;  // the first bound_count_
  int bound_count_ = 0;
  double step_mm_ = 0.0;
  double acceleration_ = 0.0;  // the tool's, mm/s^2
  // The tool's acceleration at a point, rate u + bend x (at the far state, (rate + 2 ds bend) u +
  // bend x). Its square is a u^2 + 2 b u x + c x^2 with a = |first|^2, b = first . second,
  // c = |second|^2: per point, at the state and at the far state.
  struct ToolForm {
    double a = 1.0, b = 0.0, c = 0.0;
    bool straight() const { return b == 0.0 && c == 0.0; }
  };
  std::array<ToolForm, 2> tool_{}, far_tool_{};
};

// Plans the pieces' speeds: the first entered at `entry_speed`, the machine at rest after the
// last; each grid gets its speed_squared, each piece its entry and exit speed. With `tension`
// (a hanging effector), the tensions the plan gives every point are then solved exactly; where
// one leaves its limits (the rows are lines through a balance that bends), that row is moved by
// the difference and the window planned again, up to kTensionRounds times.
void plan_time_optimal(std::deque<Piece>& pieces, double entry_speed,
                       const machine::Machine& machine, const TensionLimit* tension);
inline constexpr int kTensionRounds = 8;

// The timing of one planned piece: each interval in one or two phases of constant acceleration
// (two where the speed meets its bound inside the interval), and where the tool is at a time.
class GridTiming {
 public:
  // Fills the phases from `piece`'s planned grid; reuses its storage.
  void reset(const Piece& piece);
  double duration_s() const { return duration_s_; }
  // Distance along the piece (mm) `t` seconds into it; `t` must not decrease between calls.
  double distance(double t);

 private:
  struct Phase {
    double start_mm = 0.0, start_s = 0.0;
    double speed = 0.0, acceleration = 0.0;  // at its start: mm/s, mm/s^2
  };
  void add_phase(double start_mm, double length_mm, double from_squared, double to_squared);

  std::vector<Phase> phases_;
  std::size_t cursor_ = 0;
  double duration_s_ = 0.0, length_mm_ = 0.0;
};

}  // namespace pkm::motion
