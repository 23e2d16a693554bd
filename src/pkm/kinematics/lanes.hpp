// Four poses at once: the AVX2 lanes the models' batch entry points compute in, with the sines and
// cosines of glibc's libmvec (its vector ABI, _ZGVdN4v_sin and _ZGVdN4v_cos, accurate to 4 ulp).
// Chosen at run time: the library is built for plain x86-64 and only functions marked PKM_AVX2
// use AVX2 and FMA, so the same binary runs, on the scalar paths, where the CPU has no AVX2.
// Models write their arithmetic once, as a template over the lane type (double or Lanes4), so
// the scalar and vector paths do the same operations in the same order, but for the products the
// lanes fuse into their sums where a model asks for it (row_times_add, squared_norm).
#pragma once

#include <cmath>
#include <cstddef>

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__)) && defined(__GLIBC__)
#define PKM_HAS_AVX2_LANES 1
#include <immintrin.h>
#else
#define PKM_HAS_AVX2_LANES 0
#endif

namespace pkm::kinematics::lanes {

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
// Six coordinates of four records of six doubles each, from `records` on (four poses): out[c]
// lane k = records[6 k + c]. Four 4x4 and 2x4 transposes instead of 24 single loads.
PKM_AVX2 inline void load_6_by_4(const double* records, Lanes4 (&out)[6]) {
  const Lanes4 r0 = _mm256_loadu_pd(records), r1 = _mm256_loadu_pd(records + 6);
  const Lanes4 r2 = _mm256_loadu_pd(records + 12), r3 = _mm256_loadu_pd(records + 18);
  const Lanes4 t0 = _mm256_unpacklo_pd(r0, r1), t1 = _mm256_unpackhi_pd(r0, r1);
  const Lanes4 t2 = _mm256_unpacklo_pd(r2, r3), t3 = _mm256_unpackhi_pd(r2, r3);
  out[0] = _mm256_permute2f128_pd(t0, t2, 0x20);
  out[1] = _mm256_permute2f128_pd(t1, t3, 0x20);
  out[2] = _mm256_permute2f128_pd(t0, t2, 0x31);
  out[3] = _mm256_permute2f128_pd(t1, t3, 0x31);
  const Lanes4 h01 = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(records + 4)),
                                          _mm_loadu_pd(records + 16), 1);  // r0 r2 [4..5]
  const Lanes4 h23 = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(records + 10)),
                                          _mm_loadu_pd(records + 22), 1);  // r1 r3 [4..5]
  out[4] = _mm256_unpacklo_pd(h01, h23);
  out[5] = _mm256_unpackhi_pd(h01, h23);
}

// The next block of records of six doubles, `available` of them left from `records` on, into
// lanes as load_6_by_4 does; a last partial block repeats its last record in the spare lanes.
// Returns how many lanes hold records of their own.
PKM_AVX2 inline std::size_t load_block_6_by_4(const double* records, std::size_t available,
                                              Lanes4 (&out)[6]) {
  const std::size_t used = available < kLanes ? available : std::size_t{kLanes};
  if (used == kLanes) {
    load_6_by_4(records, out);
    return used;
  }
  double tail[kLanes * 6];
  for (std::size_t k = 0; k < kLanes; ++k) {
    const double* record = records + 6 * (k < used ? k : used - 1);
    for (int c = 0; c < 6; ++c) tail[6 * k + static_cast<std::size_t>(c)] = record[c];
  }
  load_6_by_4(tail, out);
  return used;
}

// Poses in blocks of four, a chunk of blocks at a time: their coordinates in lanes and the sines
// and cosines of their angles. The vector calls for a whole chunk's sines and cosines come first
// and the models' arithmetic after them, so the calls run back to back at the library's
// throughput instead of each waiting for the arithmetic of its own block (measured: hexapod
// batch IK 11.1 ns per pose one block at a time).
struct PoseChunk {
  static constexpr std::size_t kBlocks = 8;
  std::size_t blocks = 0;          // blocks filled
  std::size_t used[kBlocks] = {};  // lanes holding poses of their own, per block
  Lanes4 coordinates[kBlocks][6];  // x y z a b c
  Lanes4 sines[kBlocks][3];        // of a b c, where asked for
  Lanes4 cosines[kBlocks][3];
};

// The next chunk of records of six doubles (poses), `available` of them from `records` on; the
// sines and cosines of coordinates 3..5 only `with_angles`.
PKM_AVX2 inline void load_pose_chunk(const double* records, std::size_t available, bool with_angles,
                                     PoseChunk& chunk) {
  std::size_t taken = 0;
  chunk.blocks = 0;
  while (taken < available && chunk.blocks < PoseChunk::kBlocks) {
    const std::size_t block = chunk.blocks++;
    chunk.used[block] =
        load_block_6_by_4(records + 6 * taken, available - taken, chunk.coordinates[block]);
    taken += chunk.used[block];
  }
  if (!with_angles) return;
  for (std::size_t block = 0; block < chunk.blocks; ++block) {
    for (int k = 0; k < 3; ++k) {
      chunk.sines[block][k] = sin(chunk.coordinates[block][3 + k]);
      chunk.cosines[block][k] = cos(chunk.coordinates[block][3 + k]);
    }
  }
}

