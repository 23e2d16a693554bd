#include "time_optimal_reference.hpp"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include "pkm/kinematics/cable_statics.hpp"
#include "pkm/kinematics/hanging_cables.hpp"

namespace pkm::test {
namespace {

using geometry::Vector6d;
using kinematics::JointVector;
using motion::PlannedPiece;
using motion::Segment;
using motion::SegmentKind;

constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr int kMinIntervals = 20;
// A step of an arc or blend turns at most this much (rad, 0.25 deg): each step's acceleration is
// chosen at its start, and the joints' and the tool tip's share of it move on with the turn (a
// 90 deg corner blend of 0.05 mm in 20 steps, 4.5 deg each, took its Z joint 9 % past its limit
// within a step).
constexpr double kMaxTurnPerStep = 0.25 * std::numbers::pi / 180.0;
// The joints' derivatives along the path: inverse kinematics at poses this far (mm; an angle
// counts kMmPerRad mm per rad) either side of the point, along the path's tangent and along its
// curvature vector. A pose at 1,000 mm carries 1e-13 mm of rounding: a second difference over
// 0.01 mm keeps 8 digits, and 0.01 mm is short against every mechanism's own lengths. The step
// does not shrink with the piece, so a blend of a micrometre is differentiated as well as a line.
constexpr double kJointStepMm = 0.01;
constexpr double kMmPerRad = 100.0;
// The path's own differences (its tangent and curvature vector, from Segment::at) are taken on a
// copy moved next to the origin, over a thousandth of the radius (at most half the piece): the
// truncation (h/r)^2/12 and the rounding eps (r/h)^2 are both below 1e-7 of the curvature.
constexpr double kPathStepPerRadius = 1e-3;
constexpr double kLineStepMm = 0.01;  // a line's angles may follow a great circle
// Bisections stop at this share of the value (or after kBisections halvings).
constexpr double kBisectionTolerance = 1e-10;
constexpr int kBisections = 80;
// Where the tensions are searched for a feasible acceleration when the bracket's middle fails.
constexpr int kTensionSeeds = 16;

struct Interval {
  double lo = -kInfinity, hi = kInfinity;
  bool empty() const { return !(lo <= hi); }
  void cut(double low, double high) {
    lo = std::max(lo, low);
    hi = std::min(hi, high);
  }
};

// The largest x in [0, high] where holds(x), for a predicate that holds on [0, x*] and fails
// above (every constraint here is convex in (u, x) and holds at rest).
template <class Holds>
double largest_holding(double high, const Holds& holds) {
  if (holds(high)) return high;
  double lo = 0.0, hi = high;
  for (int k = 0; k < kBisections && hi - lo > kBisectionTolerance * hi; ++k) {
    const double mid = 0.5 * (lo + hi);
    (holds(mid) ? lo : hi) = mid;
  }
  return lo;
}

struct Context {
  const machine::Machine& machine;
  const kinematics::HangingCables* cables = nullptr;  // with a mass only
  double max_feed = 0.0, max_acceleration = 0.0;      // mm/s, mm/s^2
  double period_s = 0.0;
};

// A piece's path as the reference differentiates it.
struct PiecePath {
  const PlannedPiece* piece = nullptr;
  Segment local;  // the piece moved by -offset: its coordinates stay as small as its radius
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  double length = 0.0, step = 0.0, feed = 0.0;
  double turn_rad = 0.0;  // an arc's or blend's sweep
  bool line = true;
};

PiecePath piece_path(const Context& c, const PlannedPiece& piece) {
  const Segment& segment = piece.segment;
  PiecePath path;
  path.piece = &piece;
  path.line = segment.kind == SegmentKind::line;
  path.offset = path.line ? Eigen::Vector3d(segment.start.head<3>()) : segment.centre;
  path.local = segment;
  path.local.start.head<3>() -= path.offset;
  path.local.end.head<3>() -= path.offset;
  path.local.centre -= path.offset;
  path.length = segment.length();
  if (!path.line) path.turn_rad = std::abs(segment.sweep_rad);
  double radius = segment.radius_mm;
  if (segment.kind == SegmentKind::arc) {
    radius =
        std::hypot(path.local.start[segment.first_axis], path.local.start[segment.second_axis]);
  }
  path.step = std::min(0.5 * path.length, path.line ? kLineStepMm : kPathStepPerRadius * radius);
  path.feed = segment.rapid ? c.max_feed : std::min(segment.feed_mm_per_s, c.max_feed);
  return path;
}

struct PathPoint {
  Vector6d pose, d1, d2;  // mm, rad; d/ds and d2/ds2 per mm of path
};

// The pose at `s` mm along the piece and its first two derivatives: the first by central
// differences (one-sided, second order, at the ends: Segment::at stops at the end), the second at
// the nearest point a central difference reaches (a line's position has none).
PathPoint path_at(const PiecePath& path, double s) {
  const auto local = [&](double at) { return path.local.at(at / path.length); };
  const double h = path.step, length = path.length;
  PathPoint p;
  const Vector6d here = local(s);
  if (s - h >= 0.0 && s + h <= length) {
    p.d1 = (local(s + h) - local(s - h)) / (2.0 * h);
  } else if (s + 2.0 * h <= length) {
    p.d1 = (-3.0 * here + 4.0 * local(s + h) - local(s + 2.0 * h)) / (2.0 * h);
  } else {
    p.d1 = (3.0 * here - 4.0 * local(s - h) + local(s - 2.0 * h)) / (2.0 * h);
  }
  const double c = std::clamp(s, h, length - h);
  p.d2 = (local(c + h) - 2.0 * local(c) + local(c - h)) / (h * h);
  if (path.line) p.d2.head<3>().setZero();
  p.pose = here;
  p.pose.head<3>() += path.offset;
  return p;
}

JointVector joints_at(const Context& c, const Vector6d& pose, int line) {
  JointVector q;
  const kinematics::Status status =
      c.machine.kinematics().inverse(geometry::Pose::from_vector(pose), q);
  if (!status.ok() || !q.allFinite()) {
    throw std::runtime_error("time-optimal reference: line " + std::to_string(line) +
                             ": no inverse kinematics at " +
                             c.machine.format_pose(geometry::Pose::from_vector(pose)));
  }
  return q;
}

double scaled_norm(const Vector6d& w) {
  return std::hypot(w.head<3>().norm(), kMmPerRad * w.tail<3>().norm());
}

// dq/ds = Dq[p'] and d2q/ds2 = Dq[p''] + D2q[p', p'] by differences of the inverse kinematics in
// pose space (the chain rule), at a fixed step however short the piece.
void joint_derivatives(const Context& c, const PathPoint& p, int line, JointVector& q1,
                       JointVector& q2) {
  const JointVector q = joints_at(c, p.pose, line);
  q1 = JointVector::Zero(q.size());
  q2 = JointVector::Zero(q.size());
  if (const double norm = scaled_norm(p.d1); norm > 0.0) {
    const double t = kJointStepMm / norm;
    const JointVector plus = joints_at(c, p.pose + t * p.d1, line);
    const JointVector minus = joints_at(c, p.pose - t * p.d1, line);
    q1 = (plus - minus) / (2.0 * t);
    q2 = (plus - 2.0 * q + minus) / (t * t);
  }
  if (const double norm = scaled_norm(p.d2); norm > 0.0) {
    const double t = kJointStepMm / norm;
    q2 +=
        (joints_at(c, p.pose + t * p.d2, line) - joints_at(c, p.pose - t * p.d2, line)) / (2.0 * t);
  }
}

// What limits the motion at one point: v^2 <= x_max (feed, joints' velocities), and for a given
// x = v^2 the path acceleration u the joints, the tool tip and the cables allow.
struct PointLimits {
  double x_max = kInfinity;
  JointVector q1, q2;  // per mm, per mm^2
  // The tool tip's acceleration is a u + b x (mm/s^2): its path's tangent and curvature vector.
  Eigen::Vector3d a = Eigen::Vector3d::UnitX(), b = Eigen::Vector3d::Zero();
  bool cables = false;
  geometry::Pose pose;
  // On a line the tensions depend on u alone: their interval, found once.
  bool tension_fixed = false;
  Interval tension_u;
};

bool cables_hold(const Context& c, const PointLimits& p, double u, double x) {
  const Eigen::Vector2d acceleration = p.a.head<2>() * u + p.b.head<2>() * x;
  kinematics::CableStatics out;
  if (!c.cables->statics(p.pose, acceleration, out).ok()) return false;
  for (int k = 0; k < 2; ++k) {
    if (!(out.lowest_N[k] >= c.cables->tension_min_N()) ||
        !(out.highest_N[k] <= c.cables->tension_max_N())) {
      return false;
    }
  }
  return true;
}

// The part of `bracket` (finite) where the cables hold at x: a feasible seed (rest, the middle,
// then evenly across), then bisection outwards to either end. The feasible accelerations along a
// line through the acceleration plane form an interval (the tensions are m (g - a) resolved
// onto the cables).
Interval tension_interval(const Context& c, const PointLimits& p, double x, Interval bracket) {
  const auto holds = [&](double u) { return cables_hold(c, p, u, x); };
  double seed = std::clamp(0.0, bracket.lo, bracket.hi);
  for (int k = -1; !holds(seed); ++k) {  // k = -1: the middle; then lo + k/n of the bracket
    if (k > kTensionSeeds) return {kInfinity, -kInfinity};
    seed = k < 0 ? 0.5 * (bracket.lo + bracket.hi)
                 : bracket.lo + (bracket.hi - bracket.lo) * k / kTensionSeeds;
  }
  const auto edge = [&](double inside, double outside) {
    if (holds(outside)) return outside;
    const double scale = std::abs(outside - inside);
    for (int k = 0; k < kBisections && std::abs(outside - inside) > kBisectionTolerance * scale;
         ++k) {
      const double mid = 0.5 * (inside + outside);
      (holds(mid) ? inside : outside) = mid;
    }
    return inside;
  };
  return {edge(seed, bracket.lo), edge(seed, bracket.hi)};
}

// The path accelerations u (mm/s^2) the point allows at x = v^2: each joint's
// |q1 u + q2 x| <= max_acceleration and the tool tip's |a u + b x| <= A exactly, the tensions by
// bisection.
Interval accelerations(const Context& c, const PointLimits& p, double x) {
  Interval u;
  const std::vector<machine::JointSpec>& joints = c.machine.joints();
  for (int j = 0; j < p.q1.size(); ++j) {
    const double limit = joints[static_cast<std::size_t>(j)].max_acceleration;
    const double q1 = p.q1[j], q2 = p.q2[j];
    if (q1 != 0.0) {
      const double first = (-limit - q2 * x) / q1, second = (limit - q2 * x) / q1;
      u.cut(std::min(first, second), std::max(first, second));
    } else if (std::abs(q2) * x > limit) {
      return {kInfinity, -kInfinity};
    }
  }
  const double alpha = p.a.squaredNorm(), beta = p.a.dot(p.b) * x;
  const double gamma = p.b.squaredNorm() * x * x - c.max_acceleration * c.max_acceleration;
  const double discriminant = beta * beta - alpha * gamma;
  if (discriminant < 0.0) return {kInfinity, -kInfinity};
  u.cut((-beta - std::sqrt(discriminant)) / alpha, (-beta + std::sqrt(discriminant)) / alpha);
  if (u.empty() || !p.cables) return u;
  if (p.tension_fixed) {
    u.cut(p.tension_u.lo, p.tension_u.hi);
    return u;
  }
  return tension_interval(c, p, x, u);
}

PointLimits point_limits(const Context& c, const PiecePath& path, double s) {
  const PlannedPiece& piece = *path.piece;
  const PathPoint point = path_at(path, s);
  PointLimits p;
  joint_derivatives(c, point, piece.segment.line, p.q1, p.q2);
  p.x_max = path.feed * path.feed;
  for (int j = 0; j < p.q1.size(); ++j) {
    const double limit = c.machine.joints()[static_cast<std::size_t>(j)].max_velocity;
    if (p.q1[j] != 0.0) p.x_max = std::min(p.x_max, std::pow(limit / p.q1[j], 2));
  }
  Eigen::Vector3d a = point.d1.head<3>(), b = point.d2.head<3>();
  if (piece.segment.z_free) a.z() = b.z() = 0.0;
  if (a.norm() > 0.0) {  // else a move of the angles alone: |u| <= A along its own length
    p.a = a;
    p.b = b;
  }
  if (c.cables) {
    p.cables = true;
    p.pose = geometry::Pose::from_vector(point.pose);
    if (p.b.head<2>().isZero()) {
      const double widest = c.max_acceleration / p.a.norm();
      p.tension_u = tension_interval(c, p, 0.0, {-widest, widest});
      p.tension_fixed = true;
    }
  }
  return p;
}

// The highest x = v^2 the point allows: its x_max where some acceleration holds there.
double point_cap(const Context& c, const PointLimits& p, int line) {
  if (accelerations(c, p, 0.0).empty()) {
    throw std::runtime_error("time-optimal reference: line " + std::to_string(line) +
                             ": no acceleration keeps the limits at rest");
  }
  return largest_holding(p.x_max, [&](double x) { return !accelerations(c, p, x).empty(); });
}

// A junction passed without stopping: joint j's rate along the path jumps by d, and the samples
// change its velocity by v d within one period.
double junction_cap(const Context& c, const PointLimits& before, const PointLimits& after) {
  double cap = kInfinity;
  for (int j = 0; j < before.q1.size(); ++j) {
    const double jump = std::abs(after.q1[j] - before.q1[j]);
    const double limit = c.machine.joints()[static_cast<std::size_t>(j)].max_acceleration;
    if (jump > 0.0) cap = std::min(cap, std::pow(limit * c.period_s / jump, 2));
  }
  return cap;
}

// A grid point: its limits for the step that leaves it, the highest x there (with a junction's
// bound), the step (mm) and the highest x inside it (the larger of its ends' own).
struct Node {
  PointLimits limits;
  double cap = 0.0, step = 0.0, inner_cap = 0.0;
  std::size_t piece = 0;
  double s = 0.0;  // mm along its piece
};

// The grid of pieces [first, last], the machine at rest before the first and after the last.
std::vector<Node> run_grid(const Context& c, const std::vector<PlannedPiece>& pieces,
                           std::size_t first, std::size_t last, double grid_step_mm) {
  std::vector<Node> nodes;
  bool joined = false;  // a piece before this one in the run, whose end is `end`
  PointLimits end;
  double end_cap = 0.0;
  for (std::size_t k = first; k <= last; ++k) {
    const PiecePath path = piece_path(c, pieces[k]);
    if (!(path.length > 0.0)) continue;
    const int line = pieces[k].segment.line;
    const int intervals =
        std::max({kMinIntervals, static_cast<int>(std::ceil(path.length / grid_step_mm)),
                  static_cast<int>(std::ceil(path.turn_rad / kMaxTurnPerStep))});
    const double step = path.length / intervals;
    PointLimits here = point_limits(c, path, 0.0);
    double here_cap = point_cap(c, here, line);
    for (int i = 0; i < intervals; ++i) {
      PointLimits next = point_limits(c, path, i + 1 < intervals ? (i + 1) * step : path.length);
      const double next_cap = point_cap(c, next, line);
      double cap = here_cap;
      if (i == 0 && joined) cap = std::min({cap, end_cap, junction_cap(c, end, here)});
      nodes.push_back(Node{std::move(here), cap, step, std::max(here_cap, next_cap), k, i * step});
      here = std::move(next);
      here_cap = next_cap;
    }
    end = std::move(here);
    end_cap = here_cap;
    joined = true;
  }
  if (!nodes.empty()) nodes.push_back(Node{end, 0.0, 0.0, 0.0, nodes.back().piece, 0.0});  // rest
  return nodes;
}

// The least time over a step of `step` mm from x0 to x1 (v^2) with the path acceleration within
// `u` (the step's start node's, at x0): accelerating, cruising at most at `cap`, braking. The
// passes' constant acceleration over the step would charge a step in which the speed reaches its
// cap as if it took the whole step to get there: up to step / v too much, 5 % of a millimetre's
// piece at 3 mm/s and 0.05 mm; this charges what a machine held to the node's limits needs.
double step_time(double step, double x0, double x1, const Interval& u, double cap) {
  if (!(u.hi > 0.0) || !(u.lo < 0.0)) return 2.0 * step / (std::sqrt(x0) + std::sqrt(x1));
  const double up = 0.5 / u.hi, down = -0.5 / u.lo;  // mm per unit of x, accelerating, braking
  double peak = (step + up * x0 + down * x1) / (up + down);
  double cruise = 0.0;
  if (peak > cap) {
    peak = std::max({cap, x0, x1});
    cruise = std::max(0.0, step - up * (peak - x0) - down * (peak - x1));
  }
  const double v = std::sqrt(peak);
  return (v - std::sqrt(x0)) / u.hi - (v - std::sqrt(x1)) / u.lo +
         (cruise > 0.0 ? cruise / v : 0.0);
}

// The reachability passes over one run from rest to rest; each step's time to its piece.
void solve_run(const Context& c, const std::vector<Node>& nodes, ReferenceResult& result,
               bool keep_profile) {
  if (nodes.empty()) return;
  const std::size_t n = nodes.size();
  // Backward: the largest x at each node from which the limits let the machine brake to within
  // the next node's bound.
  std::vector<double> bound(n, 0.0);
  for (std::size_t i = n - 1; i-- > 0;) {
    const Node& node = nodes[i];
    const double next = bound[i + 1], twice = 2.0 * node.step;
    bound[i] = largest_holding(node.cap, [&](double x) {
      Interval u = accelerations(c, node.limits, x);
      u.cut(-x / twice, (next - x) / twice);
      return !u.empty();
    });
  }
  // Forward: from rest, the largest acceleration each node allows within the next bound.
  double x = 0.0;
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const Node& node = nodes[i];
    const Interval u = accelerations(c, node.limits, x);
    const double next = std::clamp(x + 2.0 * node.step * u.hi, 0.0, bound[i + 1]);
    result.piece_durations_s[node.piece] += step_time(node.step, x, next, u, node.inner_cap);
    if (keep_profile) {
      result.profile.push_back({node.piece, node.s, node.step, std::sqrt(x), std::sqrt(next)});
    }
    x = next;
  }
}

}  // namespace

