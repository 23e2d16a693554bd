#include "pkm/motion/time_optimal.hpp"

#include <algorithm>
#include <cmath>

namespace pkm::motion {

namespace {

// The interval of u with u^2 a + u b + c <= 0 (a > 0) intersected into `range`. Where there is
// none, a range whose low passes its high by sqrt(-discriminant) / a: empty, by how much, so that
// the searches below see how far a speed is from admissible.
void within_quadratic(double a, double b, double c, AccelerationRange& range) {
  const double discriminant = b * b - 4.0 * a * c;
  const double vertex = -b / (2.0 * a);
  if (discriminant < 0.0) {
    const double gap = std::sqrt(-discriminant) / a;
    range.low = std::max(range.low, vertex + 0.5 * gap);
    range.high = std::min(range.high, vertex - 0.5 * gap);
    return;
  }
  const double root = std::sqrt(discriminant) / (2.0 * a);
  range.low = std::max(range.low, vertex - root);
  range.high = std::min(range.high, vertex + root);
}

// The highest x in [0, cap] from which some admissible u over the interval reaches at most
// `next_bound` at its end (x + 2 ds u <= next_bound) and not below rest. The x that qualify form
// an interval from 0 (the limits are convex in u and x): its end is the root of how far x misses,
// in speed squared (the hardest braking's excess over the bound, or a fall below rest; where no
// u is admissible, the range's emptiness times 2 ds on top), found by regula falsi (Illinois)
// from [0, cap], keeping the lower end admissible.
double highest_start(const IntervalLimits& limits, double cap, double next_bound) {
  const double twice_step = 2.0 * limits.step_mm();
  const auto missed_by = [&](double x) {
    const AccelerationRange range = limits.at(x);
    const double braking = x + twice_step * range.low - next_bound;
    if (range.empty()) return std::max(braking, 0.0) + twice_step * (range.low - range.high);
    return std::max(braking, -(x + twice_step * range.high));
  };
  // The tool's acceleration across a curve alone caps x (where its range shrinks to u = 0 with an
  // infinite slope, which a secant would approach slowly).
  cap = std::min(cap, limits.curve_cap());
  double high = cap, miss_high = missed_by(cap);
  if (miss_high <= 0.0) return cap;
  double low = 0.0, miss_low = missed_by(0.0);
  if (miss_low > 0.0) return 0.0;
  const double close = 1e-13 * std::max(1.0, next_bound);
  int kept = 0;  // +1: low moved last, -1: high moved last
  for (int i = 0; i < 100 && high - low > 1e-15 * high && miss_low < -close; ++i) {
    double x = low - miss_low * (high - low) / (miss_high - miss_low);
    if (!(x > low && x < high)) x = 0.5 * (low + high);
    const double miss = missed_by(x);
    if (miss <= 0.0) {
      low = x;
      miss_low = miss;
      if (kept == 1) miss_high *= 0.5;
      kept = 1;
    } else {
      high = x;
      miss_high = miss;
      if (kept == -1) miss_low *= 0.5;
      kept = -1;
    }
  }
  return low;
}

// The backward pass: each point's highest speed squared from which the window can still brake to
// rest at its end.
void bound_reachable(std::deque<Piece>& pieces, const machine::Machine& machine) {
  double bound_after = 0.0;  // at rest after the last piece
  for (std::size_t i = pieces.size(); i-- > 0;) {
    Piece& piece = pieces[i];
    PathGrid& grid = piece.grid;
    const int last = grid.intervals;
    double end_bound = piece.stop_after ? 0.0 : bound_after;
    if (piece.max_exit_speed < 1e150) {
      end_bound = std::min(end_bound, piece.max_exit_speed * piece.max_exit_speed);
    }
    grid.reachable_bound[static_cast<std::size_t>(last)] =
        std::min(end_bound, grid.speed_squared_cap[static_cast<std::size_t>(last)]);
    for (int k = last - 1; k >= 0; --k) {
      const IntervalLimits limits(piece, k, machine);
      const std::size_t at = static_cast<std::size_t>(k);
      grid.reachable_bound[at] =
          highest_start(limits, grid.speed_squared_cap[at], grid.reachable_bound[at + 1]);
    }
    bound_after = grid.reachable_bound[0];
  }
}

// The speed along one interval, as the least of three lines in s: value at its start and slope
// (dx/ds) of each.
struct IntervalLines {
  double start[3] = {0.0, 0.0, 0.0};
  double slope[3] = {0.0, 0.0, 0.0};
  double at(double s) const {
    return std::min({start[0] + slope[0] * s, start[1] + slope[1] * s, start[2] + slope[2] * s});
  }
  // Where two lines cross inside (0, step), in order: the least of them kinks at some of them.
  int crossings(double step, double (&where)[3]) const {
    int count = 0;
    for (int a = 0; a < 3; ++a) {
      for (int b = a + 1; b < 3; ++b) {
        if (slope[a] == slope[b]) continue;
        const double s = (start[b] - start[a]) / (slope[a] - slope[b]);
        if (s > 0.0 && s < step) where[count++] = s;
      }
    }
    for (int i = 1; i < count; ++i) {  // three at most: insertion
      for (int j = i; j > 0 && where[j] < where[j - 1]; --j) std::swap(where[j], where[j - 1]);
    }
    return count;
  }
  // The fastest the speed gets along the interval (the least of lines is concave: at a kink).
  double top(double step) const {
    double where[3];
    const int count = crossings(step, where);
    double highest = std::max(at(0.0), at(step));
    for (int i = 0; i < count; ++i) highest = std::max(highest, at(where[i]));
    return highest;
  }
};

// One interval of the forward pass from speed squared `x`. With the limits taken as they are at
// its ends, the fastest speed along it is the least of three lines in s: accelerating from x as
// hard as they allow, the cap between the ends' caps, and braking as hard as they allow into the
// bound at its end. The acceleration and the braking hold at both ends of their stretch, at either
// point's derivatives (IntervalLimits::at_state): at x or the bound, and at the top, where the
// speed turns from one to the other (a bend's q'' x or the tool's kappa x tightens them there; a
// bound on q'' x that opposes q' u, as the braking lowers x, at the bound). Its kinks (at most two)
// are where the speed changes from accelerating to cruising or braking: kept, so that it does so
// where it would, not an interval early. Returns x at its end.
double advance(PathGrid& grid, int k, double x, const IntervalLimits& limits) {
  const std::size_t at = static_cast<std::size_t>(k);
  const double step = grid.step_mm;
  const double end_bound = grid.reachable_bound[at + 1];
  grid.split_mm[at] = {0.0, 0.0};
  const AccelerationRange range = limits.at(x);
  if (range.empty()) return std::max(0.0, std::min(end_bound, x));
  const double in_time = (end_bound - x) / (2.0 * step);  // x itself can still brake in time
  double accelerate = range.high;
  double brake = std::min(range.low, in_time);
  const double cap_start = grid.speed_squared_cap[at], cap_end = grid.speed_squared_cap[at + 1];
  IntervalLines lines;
  // The braking's own end state: the bound it brakes into.
  const AccelerationRange at_bound = limits.at_state(end_bound);
  if (!at_bound.empty()) brake = std::min(std::max(brake, at_bound.low), in_time);
  for (int round = 0; round < 3; ++round) {
    lines = IntervalLines{{x, cap_start, end_bound - 2.0 * brake * step},
                          {2.0 * accelerate, (cap_end - cap_start) / step, 2.0 * brake}};
    const AccelerationRange top = limits.at_state(lines.top(step));
    if (top.empty() || (top.high >= accelerate && top.low <= brake)) break;
    accelerate = std::min(accelerate, top.high);
    brake = std::min(std::max(brake, top.low), in_time);
  }
  double kinks[3];
  const int count = lines.crossings(step, kinks);
  int kept = 0;
  double before = 0.0;
  for (int i = 0; i < count && kept < 2; ++i) {
    const double after = i + 1 < count ? kinks[i + 1] : step;
    const double middle = lines.at(kinks[i]);
    const double straight = lines.at(before) + (lines.at(after) - lines.at(before)) *
                                                   (kinks[i] - before) / (after - before);
    if (std::abs(middle - straight) <= 1e-12 * std::max(1.0, std::abs(middle))) continue;
    grid.split_mm[at][static_cast<std::size_t>(kept)] = kinks[i];
    grid.split_speed_squared[at][static_cast<std::size_t>(kept)] = std::max(0.0, middle);
    ++kept;
    before = kinks[i];
  }
  return std::max(0.0, std::min(lines.at(step), end_bound));
}

void plan_forward(std::deque<Piece>& pieces, double entry_speed, const machine::Machine& machine);
bool tighten_tensions(Piece& piece, const TensionLimit& tension);

}  // namespace

IntervalLimits::IntervalLimits(const Piece& piece, int interval, const machine::Machine& machine)
    : step_mm_(piece.grid.step_mm), acceleration_(machine.cartesian().max_acceleration_mm_per_s2) {
  const PathGrid& grid = piece.grid;
  const auto form = [](const Eigen::Vector3d& first, const Eigen::Vector3d& second) {
    return ToolForm{first.squaredNorm(), first.dot(second), second.squaredNorm()};
  };
  for (std::size_t end = 0; end < 2; ++end) {
    const std::size_t point = static_cast<std::size_t>(interval) + end;
    tool_[end] = form(grid.tool_rate[point], grid.tool_bend[point]);
    far_tool_[end] =
        form(grid.tool_rate[point] + 2.0 * step_mm_ * grid.tool_bend[point], grid.tool_bend[point]);
  }
  // An interval that reaches into the stretch where a sample sees a junction's change keeps the
  // junction's reserve along all of it.
  Reserved reserved;
  reserved.entry = piece.entry_reserve_mm > 0.0 && grid.s_mm(interval) < piece.entry_reserve_mm;
  reserved.exit = piece.exit_reserve_mm > 0.0 &&
                  grid.s_mm(interval + 1) > grid.length_mm() - piece.exit_reserve_mm;
  double tool_reserve = 0.0;
  if (reserved.entry) tool_reserve = piece.entry_tool_reserve;
  if (reserved.exit) tool_reserve = std::max(tool_reserve, piece.exit_tool_reserve);
  acceleration_ *= 1.0 - tool_reserve;
  add_point(piece, interval, reserved, machine);
  add_point(piece, interval + 1, reserved, machine);
}

// The point's bounds on (u, x).
void IntervalLimits::add_point(const Piece& piece, int point, Reserved reserved,
                               const machine::Machine& machine) {
  const PathGrid& grid = piece.grid;
  const bool entry = reserved.entry, exit = reserved.exit;
  for (int j = 0; j < grid.joint_count; ++j) {
    double reserve = 0.0;
    if (entry && piece.entry_reserve.size() > j) reserve = piece.entry_reserve[j];
    if (exit && piece.exit_reserve.size() > j) reserve = std::max(reserve, piece.exit_reserve[j]);
    const double limit = kGridLimitShare * (1.0 - reserve) *
                         machine.joints()[static_cast<std::size_t>(j)].max_acceleration;
    bounds_[static_cast<std::size_t>(bound_count_++)] =
        LinearBound{grid.slope(point, j), grid.bend(point, j), -limit, limit};
  }
  if (const TensionRow* rows = grid.tensions(point)) {
    const bool turning =
        (entry && piece.entry_tension_reserve) || (exit && piece.exit_tension_reserve);
    const double share = turning ? kTensionMoveShare : 1.0;
    for (int r = 0; r < grid.rows_per_point; ++r) {
      const TensionRow& row = rows[r];
      bounds_[static_cast<std::size_t>(bound_count_++)] =
          LinearBound{row.along, row.across, share * (row.low_N - row.rest_N),
                      share * (row.high_N - row.rest_N)};
    }
    if (grid.exact_tension_rows) return;
    const std::array<double, 2>& along = grid.tangential_range[static_cast<std::size_t>(point)];
    bounds_[static_cast<std::size_t>(bound_count_++)] =
        LinearBound{1.0, 0.0, share * along[0], share * along[1]};
  }
}

double IntervalLimits::curve_cap() const {
  // a u^2 + 2 b x u + c x^2 <= A^2 has a u for x only while its discriminant, 4 x^2 (b^2 - a c) +
  // 4 a A^2, is not negative: x <= A sqrt(a / (a c - b^2)) (a c - b^2 = |first x second|^2).
  double cap = 1e300;
  for (const std::array<ToolForm, 2>* forms : {&tool_, &far_tool_}) {
    for (const ToolForm& tool : *forms) {
      const double cross = tool.a * tool.c - tool.b * tool.b;
      if (cross > 0.0) cap = std::min(cap, acceleration_ * std::sqrt(tool.a / cross));
    }
  }
  return cap;
}

void IntervalLimits::bound(double x, bool far, AccelerationRange& range, double& miss) const {
  const double shift = far ? 2.0 * step_mm_ : 0.0;
  for (int i = 0; i < bound_count_; ++i) {
    const LinearBound& b = bounds_[static_cast<std::size_t>(i)];
    const double along = b.along + shift * b.across;
    const double fixed = b.across * x;
    if (along > 0.0) {
      range.low = std::max(range.low, (b.low - fixed) / along);
      range.high = std::min(range.high, (b.high - fixed) / along);
    } else if (along < 0.0) {
      range.low = std::max(range.low, (b.high - fixed) / along);
      range.high = std::min(range.high, (b.low - fixed) / along);
    } else {  // a bound on x alone: missed by how far x is past it
      miss = std::max({miss, fixed - b.high, b.low - fixed});
    }
  }
  // The tool: |rate u + bend x| <= A (|u| <= A on a line, most of a job).
  const double a2 = acceleration_ * acceleration_;
  for (const ToolForm& tool : far ? far_tool_ : tool_) {
    if (tool.straight()) {
      const double most = acceleration_ / std::sqrt(tool.a);
      range.low = std::max(range.low, -most);
      range.high = std::min(range.high, most);
    } else {
      within_quadratic(tool.a, 2.0 * tool.b * x, tool.c * x * x - a2, range);
    }
  }
}

AccelerationRange IntervalLimits::at_state(double x) const {
  AccelerationRange range;
  double miss = 0.0;
  bound(x, false, range, miss);
  if (miss > 0.0) range.low = std::max(range.low, range.high + miss / step_mm_);
  return range;
}

AccelerationRange IntervalLimits::at(double x) const {
  AccelerationRange range;
  double miss = 0.0;
  bound(x, false, range, miss);
  bound(x, true, range, miss);
  if (miss > 0.0) range.low = std::max(range.low, range.high + miss / step_mm_);
  return range;
}

void plan_time_optimal(std::deque<Piece>& pieces, double entry_speed,
                       const machine::Machine& machine, const TensionLimit* tension) {
  for (int round = 0; round < kTensionRounds; ++round) {
    bound_reachable(pieces, machine);
    plan_forward(pieces, entry_speed, machine);
    if (tension == nullptr) return;
    bool moved = false;
    for (Piece& piece : pieces) moved = tighten_tensions(piece, *tension) || moved;
    if (!moved) return;
  }
}

namespace {

void plan_forward(std::deque<Piece>& pieces, double entry_speed, const machine::Machine& machine) {
  double x = entry_speed * entry_speed;
  for (Piece& piece : pieces) {
    PathGrid& grid = piece.grid;
    x = std::min(x, grid.reachable_bound[0]);
    grid.speed_squared[0] = x;
    for (int k = 0; k < grid.intervals; ++k) {
      x = advance(grid, k, x, IntervalLimits(piece, k, machine));
      grid.speed_squared[static_cast<std::size_t>(k) + 1] = x;
    }
    piece.entry_speed = std::sqrt(grid.speed_squared.front());
    piece.exit_speed = std::sqrt(grid.speed_squared.back());
  }
}

// The path accelerations of the phases that reach and leave point k of `grid`.
std::array<double, 2> accelerations_at(const PathGrid& grid, int k) {
  const auto phase = [&](int interval, bool first) {
    const std::size_t at = static_cast<std::size_t>(interval);
    double from_mm = 0.0, from_x = grid.speed_squared[at];
    double to_mm = grid.step_mm, to_x = grid.speed_squared[at + 1];
    const std::array<double, 2>& split = grid.split_mm[at];
    const std::array<double, 2>& split_x = grid.split_speed_squared[at];
    const int splits = split[1] > 0.0 ? 2 : split[0] > 0.0 ? 1 : 0;
    if (first && splits > 0) {
      to_mm = split[0];
      to_x = split_x[0];
    } else if (!first && splits > 0) {
      from_mm = split[static_cast<std::size_t>(splits - 1)];
      from_x = split_x[static_cast<std::size_t>(splits - 1)];
    }
    return (to_x - from_x) / (2.0 * (to_mm - from_mm));
  };
  const double arriving = k > 0 ? phase(k - 1, false) : phase(k, true);
  const double leaving = k < grid.intervals ? phase(k, true) : arriving;
  return {arriving, leaving};
}

// The exact tensions at every point of `piece` as planned; a row whose line let a tension pass its
// limit is moved by the difference (and a hair more). True when one moved.
bool tighten_tensions(Piece& piece, const TensionLimit& tension) {
  PathGrid& grid = piece.grid;
  if (grid.tension_rows.empty() || grid.exact_tension_rows) return false;
  bool moved = false;
  for (int k = 0; k <= grid.intervals; ++k) {
    const std::size_t at = static_cast<std::size_t>(k);
    const double x = grid.speed_squared[at];
    const geometry::Vector6d pose = piece.segment.at(static_cast<double>(k) / grid.intervals);
    for (const double u : accelerations_at(grid, k)) {
      const Eigen::Vector2d acceleration = grid.tangent_xy[at] * u + grid.curvature_xy[at] * x;
      const TensionExcess excess = tension.excess(pose, acceleration);
      if (!excess.outside || excess.cable < 0) continue;
      TensionRow& row =
          grid.tension_rows[at * kTensionRowsPerPoint + static_cast<std::size_t>(2 * excess.cable) +
                            (excess.slack ? 0u : 1u)];
      const double predicted = row.rest_N + row.along * u + row.across * x;
      const double hair = 1e-6 + 1e-3 * std::abs(predicted - excess.tension_N);
      if (excess.slack) {
        row.low_N += predicted - excess.tension_N + hair;
      } else {
        row.high_N -= excess.tension_N - predicted + hair;
      }
      moved = true;
    }
  }
  return moved;
}

}  // namespace

void GridTiming::add_phase(double start_mm, double length_mm, double from_squared,
                           double to_squared) {
  const double from = std::sqrt(from_squared), to = std::sqrt(to_squared);
  phases_.push_back(
      Phase{start_mm, duration_s_, from, (to_squared - from_squared) / (2.0 * length_mm)});
  duration_s_ += 2.0 * length_mm / (from + to);
}

void GridTiming::reset(const Piece& piece) {
  const PathGrid& grid = piece.grid;
  phases_.clear();
  cursor_ = 0;
  duration_s_ = 0.0;
  length_mm_ = piece.length;
  for (int k = 0; k < grid.intervals; ++k) {
    const std::size_t at = static_cast<std::size_t>(k);
    const double start = grid.s_mm(k);
    double from_mm = 0.0, from_x = grid.speed_squared[at];
    for (std::size_t i = 0; i < 2 && grid.split_mm[at][i] > 0.0; ++i) {
      add_phase(start + from_mm, grid.split_mm[at][i] - from_mm, from_x,
                grid.split_speed_squared[at][i]);
      from_mm = grid.split_mm[at][i];
      from_x = grid.split_speed_squared[at][i];
    }
    add_phase(start + from_mm, grid.step_mm - from_mm, from_x, grid.speed_squared[at + 1]);
  }
}

double GridTiming::distance(double t) {
  if (phases_.empty() || t <= 0.0) return 0.0;
  if (t >= duration_s_) return length_mm_;
  while (cursor_ + 1 < phases_.size() && phases_[cursor_ + 1].start_s <= t) ++cursor_;
  const Phase& phase = phases_[cursor_];
  const double into = t - phase.start_s;
  const double end_mm = cursor_ + 1 < phases_.size() ? phases_[cursor_ + 1].start_mm : length_mm_;
  return std::min(end_mm,
                  phase.start_mm + phase.speed * into + 0.5 * phase.acceleration * into * into);
}

}  // namespace pkm::motion
