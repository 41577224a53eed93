// The Lambert lanes and the BRDF lanes with AVX2: integrators/lambert_kernel.h on eight lanes per
// instruction, run twice for the sixteen lanes of a LambertIn or a BrdfIn. Everything below the
// pragma is compiled for AVX2 (not FMA: a fused multiply-add rounds once where the kernel rounds
// twice) and called only where the CPU has it.
#include <immintrin.h>

#include <bit>
#include <cmath>
#include <cstdint>

#include "dacrt/integrators/lambert_lanes.h"

namespace dacrt {

#pragma GCC push_options
#pragma GCC target("avx2")

namespace {

// A lane mask (all bits set in a taken lane), and eight floats.
struct M8 {
  __m256 m;
};
inline M8 operator&(M8 a, M8 b) {
  return {_mm256_and_ps(a.m, b.m)};
}
inline M8 operator|(M8 a, M8 b) {
  return {_mm256_or_ps(a.m, b.m)};
}
inline M8& operator&=(M8& a, M8 b) {
  return a = a & b;
}
inline M8 unmask(M8 a) {
  return {_mm256_xor_ps(a.m, _mm256_castsi256_ps(_mm256_set1_epi32(-1)))};
}

struct V8 {
  __m256 v;
  V8() = default;
  V8(float f) : v(_mm256_set1_ps(f)) {}
  V8(__m256 x) : v(x) {}
};
inline V8 operator+(V8 a, V8 b) {
  return _mm256_add_ps(a.v, b.v);
}
inline V8 operator-(V8 a, V8 b) {
  return _mm256_sub_ps(a.v, b.v);
}
inline V8 operator*(V8 a, V8 b) {
  return _mm256_mul_ps(a.v, b.v);
}
inline V8 operator/(V8 a, V8 b) {
  return _mm256_div_ps(a.v, b.v);
}
inline V8 operator-(V8 a) {
  return _mm256_xor_ps(a.v, _mm256_set1_ps(-0.f));
}
inline M8 operator<(V8 a, V8 b) {
  return {_mm256_cmp_ps(a.v, b.v, _CMP_LT_OQ)};
}
inline M8 operator<=(V8 a, V8 b) {
  return {_mm256_cmp_ps(a.v, b.v, _CMP_LE_OQ)};
}
inline M8 operator>(V8 a, V8 b) {
  return {_mm256_cmp_ps(a.v, b.v, _CMP_GT_OQ)};
}
inline M8 operator>=(V8 a, V8 b) {
  return {_mm256_cmp_ps(a.v, b.v, _CMP_GE_OQ)};
}
inline M8 operator==(V8 a, V8 b) {
  return {_mm256_cmp_ps(a.v, b.v, _CMP_EQ_OQ)};
}
inline M8 operator!=(V8 a, V8 b) {
  return {_mm256_cmp_ps(a.v, b.v, _CMP_NEQ_UQ)};
}
// minps/maxps: the second operand on a tie or a NaN, as the one-float vmin and vmax.
inline V8 vmin(V8 a, V8 b) {
  return _mm256_min_ps(a.v, b.v);
}
inline V8 vmax(V8 a, V8 b) {
  return _mm256_max_ps(a.v, b.v);
}
inline V8 vabs(V8 a) {
  return _mm256_andnot_ps(_mm256_set1_ps(-0.f), a.v);
}
inline V8 vsqrt(V8 a) {
  return _mm256_sqrt_ps(a.v);
}
inline V8 sel(M8 m, V8 a, V8 b) {
  return _mm256_blendv_ps(b.v, a.v, m.m);
}
// tracer/ray.h's next_float_up: one step away from 0 for positive values, towards it for
// negative ones, the smallest denormal for ±0.
inline V8 next_up(V8 x) {
  const __m256i bits = _mm256_castps_si256(x.v);
  const __m256i positive =
      _mm256_castps_si256(_mm256_cmp_ps(x.v, _mm256_setzero_ps(), _CMP_GT_OQ));
  // bits + 1 where positive (positive is −1 there), bits − 1 elsewhere.
  const __m256i step = _mm256_or_si256(positive, _mm256_set1_epi32(1));
  const __m256i stepped = _mm256_sub_epi32(bits, step);
  const __m256 zero = _mm256_cmp_ps(x.v, _mm256_setzero_ps(), _CMP_EQ_OQ);
  return _mm256_blendv_ps(_mm256_castsi256_ps(stepped), _mm256_set1_ps(0x1p-149f), zero);
}
inline V8 next_down(V8 x) {
  return -next_up(-x);
}
// std::cos and std::sin, lane by lane.
inline void vcos_sin(V8 x, V8& c, V8& s) {
  alignas(32) float in[8], cos[8], sin[8];
  _mm256_store_ps(in, x.v);
  for (int k = 0; k < 8; ++k) cos[k] = std::cos(in[k]), sin[k] = std::sin(in[k]);
  c = _mm256_load_ps(cos), s = _mm256_load_ps(sin);
}

}  // namespace
}  // namespace dacrt

#include "dacrt/integrators/lambert_kernel.h"

namespace dacrt {
namespace {

// Lanes k … k + 7 of the arrays (k is 0 or 8: 32-byte aligned).
struct EightLanes {
  using F = V8;
  static V8 load(const float* a, int k) { return _mm256_load_ps(a + k); }
  static void store(float* a, int k, V8 v) { _mm256_store_ps(a + k, v.v); }
  static void mask(uint32_t& m, int k, M8 b) {
    m |= uint32_t(_mm256_movemask_ps(b.m)) << k;
  }
};

}  // namespace

void shade_lambert_avx2(const LambertScene& scene, const LambertIn& in, int lanes,
                        LambertOut& out) {
  out.taken = out.shadow = out.bounce = 0;
  lambert_vertex<EightLanes>(scene, in, 0, out);
  if (lanes > 8) lambert_vertex<EightLanes>(scene, in, 8, out);
}

void sample_brdf_avx2(const BrdfIn& in, int lanes, BrdfOut& out) {
  out.sampled = 0;
  brdf_sample<EightLanes>(in, 0, out);
  if (lanes > 8) brdf_sample<EightLanes>(in, 8, out);
}

#pragma GCC pop_options

}  // namespace dacrt
