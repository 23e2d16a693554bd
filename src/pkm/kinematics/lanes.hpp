// Four poses at once: the AVX2 lanes the models' batch entry points compute in, with the sines and
// cosines of glibc's libmvec (its vector ABI, _ZGVdN4v_sin and _ZGVdN4v_cos, accurate to 4 ulp).
// Chosen at run time: the library is built for plain x86-64 and only functions marked PKM_AVX2
// use AVX2 and FMA, so the same binary runs, on the scalar paths, where the CPU has no AVX2.
// Models write their arithmetic once, as a template over the lane type (double or Lanes4), so
// the scalar and vector paths do the same operations in the same order.
#pragma once

#include <cmath>

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__)) && defined(__GLIBC__)
#define PKM_HAS_AVX2_LANES 1
#include <immintrin.h>
#else
#define PKM_HAS_AVX2_LANES 0
#endif

namespace pkm::lanes {

// Whether the vector paths run: the CPU has AVX2 and FMA, and nothing turned them off.
bool avx2_enabled();
// Turns the vector paths off (false) or back on where the CPU has them; returns the previous
// state. For tests and benchmarks that compare the two paths; not for concurrent use.
bool set_avx2_enabled(bool enabled);

// The sines and cosines of three angles (rad) through one vector call each where AVX2 runs,
// std::sin and std::cos otherwise.
void sin_cos_3(const double angles[3], double sines[3], double cosines[3]);

#if PKM_HAS_AVX2_LANES
#define PKM_AVX2 __attribute__((target("avx2,fma")))
using Lanes4 = __m256d;  // GCC and Clang give it + - * / and [lane]
inline constexpr int kLanes = 4;

extern "C" PKM_AVX2 __m256d _ZGVdN4v_sin(__m256d);  // NOLINT: glibc's libmvec names
extern "C" PKM_AVX2 __m256d _ZGVdN4v_cos(__m256d);  // NOLINT

PKM_AVX2 inline Lanes4 sin(Lanes4 x) {
  return _ZGVdN4v_sin(x);
}
PKM_AVX2 inline Lanes4 cos(Lanes4 x) {
  return _ZGVdN4v_cos(x);
}
PKM_AVX2 inline Lanes4 sqrt(Lanes4 x) {
  return _mm256_sqrt_pd(x);
}
// Lane k = values[k * stride]: one coordinate of four consecutive records (poses).
PKM_AVX2 inline Lanes4 gather(const double* values, int stride) {
  return _mm256_set_pd(values[3 * stride], values[2 * stride], values[stride], values[0]);
}
// Bit k set where lane k is not above `limit`: at or below it, or NaN.
PKM_AVX2 inline int lanes_not_above(Lanes4 x, double limit) {
  return _mm256_movemask_pd(_mm256_cmp_pd(x, _mm256_set1_pd(limit), _CMP_NGT_UQ));
}
PKM_AVX2 inline Lanes4 zero() {
  return _mm256_setzero_pd();
}
// sin_cos_3 for callers that are AVX2 code themselves.
PKM_AVX2 inline void sin_cos_3_avx2(const double angles[3], double sines[3], double cosines[3]) {
  const Lanes4 x = _mm256_set_pd(0.0, angles[2], angles[1], angles[0]);
  const Lanes4 s = sin(x);
  const Lanes4 c = cos(x);
  for (int k = 0; k < 3; ++k) {
    sines[k] = s[k];
    cosines[k] = c[k];
  }
}
// The square roots of six numbers (a hexapod's legs) in two vector square roots: bit for bit
// std::sqrt's (IEEE square roots are correctly rounded).
PKM_AVX2 inline void sqrt_6_avx2(const double squares[6], double roots[6]) {
  _mm256_storeu_pd(roots, _mm256_sqrt_pd(_mm256_loadu_pd(squares)));
  _mm_storeu_pd(roots + 4, _mm_sqrt_pd(_mm_loadu_pd(squares + 4)));
}
#endif

// R = Rz(c) Ry(b) Rx(a) (geometry/pose.hpp), row-major, from the sines and cosines of a b c: one
// pose's (T = double) or four poses' (T = Lanes4). Always inlined, so the vector instance is
// compiled for AVX2 inside its PKM_AVX2 caller.
template <class T>
[[gnu::always_inline]] inline void rotation_abc(const T (&sines)[3], const T (&cosines)[3],
                                                T (&r)[9]) {
  const T& sa = sines[0];
  const T& sb = sines[1];
  const T& sc = sines[2];
  const T& ca = cosines[0];
  const T& cb = cosines[1];
  const T& cc = cosines[2];
  r[0] = cc * cb;
  r[1] = cc * sb * sa - sc * ca;
  r[2] = cc * sb * ca + sc * sa;
  r[3] = sc * cb;
  r[4] = sc * sb * sa + cc * ca;
  r[5] = sc * sb * ca - cc * sa;
  r[6] = -sb;
  r[7] = cb * sa;
  r[8] = cb * ca;
}

// r * v for a constant vector v (mm) of the model. (Results by reference: a function returning a
// Lanes4 by value has an ABI of its own outside AVX2 code.)
template <class T>
[[gnu::always_inline]] inline void rotate(const T* r, const double* v, T (&out)[3]) {
  for (int k = 0; k < 3; ++k) out[k] = r[3 * k] * v[0] + r[3 * k + 1] * v[1] + r[3 * k + 2] * v[2];
}

inline double sqrt(double x) {
  return std::sqrt(x);
}

}  // namespace pkm::lanes
