// FeedLimits' grids: what the time-optimal planner needs at points along a piece (path_grid.hpp),
// and the report's entries for the limits that lower the piece's speed there.
#include <algorithm>
#include <cmath>

#include "pkm/motion/feed_limits.hpp"
#include "pkm/motion/feed_rule.hpp"
#include "pkm/motion/plan_sampling.hpp"
#include "pkm/motion/time_optimal.hpp"

namespace pkm::motion {

namespace {

// Grids finer than this (mm) take their joints' derivatives along the path's own tangent over
// this distance instead of from their points' differences (fine_joint_terms).
constexpr double kFineStepMm = 0.01;

// A curve's grid turns by at most this much per interval (rad): the limits are held at the
// points, and the direction of the tool's acceleration across a curve turns with it.
constexpr double kGridTurnRad = 0.05;

// Points on a piece's grid: one every kJointSampleStepMm and every kGridTurnRad of a curve, at
// least 4 intervals (the differences at its ends take three points) and at most 512.
int grid_intervals(const Segment& segment, double length_mm) {
  const double turn = segment.kind == SegmentKind::line ? 0.0 : std::abs(segment.sweep_rad);
  const double by_length = std::ceil(length_mm / kJointSampleStepMm);
  const double by_turn = std::ceil(turn / kGridTurnRad);
  return static_cast<int>(std::clamp(std::max(by_length, by_turn), 4.0, 512.0));
}

}  // namespace

void FeedLimits::build_grid(Piece& piece) {
  const Segment& segment = piece.segment;
  PathGrid& grid = piece.grid;
  const int intervals = grid_intervals(segment, piece.length);
  const int joint_count = static_cast<int>(machine_.joints().size());
  grid.resize(intervals, joint_count, tension_ ? tension_->rows_per_point() : 0);
  grid.step_mm = piece.length / intervals;
  joints_at_points_.resize(static_cast<std::size_t>(intervals) + 1);
  for (int k = 0; k <= intervals; ++k) {
    joints_along(segment, static_cast<double>(k) / intervals,
                 joints_at_points_[static_cast<std::size_t>(k)]);
  }
  grid_joint_terms(grid);
  if (grid.step_mm < kFineStepMm) fine_joint_terms(piece);
  grid_curvature(piece);
  const double feed_squared = piece.max_speed * piece.max_speed;
  for (int k = 0; k <= intervals; ++k) {
    // The tool's own speed is the path's times |d position / ds|.
    double cap = feed_squared / grid.tool_rate[static_cast<std::size_t>(k)].squaredNorm();
    for (int j = 0; j < joint_count; ++j) {
      const double slope = std::abs(grid.slope(k, j));
      const double velocity =
          kGridLimitShare * machine_.joints()[static_cast<std::size_t>(j)].max_velocity;
      if (slope * velocity > 0.0) cap = std::min(cap, (velocity / slope) * (velocity / slope));
    }
    grid.speed_squared_cap[static_cast<std::size_t>(k)] = cap;
  }
  if (tension_) grid_tension_rows(piece);
  grid.ready = true;
}

// dq/ds and d2q/ds2 at every point by differences of the joints there: central inside, of
// second order at the ends (a one-sided first difference would be off by half a step's bend).
void FeedLimits::grid_joint_terms(PathGrid& grid) const {
  const int n = grid.intervals;
  const double h = grid.step_mm;
  const auto q = [&](int k, int j) { return joints_at_points_[static_cast<std::size_t>(k)][j]; };
  for (int j = 0; j < grid.joint_count; ++j) {
    for (int k = 0; k <= n; ++k) {
      double slope = 0.0, bend = 0.0;
      const int c = std::clamp(k, 1, n - 1);
      bend = (q(c + 1, j) - 2.0 * q(c, j) + q(c - 1, j)) / (h * h);
      if (k == 0) {
        slope = (-3.0 * q(0, j) + 4.0 * q(1, j) - q(2, j)) / (2.0 * h);
      } else if (k == n) {
        slope = (3.0 * q(n, j) - 4.0 * q(n - 1, j) + q(n - 2, j)) / (2.0 * h);
      } else {
        slope = (q(k + 1, j) - q(k - 1, j)) / (2.0 * h);
      }
      const std::size_t at = static_cast<std::size_t>((k * grid.joint_count + j) * 2);
      grid.joint_derivatives[at] = slope;
      grid.joint_derivatives[at + 1] = bend;
    }
  }
}

// On a grid finer than kFineStepMm the differences of its joints are rounding (a joint of a
// metre rounds to 1e-10 mm: over 1e-6 mm steps its bend reads thousands per mm^2 and a cable
// crawls through a micrometre's move): there the derivatives come from poses kFineStepMm apart
// along the path's own tangent and bend at each point (chain rule: q'' = D2q[p', p'] + Dq[p'']),
// where the inverse kinematics answers there.
void FeedLimits::fine_joint_terms(Piece& piece) {
  PathGrid& grid = piece.grid;
  const Segment& segment = piece.segment;
  const int n = grid.intervals;
  const double delta = kFineStepMm, length = piece.length;
  kinematics::JointVector ahead, behind, out, in;
  for (int k = 0; k <= n; ++k) {
    const double u = static_cast<double>(k) / n;
    const geometry::Vector6d pose = segment.at(u);
    const geometry::Vector6d tangent = segment.velocity_at(u) / length;
    const geometry::Vector6d bend = segment.acceleration_at(u) / (length * length);
    const auto numbers = [&](double step, const geometry::Vector6d& direction,
                             kinematics::JointVector& forth, kinematics::JointVector& back) {
      return joints_either_side(pose, direction, step, forth, back) && forth.allFinite() &&
             back.allFinite();
    };
    if (!numbers(delta, tangent, ahead, behind)) continue;
    const kinematics::JointVector& here = joints_at_points_[static_cast<std::size_t>(k)];
    kinematics::JointVector second = (ahead - 2.0 * here + behind) / (delta * delta);
    const double bend_size = bend.norm();
    if (bend_size > 0.0) {
      const double step = delta / bend_size;
      if (!numbers(step, bend, out, in)) continue;
      second += (out - in) / (2.0 * step);
    }
    for (int j = 0; j < grid.joint_count; ++j) {
      const std::size_t at = static_cast<std::size_t>((k * grid.joint_count + j) * 2);
      grid.joint_derivatives[at] = (ahead[j] - behind[j]) / (2.0 * delta);
      grid.joint_derivatives[at + 1] = second[j];
    }
  }
}

// The tool tip's rate and bend along the path at every point (from the segment's own numbers),
// and its curvature |r x b| / |r|^3.
void FeedLimits::grid_curvature(Piece& piece) const {
  PathGrid& grid = piece.grid;
  const Segment& segment = piece.segment;
  const int n = grid.intervals;
  const double length = piece.length;
  for (int k = 0; k <= n; ++k) {
    const std::size_t at = static_cast<std::size_t>(k);
    const double u = static_cast<double>(k) / n;
    Eigen::Vector3d rate = segment.velocity_at(u).head<3>() / length;
    Eigen::Vector3d bend = segment.acceleration_at(u).head<3>() / (length * length);
    if (segment.z_free) {
      rate.z() = 0.0;
      bend.z() = 0.0;
    }
    const double speed = rate.norm();
    if (!(speed > 1e-12)) {  // the angles alone
      rate = Eigen::Vector3d::UnitX();
      bend = Eigen::Vector3d::Zero();
    }
    grid.tool_rate[at] = rate;
    grid.tool_bend[at] = bend;
    grid.curvature_per_mm[at] = rate.cross(bend).norm() / std::pow(rate.norm(), 3);
  }
}

namespace {

// A unit vector along `v` (x y), or zero.
Eigen::Vector2d unit(const Eigen::Vector2d& v) {
  const double n = v.norm();
  return n > 0.0 ? Eigen::Vector2d(v / n) : Eigen::Vector2d::Zero();
}

}  // namespace

// How each cable's lowest and highest tension change with the effector's acceleration along
// `direction` (a unit vector, x y) at `pose`: central differences at +-`probe` mm/s^2 (the most a
// move accelerates the tool), and how far the tensions stray from that line there. A probe with
// no balance is retried closer.
FeedLimits::TensionSlope FeedLimits::tension_slope(const geometry::Pose& pose,
                                                   const Eigen::Vector2d& direction, double probe,
                                                   const kinematics::CableStatics& rest,
                                                   int line) const {
  TensionSlope slope;
  if (direction.isZero()) return slope;
  for (int attempt = 0; attempt < 6; ++attempt, probe *= 0.25) {
    kinematics::CableStatics plus, minus;
    const kinematics::Status a = tension_->kinematics().statics(pose, probe * direction, plus);
    const kinematics::Status b = tension_->kinematics().statics(pose, -probe * direction, minus);
    const auto balanced = [](const kinematics::Status& status) {
      return status.ok() || status.code == kinematics::StatusCode::tension;
    };
    if (!balanced(a) || !balanced(b)) continue;
    for (std::size_t c = 0; c < 2; ++c) {
      slope.lowest[c] = (plus.lowest_N[c] - minus.lowest_N[c]) / (2.0 * probe);
      slope.highest[c] = (plus.highest_N[c] - minus.highest_N[c]) / (2.0 * probe);
      slope.stray_N = std::max(
          {slope.stray_N, std::abs(0.5 * (plus.lowest_N[c] + minus.lowest_N[c]) - rest.lowest_N[c]),
           std::abs(0.5 * (plus.highest_N[c] + minus.highest_N[c]) - rest.highest_N[c])});
    }
    return slope;
  }
  throw PlanError(file_, line,
                  "the cables find no balance for the effector accelerating at a pose of the move");
}

// The exact range of the path acceleration at point k at rest speed along `tangent` (x y; 0 on a
// plunge, which the cables do not feel), up to the tool's `acceleration`, and the rows that set
// its ends.
void FeedLimits::tangential_range(PathGrid& grid, int k, const geometry::Vector6d& pose,
                                  const Eigen::Vector2d& tangent, double acceleration) const {
  const std::size_t at = static_cast<std::size_t>(k);
  const double length = tangent.norm();
  grid.tangential_range[at] = {-1e300, 1e300};
  grid.tangential_row[at] = {-1, -1};
  if (!(length > 0.0)) return;
  for (std::size_t side = 0; side < 2; ++side) {
    const double sign = side == 0 ? -1.0 : 1.0;
    TensionExcess beyond;
    const double allowed =
        tension_->allowed_along(pose, sign * tangent / length, acceleration, beyond);
    grid.tangential_range[at][side] = sign * allowed / length;
    if (allowed < acceleration && beyond.cable >= 0) {
      grid.tangential_row[at][side] = 2 * beyond.cable + (beyond.slack ? 0 : 1);
    }
  }
}

// Each cable's tensions at every point as lines in u and x (path_grid.hpp's TensionRow): the
// effector accelerates along the path's tangent by u and towards its centre by curvature * x.
void FeedLimits::grid_tension_rows(Piece& piece) {
  if (tension_->robot() != nullptr) {
    grid_force_rows(piece);
    return;
  }
  PathGrid& grid = piece.grid;
  const Segment& segment = piece.segment;
  const int n = grid.intervals;
  // Lines fitted over a quarter of gravity at most: beyond it a cable may go slack and the
  // balance bend; the tangential range at rest speed is found exactly below.
  const double acceleration = machine_.cartesian().max_acceleration_mm_per_s2;
  const double probe = std::min(acceleration, 0.25 * kinematics::kStandardGravity_mm_per_s2);
  const kinematics::HangingCables& cables = tension_->kinematics();
  for (int k = 0; k <= n; ++k) {
    const geometry::Pose pose = geometry::Pose::from_vector(segment.at(static_cast<double>(k) / n));
    kinematics::CableStatics rest;
    if (!cables.statics(pose, Eigen::Vector2d::Zero(), rest).ok()) leaves_reach(segment);
    // The effector's acceleration per u and per x (zero for a move of the angles alone).
    const double u = static_cast<double>(k) / n;
    const Eigen::Vector2d tangent = segment.velocity_at(u).head<2>() / piece.length;
    const Eigen::Vector2d across = grid.tool_bend[static_cast<std::size_t>(k)].head<2>();
    const TensionSlope along_slope = tension_slope(pose, unit(tangent), probe, rest, segment.line);
    const TensionSlope across_slope = tension_slope(pose, unit(across), probe, rest, segment.line);
    const double stray = along_slope.stray_N + across_slope.stray_N;
    const geometry::Vector6d pose_vector = pose.as_vector();
    grid.tangent_xy[static_cast<std::size_t>(k)] = tangent;
    grid.curvature_xy[static_cast<std::size_t>(k)] = across;
    tangential_range(grid, k, pose_vector, tangent, acceleration);
    TensionRow* rows = &grid.tension_rows[static_cast<std::size_t>(k * grid.rows_per_point)];
    for (std::size_t cable = 0; cable < 2; ++cable) {
      rows[2 * cable] =
          TensionRow{rest.lowest_N[cable], along_slope.lowest[cable] * tangent.norm(),
                     across_slope.lowest[cable] * across.norm(),
                     std::min(cables.tension_min_N() + stray, rest.lowest_N[cable]), 1e300};
      rows[2 * cable + 1] = TensionRow{
          rest.highest_N[cable], along_slope.highest[cable] * tangent.norm(),
          across_slope.highest[cable] * across.norm(), -1e300,
          std::max(std::min(1e300, cables.tension_max_N()) - stray, rest.highest_N[cable])};
    }
  }
}

// n cables: at every point a row per facet pair of the forces the cables can exert there
// (cable_force_polytope.hpp). The force they must exert is m (a - g) with a = rate u + bend x, so
// its component along a facet's normal is exactly linear in u and x: the rows need no probing
// and no tightening. The path acceleration each allows at rest speed, for the report.
void FeedLimits::grid_force_rows(Piece& piece) {
  PathGrid& grid = piece.grid;
  const kinematics::CableTensions& robot = *tension_->robot();
  const double mass = 1e-3 * robot.effector_mass_kg();  // N per mm/s^2
  const Eigen::Vector3d rest_force = robot.cable_force_N(Eigen::Vector3d::Zero());
  const double tool = machine_.cartesian().max_acceleration_mm_per_s2;
  const int n = grid.intervals, per_point = grid.rows_per_point;
  grid.exact_tension_rows = true;
  kinematics::CableForcePolytope polytope;
  const auto finite = [](double value) { return std::clamp(value, -1e300, 1e300); };
  for (int k = 0; k <= n; ++k) {
    const std::size_t at = static_cast<std::size_t>(k);
    const geometry::Pose pose =
        geometry::Pose::from_vector(piece.segment.at(static_cast<double>(k) / n));
    if (!robot.force_polytope(pose, polytope) || polytope.count > per_point) {
      leaves_reach(piece.segment);
    }
    TensionRow* rows = &grid.tension_rows[at * static_cast<std::size_t>(per_point)];
    std::array<double, 2> allowed = {tool, tool};
    std::array<int, 2> bound_by = {-1, -1};
    for (int f = 0; f < per_point; ++f) {
      if (f >= polytope.count) {
        rows[f] = TensionRow{0.0, 0.0, 0.0, -1e300, 1e300};
        continue;
      }
      const kinematics::ForceFacet& facet = polytope.facets[static_cast<std::size_t>(f)];
      TensionRow& row = rows[f];
      row = TensionRow{facet.normal.dot(rest_force), mass * facet.normal.dot(grid.tool_rate[at]),
                       mass * facet.normal.dot(grid.tool_bend[at]), finite(facet.low_N),
                       finite(facet.high_N)};
      // A pose the cables do not hold at rest: inverse kinematics refuses it (beyond its 1e-9
      // of the tension scale), so only a pose on the border, past a facet by rounding, gets
      // here; its row then allows rest and no acceleration outwards, as the plotter's does.
      const double rounding = 1e-8 * (1.0 + std::abs(row.rest_N));
      if (row.rest_N < row.low_N - rounding || row.rest_N > row.high_N + rounding) {
        leaves_reach(piece.segment);
      }
      row.low_N = std::min(row.low_N, row.rest_N);
      row.high_N = std::max(row.high_N, row.rest_N);
      for (std::size_t side = 0; side < 2; ++side) {  // u < 0, u > 0
        const double slope = side == 0 ? -row.along : row.along;
        if (slope == 0.0) continue;
        const bool high = slope > 0.0;
        const double most =
            std::max(0.0, (high ? row.high_N - row.rest_N : row.low_N - row.rest_N) / slope);
        if (most < allowed[side]) {
          allowed[side] = most;
          bound_by[side] = 2 * f + (high ? 1 : 0);
        }
      }
    }
    grid.tangential_range[at] = {-allowed[0], allowed[1]};
    grid.tangential_row[at] = bound_by;
  }
}

// The cable a tension row names for the report: the plotter's rows are each cable's lowest and
// highest tension; n cables', a facet's side (2 facet + high) at `point`.
TensionExcess FeedLimits::row_cable(const Piece& piece, int point, int row) const {
  if (tension_->robot() != nullptr) {
    const geometry::Vector6d pose =
        piece.segment.at(static_cast<double>(point) / piece.grid.intervals);
    return tension_->on_facet(pose, row / 2, row % 2 == 1);
  }
  TensionExcess excess;
  excess.cable = row / 2;
  excess.slack = row % 2 == 0;
  return excess;
}

// The report's entries for a piece planned on its grid: the slowest cruise any limit alone
// allows along it, when a joint or a cable sets it below the programmed feed and below what the
// tool's own acceleration allows on its curve; and the least acceleration along the path the
// cables allow at rest speed, when it is below the tool's.
void FeedLimits::report_grid_limits(const Piece& piece) {
  int tension_row = -1, tension_point = 0;
  const JointFeedLimit slowest = slowest_cruise(piece, tension_row, tension_point);
  if (tension_row >= 0) {
    const TensionExcess cable = row_cable(piece, tension_point, tension_row);
    FeedLimit limit = feed_limit(piece, cable.cable, slowest.speed_mm_per_s, LimitCause::tension);
    limit.slack = cable.slack;
    report_.feed_limits.push_back(limit);
  } else if (slowest.joint >= 0) {
    report_joint_limit(piece, slowest, kGridLimitShare, kGridLimitShare);
  }
  const PathGrid& grid = piece.grid;
  const double tool = machine_.cartesian().max_acceleration_mm_per_s2;
  double least = tool;
  int row = -1, point = 0;
  for (std::size_t k = 0; k < grid.tangential_range.size(); ++k) {
    for (std::size_t side = 0; side < 2; ++side) {
      const double allowed = std::abs(grid.tangential_range[k][side]);
      if (grid.tangential_row[k][side] >= 0 && allowed < least) {
        least = allowed;
        row = grid.tangential_row[k][side];
        point = static_cast<int>(k);
      }
    }
  }
  if (row >= 0) {
    const TensionExcess cable = row_cable(piece, point, row);
    report_.tension_limits.push_back({piece.segment.line, cable.cable, cable.slack, tool, least});
  }
}

// The slowest speed at which the piece could cruise (u = 0) by any one limit: the feed, the
// tool's v^2/r, each joint's velocity share / |q'| and bend sqrt(share amax / |q''|), each
// cable's tension across a curve. The joint that sets it, or the tension row in `tension_row`
// (else -1); neither when the feed or the tool's own acceleration does.
JointFeedLimit FeedLimits::slowest_cruise(const Piece& piece, int& tension_row,
                                          int& tension_point) const {
  const PathGrid& grid = piece.grid;
  JointFeedLimit slowest;
  slowest.speed_mm_per_s = piece.max_speed;
  const double tool = machine_.cartesian().max_acceleration_mm_per_s2;
  for (const double curvature : grid.curvature_per_mm) {
    if (curvature > 0.0) {
      slowest.speed_mm_per_s = std::min(slowest.speed_mm_per_s, std::sqrt(tool / curvature));
    }
  }
  const double cruise = slowest.speed_mm_per_s;
  tension_row = -1;
  for (int k = 0; k <= grid.intervals; ++k) {
    kinematics::JointVector slope(grid.joint_count), bend(grid.joint_count);
    for (int j = 0; j < grid.joint_count; ++j) {
      slope[j] = std::abs(grid.slope(k, j));
      bend[j] = std::abs(grid.bend(k, j));
    }
    const JointFeedLimit here = joint_feed_limit(
        machine_.joints(), slope, bend, slowest.speed_mm_per_s, kGridLimitShare, kGridLimitShare);
    if (here.joint >= 0) {
      slowest = here;
      tension_row = -1;
    }
    const TensionRow* rows = grid.tensions(k);
    for (int r = 0; rows != nullptr && r < grid.rows_per_point; ++r) {
      const TensionRow& row = rows[r];
      const double room = row.across > 0.0 ? row.high_N - row.rest_N : row.low_N - row.rest_N;
      if (row.across != 0.0 &&
          room / row.across < slowest.speed_mm_per_s * slowest.speed_mm_per_s) {
        slowest.speed_mm_per_s = std::sqrt(std::max(0.0, room / row.across));
        slowest.joint = -1;
        // n cables' rows are two-sided: the side that bound (row_cable).
        tension_row = grid.exact_tension_rows ? 2 * r + (row.across > 0.0 ? 1 : 0) : r;
        tension_point = k;
      }
    }
  }
  if (!(slowest.speed_mm_per_s < cruise * (1.0 - 1e-9))) {
    slowest.joint = -1;
    tension_row = -1;
  }
  return slowest;
}

}  // namespace pkm::motion
