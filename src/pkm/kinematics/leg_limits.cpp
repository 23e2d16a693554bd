#include "pkm/kinematics/leg_limits.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>

namespace pkm::kinematics {

namespace {

// An optional unit direction key [x, y, z].
std::optional<Eigen::Vector3d> read_axis(const ModelConfig& config, const char* key) {
  if (!config.has(key)) return std::nullopt;
  const std::vector<double> values = config.number_list(key);
  if (values.size() != 3) config.fail(key, "needs 3 numbers [x, y, z]");
  const Eigen::Vector3d axis(values[0], values[1], values[2]);
  if (!(axis.norm() > 0.0)) config.fail(key, "must not be the zero vector");
  return axis.normalized();
}

// Angle (rad) between a leg and a unit axis: atan2 keeps digits near 0 and 180 deg.
double angle_between(const Eigen::Vector3d& leg, const Eigen::Vector3d& unit_axis) {
  return std::atan2(leg.cross(unit_axis).norm(), leg.dot(unit_axis));
}

}  // namespace

LegLimitSettings read_leg_limit_settings(const ModelConfig& config, const char* inner_axis_key) {
  LegLimitSettings settings;
  if (config.has("max_joint_angle")) {
    std::vector<double> degrees;
    if (config.is_list("max_joint_angle")) {
      degrees = config.number_list("max_joint_angle");
      if (degrees.size() != 2) {
        config.fail("max_joint_angle",
                    "needs one angle for both ends or two [inner, platform] (deg)");
      }
    } else {
      degrees.assign(2, config.number("max_joint_angle"));
    }
    for (int end = 0; end < 2; ++end) {
      if (!(degrees[end] > 0.0 && degrees[end] < 180.0)) {
        config.fail("max_joint_angle", "must be between 0 and 180 deg (exclusive), not " +
                                           formatted_number("%g", degrees[end]));
      }
      settings.max_joint_angle_rad[end] = geometry::degrees_to_radians(degrees[end]);
    }
  }
  if (config.has("leg_diameter")) {
    settings.leg_diameter_mm = config.length("leg_diameter");
    if (!(settings.leg_diameter_mm > 0.0)) config.fail("leg_diameter", "must be a positive length");
  }
  settings.inner_axis = read_axis(config, inner_axis_key);
  settings.platform_axis = read_axis(config, "platform_joint_axis");
  if ((settings.inner_axis || settings.platform_axis) && !settings.checks_angles()) {
    config.fail(settings.inner_axis ? inner_axis_key : "platform_joint_axis",
                "is only read beside max_joint_angle");
  }
  return settings;
}

void write_leg_limit_settings(const LegLimitSettings& settings, const char* inner_axis_key,
                              ModelConfigWriter& out) {
  const auto& angle = settings.max_joint_angle_rad;
  if (settings.checks_angles()) {
    if (angle[0] == angle[1]) {
      out.number("max_joint_angle", geometry::radians_to_degrees(angle[0]));
    } else {
      const double degrees[2] = {geometry::radians_to_degrees(angle[0]),
                                 geometry::radians_to_degrees(angle[1])};
      out.number_list("max_joint_angle", degrees);
    }
  }
  if (settings.leg_diameter_mm > 0.0) out.length("leg_diameter", settings.leg_diameter_mm);
  if (settings.inner_axis) out.vector3(inner_axis_key, *settings.inner_axis);
  if (settings.platform_axis) out.vector3("platform_joint_axis", *settings.platform_axis);
}

LegLimits::LegLimits(const LegLimitSettings& settings, int legs)
    : settings_(settings), legs_(legs), active_(settings.any()) {
  for (int end = 0; end < 2; ++end) {
    const double max = settings.max_joint_angle_rad[end];
    cos_max_[end] = std::isfinite(max) ? std::cos(max) : -2.0;  // -2: every direction passes
    axes_[end].assign(static_cast<std::size_t>(legs), Eigen::Vector3d::Zero());
  }
}

void LegLimits::set_home(const LegEnds& at_home) {
  if (!active_) return;
  for (int leg = 0; leg < legs_; ++leg) {
    const Eigen::Vector3d direction =
        (at_home.platform.col(leg) - at_home.inner.col(leg)).normalized();
    const auto k = static_cast<std::size_t>(leg);
    axes_[kInnerEnd][k] = settings_.inner_axis.value_or(direction);
    axes_[kPlatformEnd][k] =
        settings_.platform_axis.value_or(at_home.rotation.transpose() * direction);
  }
  checked_pairs_ = 0;
  const double d = settings_.leg_diameter_mm;
  for (int i = 0; d > 0.0 && i < legs_; ++i) {
    for (int j = i + 1; j < legs_; ++j) {
      const bool neighbours = (at_home.inner.col(i) - at_home.inner.col(j)).norm() < d ||
                              (at_home.platform.col(i) - at_home.platform.col(j)).norm() < d;
      if (!neighbours) checked_pairs_ |= std::uint64_t{1} << pair_bit(i, j);
    }
  }
  homed_ = true;
}

Eigen::Vector3d LegLimits::axis_in_world(int leg, int end, const Eigen::Matrix3d& rotation) const {
  const Eigen::Vector3d& axis = axes_[static_cast<std::size_t>(end)][static_cast<std::size_t>(leg)];
  return end == kInnerEnd ? axis : Eigen::Vector3d(rotation * axis);
}

Status LegLimits::check(const LegEnds& ends) const {
  if (!active_ || !homed_) return Status::success();
  if (settings_.checks_angles()) {
    for (int leg = 0; leg < legs_; ++leg) {
      const Eigen::Vector3d along = ends.platform.col(leg) - ends.inner.col(leg);
      const double length = along.norm();
      for (int end = 0; end < 2; ++end) {
        // cos(angle) >= cos(max), written so that NaN fails.
        if (!(along.dot(axis_in_world(leg, end, ends.rotation)) >= cos_max_[end] * length)) {
          return Status::failure(StatusCode::joint_angle, leg);
        }
      }
    }
  }
  const double d = settings_.leg_diameter_mm;
  for (int i = 0; checked_pairs_ != 0 && i < legs_; ++i) {
    for (int j = i + 1; j < legs_; ++j) {
      if (!pair_checked(i, j)) continue;
      const double apart = segment_distance(ends.inner.col(i), ends.platform.col(i),
                                            ends.inner.col(j), ends.platform.col(j));
      if (!(apart >= d)) return Status::failure(StatusCode::interference, i);
    }
  }
  return Status::success();
}

void LegLimits::append_values(const LegEnds& ends, std::vector<MechanismLimit>& out) const {
  if (!active_ || !homed_) return;
  for (int leg = 0; settings_.checks_angles() && leg < legs_; ++leg) {
    const Eigen::Vector3d along = ends.platform.col(leg) - ends.inner.col(leg);
    for (int end = 0; end < 2; ++end) {
      const double max = settings_.max_joint_angle_rad[static_cast<std::size_t>(end)];
      if (!std::isfinite(max)) continue;
      out.push_back({StatusCode::joint_angle, leg, end,
                     angle_between(along, axis_in_world(leg, end, ends.rotation)), max});
    }
  }
  for (int i = 0; i < legs_; ++i) {
    for (int j = i + 1; j < legs_; ++j) {
      if (!pair_checked(i, j)) continue;
      out.push_back({StatusCode::interference, i, j,
                     segment_distance(ends.inner.col(i), ends.platform.col(i), ends.inner.col(j),
                                      ends.platform.col(j)),
                     settings_.leg_diameter_mm});
    }
  }
}

std::string LegLimits::why(const LegEnds& ends, const Status& status, const char* leg_word) const {
  if (status.code != StatusCode::joint_angle && status.code != StatusCode::interference) return {};
  std::vector<MechanismLimit> values;
  append_values(ends, values);
  // The worst value of the failing leg: the one check() stopped at, or one as bad.
  const MechanismLimit* worst = nullptr;
  for (const MechanismLimit& limit : values) {
    if (limit.code != status.code || limit.leg != status.joint) continue;
    if (worst == nullptr || limit.margin() < worst->margin()) worst = &limit;
  }
  if (worst == nullptr) return {};
  const std::string leg = std::string(leg_word) + " " + std::to_string(worst->leg + 1);
  if (worst->code == StatusCode::joint_angle) {
    const char* end = worst->other == kInnerEnd ? "inner (base or carriage)" : "platform";
    return "the " + std::string(end) + " joint of " + leg + " is at " +
           formatted_number("%.3f", geometry::radians_to_degrees(worst->value)) +
           " deg from its axis, beyond max_joint_angle " +
           formatted_number("%g", geometry::radians_to_degrees(worst->limit)) + " deg";
  }
  return std::string(leg_word) + "s " + std::to_string(worst->leg + 1) + " and " +
         std::to_string(worst->other + 1) + " are " + formatted_number("%.3f", worst->value) +
         " mm apart (axis to axis), closer than leg_diameter " +
         formatted_number("%g", worst->limit) + " mm";
}

// Closest points of two segments: minimise |p0 + s u - q0 - t v| over s, t in [0, 1]; the
// unconstrained minimum clamped to the square, then each parameter re-optimised given the other
// (the minimum of a convex quadratic over a square lies on the clamped lines).
double segment_distance(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                        const Eigen::Vector3d& q0, const Eigen::Vector3d& q1) {
  const Eigen::Vector3d u = p1 - p0, v = q1 - q0, w = p0 - q0;
  const double a = u.squaredNorm(), b = u.dot(v), c = v.squaredNorm();
  const double d = u.dot(w), e = v.dot(w);
  const double denominator = a * c - b * b;
  double s = 0.0;
  // Parallel (or degenerate) segments: any s will do for the first guess.
  if (denominator > 1e-12 * a * c) s = std::clamp((b * e - c * d) / denominator, 0.0, 1.0);
  double t = c > 0.0 ? std::clamp((b * s + e) / c, 0.0, 1.0) : 0.0;
  s = a > 0.0 ? std::clamp((b * t - d) / a, 0.0, 1.0) : 0.0;
  t = c > 0.0 ? std::clamp((b * s + e) / c, 0.0, 1.0) : 0.0;
  return (w + s * u - t * v).norm();
}

}  // namespace pkm::kinematics
