#include "pkm/kinematics/lanes.hpp"

#include <atomic>

namespace pkm::kinematics::lanes {

namespace {
bool cpu_has_avx2() {
#if PKM_HAS_AVX2_LANES
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#else
  return false;
#endif
}

std::atomic<bool>& enabled_flag() {
  static std::atomic<bool> flag{cpu_has_avx2()};
  return flag;
}

}  // namespace

bool avx2_enabled() {
  return enabled_flag().load(std::memory_order_relaxed);
}

bool set_avx2_enabled(bool enabled) {
  return enabled_flag().exchange(enabled && cpu_has_avx2());
}

void sin_cos_3(const double angles[3], double sines[3], double cosines[3]) {
#if PKM_HAS_AVX2_LANES
  if (avx2_enabled()) {
    sin_cos_3_avx2(angles, sines, cosines);
    return;
  }
#endif
  for (int k = 0; k < 3; ++k) {
    sines[k] = std::sin(angles[k]);
    cosines[k] = std::cos(angles[k]);
  }
}

}  // namespace pkm::kinematics::lanes
