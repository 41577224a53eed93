// The Lambert lanes with AVX-512: integrators/lambert_kernel.h on sixteen lanes per instruction.
// Everything below the pragma is compiled for AVX512F and AVX512DQ and called only where the CPU
// has them.
#include <immintrin.h>

#include <bit>
#include <cstdint>

#include "dacrt/integrators/lambert_lanes.h"

namespace dacrt {

bool lambert_avx512_available() {
  static const bool yes = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq");
  return yes;
}

#pragma GCC push_options
#pragma GCC target("avx512f,avx512dq")
// GCC 12's AVX-512 headers start masked intrinsics from _mm512_undefined_*(), which
// -Wmaybe-uninitialized reports once inlined (GCC bug 105593, fixed in GCC 13).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"

namespace {

// A lane mask, and sixteen floats.
struct M16 {
  __mmask16 m;
};
inline M16 operator&(M16 a, M16 b) {
  return {__mmask16(a.m & b.m)};
}
inline M16 operator|(M16 a, M16 b) {
  return {__mmask16(a.m | b.m)};
}
inline M16& operator&=(M16& a, M16 b) {
  return a = a & b;
}
inline M16 unmask(M16 a) {
  return {__mmask16(~a.m)};
}

struct V16 {
  __m512 v;
  V16() = default;
  V16(float f) : v(_mm512_set1_ps(f)) {}
  V16(__m512 x) : v(x) {}
};
inline V16 operator+(V16 a, V16 b) {
  return _mm512_add_ps(a.v, b.v);
}
inline V16 operator-(V16 a, V16 b) {
  return _mm512_sub_ps(a.v, b.v);
}
inline V16 operator*(V16 a, V16 b) {
  return _mm512_mul_ps(a.v, b.v);
}
inline V16 operator/(V16 a, V16 b) {
  return _mm512_div_ps(a.v, b.v);
}
inline V16 operator-(V16 a) {
  return _mm512_xor_ps(a.v, _mm512_set1_ps(-0.f));
}
inline M16 operator<(V16 a, V16 b) {
  return {_mm512_cmp_ps_mask(a.v, b.v, _CMP_LT_OQ)};
}
inline M16 operator<=(V16 a, V16 b) {
  return {_mm512_cmp_ps_mask(a.v, b.v, _CMP_LE_OQ)};
}
inline M16 operator>(V16 a, V16 b) {
  return {_mm512_cmp_ps_mask(a.v, b.v, _CMP_GT_OQ)};
}
inline M16 operator>=(V16 a, V16 b) {
  return {_mm512_cmp_ps_mask(a.v, b.v, _CMP_GE_OQ)};
}
inline M16 operator!=(V16 a, V16 b) {
  return {_mm512_cmp_ps_mask(a.v, b.v, _CMP_NEQ_UQ)};
}
inline V16 vmin(V16 a, V16 b) {
  return _mm512_min_ps(a.v, b.v);
}
inline V16 vmax(V16 a, V16 b) {
  return _mm512_max_ps(a.v, b.v);
}
inline V16 vabs(V16 a) {
  return _mm512_abs_ps(a.v);
}
inline V16 vsqrt(V16 a) {
  return _mm512_sqrt_ps(a.v);
}
inline V16 sel(M16 m, V16 a, V16 b) {
  return _mm512_mask_blend_ps(m.m, b.v, a.v);
}
// tracer/ray.h's next_float_up: one step away from 0 for positive values, towards it for
// negative ones, the smallest denormal for ±0.
inline V16 next_up(V16 x) {
  const __m512i bits = _mm512_castps_si512(x.v);
  const __mmask16 positive = _mm512_cmp_ps_mask(x.v, _mm512_setzero_ps(), _CMP_GT_OQ);
  const __m512i one = _mm512_set1_epi32(1);
  const __m512i stepped = _mm512_mask_add_epi32(_mm512_sub_epi32(bits, one), positive, bits, one);
  const __mmask16 zero = _mm512_cmp_ps_mask(x.v, _mm512_setzero_ps(), _CMP_EQ_OQ);
  return _mm512_mask_blend_ps(zero, _mm512_castsi512_ps(stepped), _mm512_set1_ps(0x1p-149f));
}
inline V16 next_down(V16 x) {
  return -next_up(-x);
}

}  // namespace
}  // namespace dacrt

#include "dacrt/integrators/lambert_kernel.h"

namespace dacrt {
namespace {

struct SixteenLanes {
  using F = V16;
  static V16 load(const float* a, int) { return _mm512_load_ps(a); }
  static void store(float* a, int, V16 v) { _mm512_store_ps(a, v.v); }
  static void mask(uint32_t& m, int, M16 b) { m = b.m; }
};

}  // namespace

void shade_lambert_avx512(const LambertScene& scene, const LambertIn& in, LambertOut& out) {
  lambert_vertex<SixteenLanes>(scene, in, 0, out);
}

#pragma GCC diagnostic pop
#pragma GCC pop_options

}  // namespace dacrt
