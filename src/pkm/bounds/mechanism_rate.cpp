// How fast the leg limits' values can change over a ball of poses (mechanism_rate.hpp).
#include "pkm/bounds/mechanism_rate.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "pkm/kinematics/derivative_bounds.hpp"
#include "pkm/kinematics/leg_limits.hpp"

namespace pkm::bounds {

kinematics::LegMotion leg_motion(const kinematics::Kinematics& model,
                                 const kinematics::JointVector& joints,
                                 const kinematics::JointJacobian& jacobian,
                                 const kinematics::HessianBounds& hessians, double radius,
                                 double scale) {
  const kinematics::DerivativeBounds* own = model.derivative_bounds();
  if (own == nullptr) return {};
  return own->leg_motion(joints, jacobian, hessians, radius, scale);
}

// How fast (per scaled unit) a joint-angle or clearance value can change over the ball.
double mechanism_rate(const kinematics::MechanismLimit& limit,
                      const kinematics::LegMotion& motion) {
  const auto k = static_cast<std::size_t>(limit.leg);
  if (limit.code == kinematics::StatusCode::joint_angle) {
    if (!(motion.shortest_mm[k] > 0.0)) return INFINITY;
    const double turn = (motion.inner_speed[k] + motion.platform_speed[k]) / motion.shortest_mm[k];
    return turn + (limit.other == kinematics::kPlatformEnd ? motion.platform_turn : 0.0);
  }
  // Each point of a leg is a mix of its ends: it moves no faster than the faster end.
  const auto j = static_cast<std::size_t>(limit.other);
  return std::max(motion.inner_speed[k], motion.platform_speed[k]) +
         std::max(motion.inner_speed[j], motion.platform_speed[j]);
}

std::optional<kinematics::LegEnds> legs_at(const kinematics::Kinematics& model,
                                           const geometry::Pose& pose,
                                           const kinematics::JointVector& joints) {
  const kinematics::DerivativeBounds* own = model.derivative_bounds();
  if (own == nullptr) return std::nullopt;
  return own->legs_at(pose, joints);
}

namespace {

// How far the points of two legs can move relative to each other over the ball: the shared
// translation moves the point at s of one leg and the point at u of the other alike, so it
// parts them by at most shared |s - u|; the rest (a carriage's own travel at the inner end, the
// platform's turn at the platform end) moves a leg's point by at most the mix of its ends.
struct PairMotion {
  double shared = 0.0;               // mm: the platform's translation
  std::array<double, 2> inner{};     // mm: each leg's inner end, not counting the translation
  std::array<double, 2> platform{};  // mm: each leg's platform end, not counting it
  double own(int leg, double s) const {
    const auto k = static_cast<std::size_t>(leg);
    return inner[k] + s * (platform[k] - inner[k]);
  }
  double apart(double s, double u) const {
    return shared * std::abs(s - u) + own(0, s) + own(1, u);
  }
};

// min over u in [low, high] of |b - u w| - slope u: convex in u; the stationary point of
// sqrt(h^2 + (u - e)^2 |w|^2) - slope u, clamped, where |slope| < |w|; else an end.
double least_along(const Eigen::Vector3d& b, const Eigen::Vector3d& w, double slope, double low,
                   double high, double& u) {
  const double ww = w.squaredNorm();
  const auto value = [&](double at) { return (b - at * w).norm() - slope * at; };
  if (ww > 0.0 && slope * slope < ww) {
    const double e = b.dot(w) / ww;
    const double h = std::sqrt(std::max(0.0, b.squaredNorm() - e * e * ww));
    u = std::clamp(e + slope * h / std::sqrt(ww * (ww - slope * slope)), low, high);
    return value(u);
  }
  const double at_low = value(low), at_high = value(high);
  u = at_low <= at_high ? low : high;
  return std::min(at_low, at_high);
}

struct Clearance {
  double least = 0.0, most = 0.0;  // bounds on the legs' distance over the ball
};

// The least of F(s, u) = |X(s) - Y(u)| - motion.apart(s, u) over one triangle of the unit
// square (u <= s, or u >= s), where F is convex (a norm of an affine map less a linear
// function): min over u in closed form, convex in s, golden-section search on s; the minimum
// lies in the last bracket, so F there less its Lipschitz constant times the bracket's width
// bounds it from below (the ends' values, taken if lower, only make it safer). `at`: the (s, u)
// of the least value found, whose distance bounds the legs' from above.
double least_on_triangle(const Eigen::Vector3d& base, const Eigen::Vector3d& wi,
                         const Eigen::Vector3d& wj, const PairMotion& motion, bool u_below_s,
                         std::array<double, 2>& at) {
  const double slope_u =
      motion.platform[1] - motion.inner[1] + (u_below_s ? -1.0 : 1.0) * motion.shared;
  const double slope_s =
      motion.platform[0] - motion.inner[0] + (u_below_s ? 1.0 : -1.0) * motion.shared;
  const auto at_s = [&](double s, double& u) {
    const double low = u_below_s ? 0.0 : s, high = u_below_s ? s : 1.0;
    return least_along(base + s * wi, wj, slope_u, low, high, u) - slope_s * s - motion.inner[0] -
           motion.inner[1];
  };
  constexpr double kGolden = 0.6180339887498949;
  double low = 0.0, high = 1.0, u = 0.0;
  double left = high - kGolden, right = kGolden;
  double f_left = at_s(left, u), f_right = at_s(right, u);
  for (int step = 0; step < 40; ++step) {
    if (f_left <= f_right) {
      high = right;
      right = left;
      f_right = f_left;
      left = high - kGolden * (high - low);
      f_left = at_s(left, u);
    } else {
      low = left;
      left = right;
      f_left = f_right;
      right = low + kGolden * (high - low);
      f_right = at_s(right, u);
    }
  }
  // The min over u moves with s through F's slope in s and, where the triangle's side s = u
  // cuts the minimiser off, through its slope in u.
  const double lipschitz = wi.norm() + std::abs(slope_s) + wj.norm() + std::abs(slope_u) + 1e-9;
  double best = at_s(0.5 * (low + high), u) - lipschitz * (high - low);
  at = {0.5 * (low + high), u};
  for (const double end : {0.0, 1.0}) {
    const double f_end = at_s(end, u);
    if (f_end < best) {
      best = f_end;
      at = {end, u};
    }
  }
  return best;
}

Clearance leg_clearance(const Eigen::Vector3d& inner_i, const Eigen::Vector3d& platform_i,
                        const Eigen::Vector3d& inner_j, const Eigen::Vector3d& platform_j,
                        const PairMotion& motion) {
  const Eigen::Vector3d wi = platform_i - inner_i, wj = platform_j - inner_j;
  const Eigen::Vector3d base = inner_i - inner_j;
  std::array<double, 2> below{}, above{};
  const double least_below = least_on_triangle(base, wi, wj, motion, true, below);
  const double least_above = least_on_triangle(base, wi, wj, motion, false, above);
  const std::array<double, 2>& at = least_below <= least_above ? below : above;
  const double apart = (base + at[0] * wi - at[1] * wj).norm();
  return {std::min(least_below, least_above), apart + motion.apart(at[0], at[1])};
}

}  // namespace

Reach mechanism_reach(const kinematics::MechanismLimit& limit, const kinematics::LegMotion& motion,
                      double radius, const kinematics::LegEnds* ends) {
  const double spread = mechanism_rate(limit, motion) * radius;
  // The rate alone is enough where it keeps the legs apart (most pairs, most of the time).
  if (limit.code == kinematics::StatusCode::joint_angle || ends == nullptr ||
      !std::isfinite(spread) || motion.platform_arm_mm.empty() ||
      limit.value - spread > limit.limit)
    return {spread, spread};
  const int i = limit.leg, j = limit.other;
  const auto k = static_cast<std::size_t>(i), l = static_cast<std::size_t>(j);
  // Over the ball the translation is at most the radius and the turn at most platform_turn
  // times it; a carriage travels at most its inner speed times it.
  PairMotion pair;
  pair.shared = radius;
  pair.inner = {motion.inner_speed[k] * radius, motion.inner_speed[l] * radius};
  pair.platform = {motion.platform_arm_mm[k] * motion.platform_turn * radius,
                   motion.platform_arm_mm[l] * motion.platform_turn * radius};
  const Clearance clearance = leg_clearance(ends->inner.col(i), ends->platform.col(i),
                                            ends->inner.col(j), ends->platform.col(j), pair);
  return {std::min(spread, limit.value - clearance.least),
          std::min(spread, clearance.most - limit.value)};
}

}  // namespace pkm::bounds
