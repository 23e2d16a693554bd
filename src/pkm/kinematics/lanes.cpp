#include "pkm/kinematics/lanes.hpp"

#include <atomic>

namespace pkm::lanes {

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

#if PKM_HAS_AVX2_LANES
PKM_AVX2 void sin_cos_3_avx2(const double angles[3], double sines[3], double cosines[3]) {
  const Lanes4 x = _mm256_set_pd(0.0, angles[2], angles[1], angles[0]);
  const Lanes4 s = sin(x);
  const Lanes4 c = cos(x);
  for (int k = 0; k < 3; ++k) {
    sines[k] = s[k];
    cosines[k] = c[k];
  }
}

PKM_AVX2 void sqrt_6_avx2(const double squares[6], double roots[6]) {
  _mm256_storeu_pd(roots, _mm256_sqrt_pd(_mm256_loadu_pd(squares)));
  _mm_storeu_pd(roots + 4, _mm_sqrt_pd(_mm_loadu_pd(squares + 4)));
}
#endif
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

void sqrt_6(const double squares[6], double roots[6]) {
#if PKM_HAS_AVX2_LANES
  if (avx2_enabled()) {
    sqrt_6_avx2(squares, roots);
    return;
  }
#endif
  for (int k = 0; k < 6; ++k) roots[k] = std::sqrt(squares[k]);
}

}  // namespace pkm::lanes
