// The planner's speed profiles (internal to motion/): a change of speed at an acceleration limit,
// optionally a jerk limit (S-curves), and a move's profile of acceleration, cruise and braking.
#pragma once

namespace pkm::motion {

// A change of speed at an acceleration limit and, optionally, a jerk limit (0: none). With a jerk
// limit the acceleration rises and falls linearly (an S-curve); its velocity is symmetric about
// the ramp's middle, so a ramp covers the mean of its two speeds times its duration.
struct Ramp {
  double acceleration = 0.0;
  double jerk = 0.0;

  // The acceleration reached and the time at constant acceleration, for a change of `change`.
  void shape(double change, double& peak_acceleration, double& jerk_s, double& constant_s) const;
  double time(double from, double to) const;
  double distance(double from, double to) const { return 0.5 * (from + to) * time(from, to); }
  // The highest speed reachable from `from` within `length` (or the highest speed from which
  // `from` can be reached: the same by symmetry).
  double reachable(double from, double length) const;
  // Distance covered `t` seconds into the ramp from `from` to `to`.
  double position(double from, double to, double t) const;
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
  double distance(double t) const;
};

}  // namespace pkm::motion