// The transpose back: six values of each of four records, out[k][c] = in[c] lane k.
PKM_AVX2 inline void store_6_by_4(const Lanes4 (&in)[6], double* const (&out)[4]) {
  const Lanes4 t0 = _mm256_unpacklo_pd(in[0], in[1]), t1 = _mm256_unpackhi_pd(in[0], in[1]);
  const Lanes4 t2 = _mm256_unpacklo_pd(in[2], in[3]), t3 = _mm256_unpackhi_pd(in[2], in[3]);
  _mm256_storeu_pd(out[0], _mm256_permute2f128_pd(t0, t2, 0x20));
  _mm256_storeu_pd(out[1], _mm256_permute2f128_pd(t1, t3, 0x20));
  _mm256_storeu_pd(out[2], _mm256_permute2f128_pd(t0, t2, 0x31));
  _mm256_storeu_pd(out[3], _mm256_permute2f128_pd(t1, t3, 0x31));
  const Lanes4 t4 = _mm256_unpacklo_pd(in[4], in[5]), t5 = _mm256_unpackhi_pd(in[4], in[5]);
  _mm_storeu_pd(out[0] + 4, _mm256_castpd256_pd128(t4));
  _mm_storeu_pd(out[1] + 4, _mm256_castpd256_pd128(t5));
  _mm_storeu_pd(out[2] + 4, _mm256_extractf128_pd(t4, 1));
  _mm_storeu_pd(out[3] + 4, _mm256_extractf128_pd(t5, 1));
}

// Bit k set where lane k is not above `limit`: at or below it, or NaN.
PKM_AVX2 inline int lanes_not_above(Lanes4 x, double limit) {
  return _mm256_movemask_pd(_mm256_cmp_pd(x, _mm256_set1_pd(limit), _CMP_NGT_UQ));
}
// Bit k set where lane k is not above lane k of `limit`: at or below it, or NaN.
PKM_AVX2 inline int lanes_not_above(Lanes4 x, Lanes4 limit) {
  return _mm256_movemask_pd(_mm256_cmp_pd(x, limit, _CMP_NGT_UQ));
}
// Bit k set where lane k is finite (x - x is 0 there, NaN for an infinity or a NaN).
PKM_AVX2 inline int lanes_finite(Lanes4 x) {
  return _mm256_movemask_pd(_mm256_cmp_pd(x - x, _mm256_setzero_pd(), _CMP_EQ_OQ));
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
  // Built from the values (in registers when inlined), not loaded: a 32-byte load of values just
  // stored one by one stalls on store forwarding.
  const Lanes4 low = sqrt(_mm256_set_pd(squares[3], squares[2], squares[1], squares[0]));
  const __m128d high = _mm_sqrt_pd(_mm_set_pd(squares[5], squares[4]));
  for (int k = 0; k < 4; ++k) roots[k] = low[k];
  roots[4] = high[0];
  roots[5] = high[1];
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

// Row `row` of r times v, plus offset; and a vector's squared norm: one pose's or, as the overloads
// below, four poses'. The scalar paths round every product and sum as they always have (the
// library is built without FMA contraction, so results do not depend on the compiler's choices);
// the lanes fuse each product into its sum, one rounding instead of two and fewer instructions,
// which leaves the two paths a few ulp apart (within 1e-12 mm, tested).
[[gnu::always_inline]] inline void row_times_add(const double* row, const double* v, double offset,
                                                 double& out) {
  out = (row[0] * v[0] + row[1] * v[1] + row[2] * v[2]) + offset;
}
[[gnu::always_inline]] inline void squared_norm(const double (&v)[3], double& out) {
  out = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
}
#if PKM_HAS_AVX2_LANES
PKM_AVX2 inline void row_times_add(const Lanes4* row, const double* v, const Lanes4& offset,
                                   Lanes4& out) {
  out = _mm256_fmadd_pd(row[0], _mm256_set1_pd(v[0]), offset);
  out = _mm256_fmadd_pd(row[1], _mm256_set1_pd(v[1]), out);
  out = _mm256_fmadd_pd(row[2], _mm256_set1_pd(v[2]), out);
}
PKM_AVX2 inline void squared_norm(const Lanes4 (&v)[3], Lanes4& out) {
  out = _mm256_fmadd_pd(v[0], v[0], _mm256_fmadd_pd(v[1], v[1], v[2] * v[2]));
}
#endif

inline double sqrt(double x) {
  return std::sqrt(x);
}

}  // namespace pkm::kinematics::lanes
