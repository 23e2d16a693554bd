#include "pkm/motion/planner_profiles.hpp"

#include <algorithm>
#include <cmath>

namespace pkm::motion {

void Ramp::shape(double change, double& peak_acceleration, double& jerk_s,
                 double& constant_s) const {
  peak_acceleration = jerk > 0.0 ? std::min(acceleration, std::sqrt(change * jerk)) : acceleration;
  jerk_s = jerk > 0.0 ? peak_acceleration / jerk : 0.0;
  constant_s = peak_acceleration > 0.0 ? std::max(0.0, change / peak_acceleration - jerk_s) : 0.0;
}

double Ramp::time(double from, double to) const {
  double peak = 0.0, jerk_s = 0.0, constant_s = 0.0;
  shape(std::abs(to - from), peak, jerk_s, constant_s);
  return 2.0 * jerk_s + constant_s;
}

double Ramp::reachable(double from, double length) const {
  if (jerk <= 0.0) return std::sqrt(from * from + 2.0 * acceleration * length);
  double low = from, high = from + std::sqrt(2.0 * acceleration * length) + 1.0;
  for (int i = 0; i < 60; ++i) {
    const double middle = 0.5 * (low + high);
    (distance(from, middle) <= length ? low : high) = middle;
  }
  return low;
}

double Ramp::position(double from, double to, double t) const {
  const double sign = to >= from ? 1.0 : -1.0;
  double peak = 0.0, jerk_s = 0.0, constant_s = 0.0;
  shape(std::abs(to - from), peak, jerk_s, constant_s);
  if (jerk_s == 0.0) return from * t + 0.5 * sign * peak * t * t;
  const double j = sign * jerk;
  if (t <= jerk_s) return from * t + j * t * t * t / 6.0;
  const double v1 = from + 0.5 * j * jerk_s * jerk_s;
  const double x1 = from * jerk_s + j * jerk_s * jerk_s * jerk_s / 6.0;
  if (t <= jerk_s + constant_s) {
    const double u = t - jerk_s;
    return x1 + v1 * u + 0.5 * sign * peak * u * u;
  }
  const double v2 = v1 + sign * peak * constant_s;
  const double x2 = x1 + v1 * constant_s + 0.5 * sign * peak * constant_s * constant_s;
  const double u = std::min(t - jerk_s - constant_s, jerk_s);
  return x2 + v2 * u + 0.5 * sign * peak * u * u - j * u * u * u / 6.0;
}

Profile Profile::make(double length, double entry, double exit, double max_speed,
                      const Ramp& ramp) {
  Profile p;
  p.length = length;
  p.entry_speed = entry;
  p.exit_speed = exit;
  p.ramp = ramp;
  if (length <= 0.0) return p;
  const auto fits = [&](double peak) {
    return ramp.distance(entry, peak) + ramp.distance(peak, exit) <= length;
  };
  double low = std::max(entry, exit), high = std::max(low, max_speed);
  if (fits(high)) {
    low = high;
  } else {
    for (int i = 0; i < 60; ++i) {
      const double middle = 0.5 * (low + high);
      (fits(middle) ? low : high) = middle;
    }
  }
  p.peak_speed = low;
  p.accelerate_s = ramp.time(entry, p.peak_speed);
  p.brake_s = ramp.time(p.peak_speed, exit);
  p.accelerate_mm = ramp.distance(entry, p.peak_speed);
  p.cruise_mm = std::max(0.0, length - p.accelerate_mm - ramp.distance(p.peak_speed, exit));
  p.cruise_s = p.peak_speed > 0.0 ? p.cruise_mm / p.peak_speed : 0.0;
  p.duration_s = p.accelerate_s + p.cruise_s + p.brake_s;
  return p;
}

double Profile::distance(double t) const {
  if (t <= 0.0) return 0.0;
  if (t >= duration_s) return length;
  if (t < accelerate_s) return ramp.position(entry_speed, peak_speed, t);
  if (t < accelerate_s + cruise_s) return accelerate_mm + peak_speed * (t - accelerate_s);
  const double braking = t - accelerate_s - cruise_s;
  return std::min(length,
                  accelerate_mm + cruise_mm + ramp.position(peak_speed, exit_speed, braking));
}

}  // namespace pkm::motion
