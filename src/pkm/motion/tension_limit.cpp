#include "pkm/motion/tension_limit.hpp"

#include "pkm/motion/path_grid.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <vector>

namespace pkm::motion {

namespace {

using Vector2 = Eigen::Vector2d;
using Vector3 = Eigen::Vector3d;

// A headroom's search stops within this margin of the limit (N), or after this many steps.
constexpr double kMarginTolerance_N = 1e-10;
constexpr int kIterations = 60;

const char* cable_name(int cable) {
  return cable == 0 ? "left" : "right";
}

std::string newtons(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g N", value);
  return text;
}

}  // namespace

std::optional<TensionLimit> TensionLimit::of(const kinematics::Kinematics& kinematics,
                                             double share) {
  if (const kinematics::HangingCables* cables = kinematics.hanging_cables()) {
    if (!(cables->effector_mass_kg() > 0.0)) return std::nullopt;
    return TensionLimit(*cables, share);
  }
  const kinematics::CableTensions* robot = kinematics.cable_tensions();
  if (robot == nullptr || !(robot->effector_mass_kg() > 0.0)) return std::nullopt;
  return TensionLimit(*robot, share);
}

int TensionLimit::rows_per_point() const {
  if (robot_ == nullptr) return kTensionRowsPerPoint;
  const int n = robot_->tension_count();
  return std::max(n, n * (n - 1) / 2);
}

TensionExcess TensionLimit::excess(const geometry::Vector6d& pose,
                                   const Eigen::Vector3d& acceleration_mm_per_s2) const {
  if (robot_ != nullptr) return robot_excess(pose, acceleration_mm_per_s2);
  return plotter_excess(pose, acceleration_mm_per_s2.head<2>());
}

TensionExcess TensionLimit::plotter_excess(const geometry::Vector6d& pose,
                                           const Eigen::Vector2d& acceleration_mm_per_s2) const {
  kinematics::CableStatics statics;
  const kinematics::Status status =
      kinematics_->statics(geometry::Pose::from_vector(pose), acceleration_mm_per_s2, statics);
  TensionExcess result;
  if (!status.ok()) {
    result.outside = true;
    result.margin_N = -std::numeric_limits<double>::infinity();
    if (status.code == kinematics::StatusCode::tension &&
        (status.joint == 0 || status.joint == 1)) {
      const std::size_t c = static_cast<std::size_t>(status.joint);
      result.cable = status.joint;  // it would have to push
      result.slack = true;
      result.tension_N = statics.lowest_N[c];
      result.margin_N = statics.lowest_N[c] - kinematics_->tension_min_N();
    }
    return result;
  }
  // The tension nearest to (or furthest beyond) its limit.
  result.margin_N = std::numeric_limits<double>::infinity();
  for (int cable = 0; cable < 2; ++cable) {
    const std::size_t c = static_cast<std::size_t>(cable);
    const double above_min = statics.lowest_N[c] - kinematics_->tension_min_N();
    const double below_max = kinematics_->tension_max_N() - statics.highest_N[c];
    if (above_min < result.margin_N) result = {false, cable, true, statics.lowest_N[c], above_min};
    if (below_max < result.margin_N)
      result = {false, cable, false, statics.highest_N[c], below_max};
  }
  result.outside = result.margin_N < 0.0;
  return result;
}

double TensionLimit::headroom(const geometry::Vector6d& pose, const Eigen::Vector3d& base,
                              const Eigen::Vector3d& direction, double cap, double scale,
                              TensionExcess& excess_found) const {
  excess_found = excess(pose, Vector3(scale * (base + cap * direction)));
  if (!excess_found.outside) return cap;
  const TensionExcess at_base = excess(pose, Vector3(scale * base));
  if (at_base.outside) {
    excess_found = at_base;
    return 0.0;
  }
  // The margin is nearly linear in c (min of linear functions for cables tied at the pen):
  // regula falsi, Illinois' way (the side that stays has its margin halved), from [0, cap],
  // keeping `low` within the limits; bisection where a side has no balance at all.
  double low = 0.0, high = cap, margin_low = at_base.margin_N, margin_high = excess_found.margin_N;
  int kept = 0;  // +1: low moved last, -1: high moved last
  for (int i = 0; i < kIterations && high - low > 1e-12 * cap; ++i) {
    double c = std::isfinite(margin_high)
                   ? (low * margin_high - high * margin_low) / (margin_high - margin_low)
                   : 0.5 * (low + high);
    if (!(c > low && c < high)) c = 0.5 * (low + high);
    const TensionExcess e = excess(pose, Vector3(scale * (base + c * direction)));
    if (e.outside) {
      high = c;
      margin_high = e.margin_N;
      excess_found = e;
      if (kept == -1) margin_low *= 0.5;
      kept = -1;
    } else {
      low = c;
      margin_low = e.margin_N;
      if (kept == 1) margin_high *= 0.5;
      kept = 1;
      if (e.margin_N < kMarginTolerance_N) break;
    }
  }
  return low;
}

TensionBound TensionLimit::along(const Segment& segment, double length_mm, int points, double speed,
                                 double acceleration) const {
  TensionBound bound;
  bound.speed_mm_per_s = speed;
  bound.acceleration_mm_per_s2 = acceleration;
  if (!(length_mm > 0.0) || points < 2) return bound;
  const double step = length_mm / points;
  std::vector<geometry::Vector6d> poses(static_cast<std::size_t>(points) + 1);
  for (int k = 0; k <= points; ++k) {
    poses[static_cast<std::size_t>(k)] = segment.at(static_cast<double>(k) / points);
  }
  // The tool point as the cables feel it (x y alone for the plotter).
  const auto xy = [&](int k) -> Vector3 {
    return felt(poses[static_cast<std::size_t>(k)].head<3>());
  };
  // The path's derivatives by differences: d/ds (a unit tangent in the plane of a plane move)
  // and d2/ds2 (the curvature vector, 1 / r towards the centre).
  const auto tangent = [&](int k) -> Vector3 {
    const int a = std::max(k - 1, 0), b = std::min(k + 1, points);
    return (xy(b) - xy(a)) / ((b - a) * step);
  };
  const auto curvature = [&](int k) -> Vector3 {
    const int c = std::clamp(k, 1, points - 1);
    return (xy(c + 1) - 2.0 * xy(c) + xy(c - 1)) / (step * step);
  };
  const double scale = 1.0 / share_;
  // A line is straight (its differences' rounding would read as a curvature on short lines).
  const bool line = segment.kind == SegmentKind::line;
  const auto curved = [&](const Vector3& kappa) { return !line && kappa.norm() > 0.0; };
  TensionExcess excess_found;
  // On a curve v^2 / r across takes at most half of the headroom.
  for (int k = 0; k <= points; ++k) {
    const Vector3 kappa = curvature(k);
    if (!curved(kappa)) continue;
    const double bend = kappa.norm();
    const double across = bound.speed_mm_per_s * bound.speed_mm_per_s * bend;
    const geometry::Vector6d& pose = poses[static_cast<std::size_t>(k)];
    const double allowed =
        headroom(pose, Vector3::Zero(), kappa / bend, 2.0 * across, scale, excess_found);
    if (allowed < 2.0 * across) {
      bound.speed_mm_per_s = std::sqrt(0.5 * allowed / bend);
      bound.speed_limited = true;
      bound.excess = excess_found;
    }
  }
  // Along the path: +-A along the tangent, the centripetal part at that speed across.
  for (int k = 0; k <= points; ++k) {
    const Vector3 kappa = curvature(k);
    const Vector3 across = curved(kappa)
                               ? Vector3(bound.speed_mm_per_s * bound.speed_mm_per_s * kappa)
                               : Vector3::Zero();
    const Vector3 along = tangent(k);
    const geometry::Vector6d& pose = poses[static_cast<std::size_t>(k)];
    for (const double sign : {1.0, -1.0}) {
      const double cap = bound.acceleration_mm_per_s2;
      const double allowed = headroom(pose, across, sign * along, cap, scale, excess_found);
      if (allowed < cap) {
        bound.acceleration_mm_per_s2 = allowed;
        bound.acceleration_limited = true;
        bound.excess = excess_found;
      }
    }
  }
  return bound;
}

double TensionLimit::junction_speed(const geometry::Vector6d& pose, const Eigen::Vector3d& out,
                                    const Eigen::Vector3d& in, double chord_mm, double period_s,
                                    double speed) const {
  const Vector3 change = felt(in - out);
  const double jump = change.norm();
  if (!(jump > 0.0) || !(speed > 0.0)) return speed;
  // The velocity's change v |in - out| spread over the period, or over the time between two
  // junctions where they come closer (v^2 |in - out| / chord: a curve's v^2 / r, in chords).
  const auto kick = [&](double v) { return v * jump * std::max(1.0 / period_s, v / chord_mm); };
  TensionExcess excess_found;
  const double allowed = headroom(pose, Vector3::Zero(), change / jump, kick(speed),
                                  1.0 / (1.0 - share_), excess_found);
  if (!(allowed < kick(speed))) return speed;
  return std::min(allowed * period_s / jump, std::sqrt(allowed * chord_mm / jump));
}

std::string TensionLimit::beyond_limits_at_rest(
    const std::function<geometry::Vector6d(double)>& pose_at) const {
  if (robot_ != nullptr) return robot_beyond_limits_at_rest(pose_at);
  constexpr int kSamples = 1000;
  double lowest[2] = {1e300, 1e300}, highest[2] = {-1e300, -1e300};
  for (int k = 0; k <= kSamples; ++k) {
    kinematics::CableStatics statics;
    const geometry::Pose pose =
        geometry::Pose::from_vector(pose_at(static_cast<double>(k) / kSamples));
    if (!kinematics_->statics(pose, Vector2::Zero(), statics).ok()) continue;
    for (std::size_t c = 0; c < 2; ++c) {
      lowest[c] = std::min(lowest[c], statics.lowest_N[c]);
      highest[c] = std::max(highest[c], statics.highest_N[c]);
    }
  }
  std::string text;
  for (int cable = 0; cable < 2; ++cable) {
    const std::string name = std::string(" the ") + cable_name(cable) + " cable's tension ";
    if (highest[cable] > kinematics_->tension_max_N()) {
      text += (text.empty() ? ";" : ",") + name + "reaches " + newtons(highest[cable]);
    }
    if (lowest[cable] < kinematics_->tension_min_N()) {
      text += (text.empty() ? ";" : ",") + name + "falls to " + newtons(lowest[cable]);
    }
  }
  return text.empty() ? text : text + " along the move";
}

namespace {

// The first cable among `cables` (bits), or -1.
int first_cable(std::uint32_t cables) {
  for (int k = 0; k < 32; ++k) {
    if ((cables >> k & 1u) != 0u) return k;
  }
  return -1;
}

// "cables 1 and 3" (numbered from 1).
std::string cable_list(std::uint32_t cables) {
  std::vector<int> numbers;
  for (int k = 0; k < 32; ++k) {
    if ((cables >> k & 1u) != 0u) numbers.push_back(k + 1);
  }
  std::string text = numbers.size() == 1 ? "cable " : "cables ";
  for (std::size_t i = 0; i < numbers.size(); ++i) {
    if (i > 0) text += i + 1 == numbers.size() ? " and " : ", ";
    text += std::to_string(numbers[i]);
  }
  return text;
}

// Where the load sits on a facet's side: which cables that side holds at their max (pulling
// along the normal on the high side) and at their min.
void name_facet_cables(TensionExcess& excess, const kinematics::TensionTargets& targets) {
  const kinematics::ForceFacet& f = excess.bounds;
  const std::uint32_t at_max = excess.high ? f.along : f.against;
  const std::uint32_t at_min = excess.high ? f.against : f.along;
  excess.slack = at_min != 0u;
  excess.cable = first_cable(excess.slack ? at_min : at_max);
  if (excess.cable >= 0) {
    excess.tension_N = excess.slack ? targets.min_N[excess.cable] : targets.max_N[excess.cable];
  }
}

}  // namespace

TensionExcess TensionLimit::robot_excess(const geometry::Vector6d& pose,
                                         const Eigen::Vector3d& acceleration_mm_per_s2) const {
  kinematics::CableForcePolytope polytope;
  TensionExcess result;
  if (!robot_->force_polytope(geometry::Pose::from_vector(pose), polytope)) {
    result.outside = true;
    result.margin_N = -std::numeric_limits<double>::infinity();
    return result;
  }
  const Vector3 force = robot_->cable_force_N(acceleration_mm_per_s2);
  result.margin_N = polytope.margin_N(force, result.facet, result.high);
  result.outside = !(result.margin_N >= 0.0);
  if (result.facet < 0) return result;
  result.bounds = polytope.facets[static_cast<std::size_t>(result.facet)];
  result.force_N = result.bounds.normal.dot(force);
  name_facet_cables(result, robot_->tension_targets());
  return result;
}

TensionExcess TensionLimit::on_facet(const geometry::Vector6d& pose, int facet, bool high) const {
  TensionExcess result;
  kinematics::CableForcePolytope polytope;
  if (robot_ == nullptr || !robot_->force_polytope(geometry::Pose::from_vector(pose), polytope) ||
      facet < 0 || facet >= polytope.count) {
    return result;
  }
  result.facet = facet;
  result.high = high;
  result.bounds = polytope.facets[static_cast<std::size_t>(facet)];
  result.force_N = high ? result.bounds.high_N : result.bounds.low_N;
  name_facet_cables(result, robot_->tension_targets());
  return result;
}

std::string TensionLimit::describe(const TensionExcess& excess) const {
  if (robot_ == nullptr) return describe_excess(*kinematics_, excess);
  if (excess.facet < 0)
    return "the effector has no balance there (the cables span too few directions)";
  const kinematics::ForceFacet& f = excess.bounds;
  const kinematics::TensionTargets targets = robot_->tension_targets();
  const std::uint32_t at_max = excess.high ? f.along : f.against;
  const std::uint32_t at_min = excess.high ? f.against : f.along;
  std::string held;
  if (at_max != 0u) {
    held += cable_list(at_max) + " at the maximum " + newtons(targets.max_N[first_cable(at_max)]);
  }
  if (at_min != 0u) {
    held += std::string(held.empty() ? "" : " and ") + cable_list(at_min) + " at the minimum " +
            newtons(targets.min_N[first_cable(at_min)]);
  }
  // Said on the side the load passes, the normal turned to point out of the polytope there.
  const double side = excess.high ? 1.0 : -1.0;
  const Eigen::Vector3d outwards = side * f.normal;
  char direction[96];
  std::snprintf(direction, sizeof direction, "(%.3f, %.3f, %.3f)", outwards.x(), outwards.y(),
                outwards.z());
  const double bound = side * (excess.high ? f.high_N : f.low_N);
  return "the cables would pull " + newtons(side * excess.force_N) + " along " + direction +
         ", more than the " + newtons(bound) + " they give there with " + held;
}

std::string TensionLimit::robot_beyond_limits_at_rest(
    const std::function<geometry::Vector6d(double)>& pose_at) const {
  constexpr int kSamples = 1000;
  std::optional<kinematics::TensionDistribution> worst;
  for (int k = 0; k <= kSamples; ++k) {
    const geometry::Pose pose =
        geometry::Pose::from_vector(pose_at(static_cast<double>(k) / kSamples));
    std::optional<kinematics::TensionDistribution> here = robot_->tensions(pose);
    if (!here || here->held()) continue;
    if (!worst || here->largest_violation_N > worst->largest_violation_N) worst = std::move(here);
  }
  return worst ? "; along the move " + kinematics::describe_refusal(*worst) : std::string();
}

std::string describe_excess(const kinematics::HangingCables& kinematics,
                            const TensionExcess& excess) {
  if (!excess.outside) return "the tensions are within their limits";
  if (excess.cable < 0) return "the effector has no balance there (the cables in line)";
  const std::string cable = std::string("the ") + cable_name(excess.cable) + " cable";
  if (excess.slack) {
    if (!(excess.tension_N > 0.0) && !kinematics.tension_limited()) {
      return cable + " would go slack (it would have to push)";
    }
    return cable + " would go slack: " + newtons(excess.tension_N) +
           ", below tension_limits' minimum " + newtons(kinematics.tension_min_N());
  }
  return cable + "'s tension would be " + newtons(excess.tension_N) +
         ", above tension_limits' maximum " + newtons(kinematics.tension_max_N());
}

}  // namespace pkm::motion
