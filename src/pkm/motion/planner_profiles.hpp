// The planner's speed profiles (internal to motion/): a change of speed at an acceleration limit,
// optionally a jerk limit (S-curves), and a move's profile of acceleration, cruise and braking.
// Inline: the profile's search and the samples call them in their inner loops.
#pragma once

#include <algorithm>
#include <cmath>

namespace pkm::motion {

// A change of speed at an acceleration limit and, optionally, a jerk limit (0: none). With a jerk
// limit the acceleration rises and falls linearly (an S-curve); its velocity is symmetric about
// the ramp's middle, so a ramp covers the mean of its two speeds times its duration.
struct Ramp {
  double acceleration = 0.0;
  double jerk = 0.0;

  // The acceleration reached and the time at constant acceleration, for a change of `change`.
  void shape(double change, double& peak_acceleration, double& jerk_s, double& constant_s) const {
    peak_acceleration =
        jerk > 0.0 ? std::min(acceleration, std::sqrt(change * jerk)) : acceleration;
    jerk_s = jerk > 0.0 ? peak_acceleration / jerk : 0.0;
    constant_s = peak_acceleration > 0.0 ? std::max(0.0, change / peak_acceleration - jerk_s) : 0.0;
  }
  double time(double from, double to) const {
    double peak = 0.0, jerk_s = 0.0, constant_s = 0.0;
    shape(std::abs(to - from), peak, jerk_s, constant_s);
    return 2.0 * jerk_s + constant_s;
  }
  double distance(double from, double to) const { return 0.5 * (from + to) * time(from, to); }
  // The highest speed reachable from `from` within `length` (or the highest speed from which
  // `from` can be reached: the same by symmetry).
  double reachable(double from, double length) const {
    if (jerk <= 0.0) return std::sqrt(from * from + 2.0 * acceleration * length);
    double low = from, high = from + std::sqrt(2.0 * acceleration * length) + 1.0;
    for (int i = 0; i < 60; ++i) {
      const double middle = 0.5 * (low + high);
      (distance(from, middle) <= length ? low : high) = middle;
    }
    return low;
  }
  // Distance covered `t` seconds into the ramp from `from` to `to`.
  double position(double from, double to, double t) const {
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
};

// Speed profile along one piece: from the entry speed up to the peak, cruise, and down to the
// exit speed. The planner's passes guarantee that the exit speed can be reached from the entry
// speed within the piece.
struct Profile {
  double length = 0.0, entry_speed = 0.0, peak_speed = 0.0, exit_speed = 0.0;
  Ramp ramp;
  double accelerate_s = 0.0, cruise_s = 0.0, brake_s = 0.0, duration_s = 0.0;
  double accelerate_mm = 0.0, cruise_mm = 0.0;

  static Profile make(double length, double entry, double exit, double max_speed, const Ramp& ramp);
  // Distance covered `t` seconds into the piece (once per sample: allocates nothing).
  double distance(double t) const {
    if (t <= 0.0) return 0.0;
    if (t >= duration_s) return length;
    if (t < accelerate_s) return ramp.position(entry_speed, peak_speed, t);
    if (t < accelerate_s + cruise_s) return accelerate_mm + peak_speed * (t - accelerate_s);
    const double braking = t - accelerate_s - cruise_s;
    return std::min(length,
                    accelerate_mm + cruise_mm + ramp.position(peak_speed, exit_speed, braking));
  }
};

}  // namespace pkm::motion