ReferenceResult solve_reference(const machine::Machine& machine,
                                const std::vector<PlannedPiece>& pieces, double period_s,
                                double grid_step_mm, bool keep_profile) {
  if (!(period_s > 0.0) || !(grid_step_mm > 0.0)) {
    throw std::invalid_argument("time-optimal reference: the period and the grid step must be > 0");
  }
  Context c{machine};
  const kinematics::HangingCables* cables = machine.kinematics().hanging_cables();
  if (cables && cables->effector_mass_kg() > 0.0) c.cables = cables;
  c.max_feed = machine.cartesian().max_feed_mm_per_s();
  c.max_acceleration = machine.cartesian().max_acceleration_mm_per_s2;
  c.period_s = period_s;
  ReferenceResult result;
  result.piece_durations_s.assign(pieces.size(), 0.0);
  std::size_t first = 0;
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    if (!pieces[k].stop_after && k + 1 < pieces.size()) continue;
    const std::vector<Node> nodes = run_grid(c, pieces, first, k, grid_step_mm);
    result.grid_points += static_cast<long>(nodes.size());
    solve_run(c, nodes, result, keep_profile);
    first = k + 1;
  }
  for (const double t : result.piece_durations_s) result.duration_s += t;
  return result;
}

PlannedJob plan_pieces(const machine::Machine& machine, const std::filesystem::path& program,
                       motion::PlanOptions options) {
  struct Discard final : motion::SampleSink {
    void write(const motion::Sample&) override {}
  } discard;
  PlannedJob job;
  options.estimate_only = true;
  options.on_piece = [&job](const PlannedPiece& piece) {
    job.pieces.push_back(piece);
    job.motion_time_s += piece.duration_s;
  };
  const std::clock_t start = std::clock();
  job.report = motion::plan_program(machine, program, {}, options, discard);
  job.cpu_s = static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC;
  return job;
}

}  // namespace pkm::test
