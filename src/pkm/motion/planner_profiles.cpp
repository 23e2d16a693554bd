#include "pkm/motion/planner_profiles.hpp"

#include <algorithm>
#include <cmath>

namespace pkm::motion {

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

}  // namespace pkm::motion
