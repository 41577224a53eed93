// The vector watertight triangle filter, 8 lanes (AVX2) or 16 (AVX-512) per instruction (see
// triangle_block.h). Compiled for AVX2 by a function
// attribute and chosen at run time, so the library still runs on any x86-64 (and elsewhere).
#include "dacrt/tracer/triangle_block.h"

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#define DACRT_X86 1
#endif

namespace dacrt {

#ifdef DACRT_X86

__attribute__((target("avx2"))) inline __m256 abs8(__m256 v) {
  return _mm256_andnot_ps(_mm256_set1_ps(-0.f), v);
}
__attribute__((target("avx2"))) inline __m256 max3(const __m256* v) {
  return _mm256_max_ps(_mm256_max_ps(abs8(v[0]), abs8(v[1])), abs8(v[2]));
}

// decide16 on eight lanes (AVX2): the same operations in the same order, so the same t, e1, e2,
// det and the same sure, exact and unsure lanes (bits 0..7).
struct Lanes8 {
  __m256 t, e1, e2, det;
  uint32_t sure, exact, unsure;
};
__attribute__((target("avx2"))) inline uint32_t bits(__m256 m) {
  return uint32_t(_mm256_movemask_ps(m));
}
__attribute__((target("avx2"))) inline Lanes8 decide8(const __m256* x, const __m256* y,
                                                      const __m256* z, __m256 tmin, __m256 tmax,
                                                      uint32_t used) {
  const __m256 e0 = _mm256_sub_ps(_mm256_mul_ps(x[2], y[1]), _mm256_mul_ps(y[2], x[1]));
  const __m256 e1 = _mm256_sub_ps(_mm256_mul_ps(x[0], y[2]), _mm256_mul_ps(y[0], x[2]));
  const __m256 e2 = _mm256_sub_ps(_mm256_mul_ps(x[1], y[0]), _mm256_mul_ps(y[1], x[0]));
  const __m256 zero = _mm256_setzero_ps();
  const uint32_t any_zero = bits(_mm256_or_ps(
      _mm256_or_ps(_mm256_cmp_ps(e0, zero, _CMP_EQ_OQ), _mm256_cmp_ps(e1, zero, _CMP_EQ_OQ)),
      _mm256_cmp_ps(e2, zero, _CMP_EQ_OQ)));
  const uint32_t any_neg = bits(_mm256_or_ps(
      _mm256_or_ps(_mm256_cmp_ps(e0, zero, _CMP_LT_OQ), _mm256_cmp_ps(e1, zero, _CMP_LT_OQ)),
      _mm256_cmp_ps(e2, zero, _CMP_LT_OQ)));
  const uint32_t any_pos = bits(_mm256_or_ps(
      _mm256_or_ps(_mm256_cmp_ps(e0, zero, _CMP_GT_OQ), _mm256_cmp_ps(e1, zero, _CMP_GT_OQ)),
      _mm256_cmp_ps(e2, zero, _CMP_GT_OQ)));
  const __m256 det = _mm256_add_ps(_mm256_add_ps(e0, e1), e2);
  const __m256 abs_det = abs8(det);
  const __m256 inf = _mm256_set1_ps(INFINITY);
  const uint32_t det_ok =
      bits(_mm256_and_ps(_mm256_cmp_ps(abs_det, _mm256_set1_ps(0x1p-80f), _CMP_GE_OQ),
                         _mm256_cmp_ps(abs_det, inf, _CMP_LT_OQ)));
  const uint32_t inside = ~(any_neg & any_pos) & det_ok;
  const uint32_t unsure = (any_zero | (~det_ok & 0xffu)) & used;
  const uint32_t plain = inside & ~any_zero & used;
  // Most lanes of a leaf miss: when none is left, t and its error bound are not needed.
  if (!(plain | unsure)) return {zero, zero, zero, zero, 0, 0, 0};
  const __m256 t =
      _mm256_div_ps(_mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(e0, z[0]), _mm256_mul_ps(e1, z[1])),
                                  _mm256_mul_ps(e2, z[2])),
                    det);
  const __m256 max_x = max3(x), max_y = max3(y), max_z = max3(z);
  const __m256 max_e = _mm256_max_ps(_mm256_max_ps(abs8(e0), abs8(e1)), abs8(e2));
  constexpr auto gamma = [](int n) { return n * 0x1p-24f / (1.f - n * 0x1p-24f); };
  const __m256 g2 = _mm256_set1_ps(gamma(2)), g3 = _mm256_set1_ps(gamma(3)),
               g5 = _mm256_set1_ps(gamma(5));
  const __m256 delta_z = _mm256_mul_ps(g3, max_z);
  const __m256 delta_x = _mm256_mul_ps(g5, _mm256_add_ps(max_x, max_z));
  const __m256 delta_y = _mm256_mul_ps(g5, _mm256_add_ps(max_y, max_z));
  const __m256 delta_e =
      _mm256_mul_ps(_mm256_set1_ps(2.f),
                    _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(_mm256_mul_ps(g2, max_x), max_y),
                                                _mm256_mul_ps(delta_y, max_x)),
                                  _mm256_mul_ps(delta_x, max_y)));
  const __m256 bound =
      _mm256_mul_ps(_mm256_set1_ps(3.f * (1.f + 0x1p-20f)),
                    _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(_mm256_mul_ps(g3, max_e), max_z),
                                                _mm256_mul_ps(delta_e, max_z)),
                                  _mm256_mul_ps(delta_z, max_e)));
  const __m256 abs_t = abs8(t);
  const uint32_t in_range = bits(_mm256_and_ps(_mm256_cmp_ps(t, tmin, _CMP_GE_OQ),
                                               _mm256_cmp_ps(t, tmax, _CMP_LE_OQ)));
  const uint32_t finite = bits(_mm256_cmp_ps(abs_t, inf, _CMP_LT_OQ));
  const uint32_t beyond_error =
      bits(_mm256_cmp_ps(_mm256_mul_ps(abs_t, abs_det), bound, _CMP_GT_OQ));
  const uint32_t sure = plain & finite & beyond_error & in_range;
  const uint32_t exact = plain & ~(finite & beyond_error);
  return {t, e1, e2, det, sure, exact, unsure};
}

// block_hits_avx512 with AVX2: each half of the block's lanes by decide8.
__attribute__((target("avx2"))) void block_hits_avx2(const TriangleBlock& b, const Ray& r,
                                                     float tmin, float tmax, BlockHits& out) {
  const __m256 ox = _mm256_set1_ps(r.o[r.kx]), oy = _mm256_set1_ps(r.o[r.ky]),
               oz = _mm256_set1_ps(r.o[r.kz]);
  const __m256 sx = _mm256_set1_ps(r.sx), sy = _mm256_set1_ps(r.sy), sz = _mm256_set1_ps(r.sz);
  out.sure = out.exact = out.unsure = 0;
  for (int base = 0; base < b.n; base += 8) {
    __m256 x[3], y[3], z[3];
    for (int c = 0; c < 3; ++c) {
      const __m256 ax = _mm256_sub_ps(_mm256_load_ps(b.p[c][r.kx] + base), ox);
      const __m256 ay = _mm256_sub_ps(_mm256_load_ps(b.p[c][r.ky] + base), oy);
      const __m256 az = _mm256_sub_ps(_mm256_load_ps(b.p[c][r.kz] + base), oz);
      x[c] = _mm256_sub_ps(ax, _mm256_mul_ps(sx, az));
      y[c] = _mm256_sub_ps(ay, _mm256_mul_ps(sy, az));
      z[c] = _mm256_mul_ps(sz, az);
    }
    const uint32_t used = b.n - base >= 8 ? 0xffu : (1u << (b.n - base)) - 1u;
    const Lanes8 l = decide8(x, y, z, _mm256_set1_ps(tmin), _mm256_set1_ps(tmax), used);
    out.sure |= l.sure << base, out.exact |= l.exact << base, out.unsure |= l.unsure << base;
    _mm256_store_ps(out.t + base, l.t);
    _mm256_store_ps(out.e1 + base, l.e1);
    _mm256_store_ps(out.e2 + base, l.e2);
    _mm256_store_ps(out.det + base, l.det);
  }
}

// group_hits_avx512 on the first eight lanes of g (g.used <= 0xff), with AVX2.
__attribute__((target("avx2"))) int group_hits_avx2(const TriangleBlock* blocks, int nb,
                                                    RayGroup& g, bool any_hit, GroupHits& out) {
  const __m256 dz = _mm256_load_ps(g.d[2]);
  const __m256 sh[3] = {_mm256_div_ps(_mm256_load_ps(g.d[0]), dz),
                        _mm256_div_ps(_mm256_load_ps(g.d[1]), dz),
                        _mm256_div_ps(_mm256_set1_ps(1.f), dz)};
  __m256 o[3];
  for (int a = 0; a < 3; ++a) o[a] = _mm256_load_ps(g.o[a]), _mm256_store_ps(g.s[a], sh[a]);
  const __m256 tmin = _mm256_load_ps(g.tmin), tmax = _mm256_load_ps(g.tmax);
  const __m256 inf = _mm256_set1_ps(INFINITY);
  __m256 best_t = inf, best_e1 = _mm256_setzero_ps(), best_e2 = best_e1, best_det = best_e1;
  // The best triangle, biased by 2^31 so that a signed comparison orders it as unsigned.
  const __m256i bias = _mm256_set1_epi32(int32_t(0x80000000u));
  __m256i best_tri = _mm256_set1_epi32(int32_t(0x7fffffff));  // 0xffffffff, biased
  uint32_t occluded = 0;
  int tested = 0;
  out.odd_count = 0;
  for (int b = 0; b < nb; ++b) {
    const TriangleBlock& block = blocks[b];
    for (int l = 0; l < block.n; ++l, ++tested) {
      __m256 x[3], y[3], z[3];
      for (int c = 0; c < 3; ++c) {
        const __m256 ax = _mm256_sub_ps(_mm256_set1_ps(block.p[c][g.kx][l]), o[0]);
        const __m256 ay = _mm256_sub_ps(_mm256_set1_ps(block.p[c][g.ky][l]), o[1]);
        const __m256 az = _mm256_sub_ps(_mm256_set1_ps(block.p[c][g.kz][l]), o[2]);
        x[c] = _mm256_sub_ps(ax, _mm256_mul_ps(sh[0], az));
        y[c] = _mm256_sub_ps(ay, _mm256_mul_ps(sh[1], az));
        z[c] = _mm256_mul_ps(sh[2], az);
      }
      const Lanes8 h = decide8(x, y, z, tmin, tmax, g.used & ~occluded);
      if (h.exact | h.unsure) {
        OddLanes& odd = out.odd[out.odd_count++];
        odd.tri = block.id[l], odd.exact = h.exact, odd.unsure = h.unsure;
        _mm256_store_ps(odd.e1, h.e1), _mm256_store_ps(odd.e2, h.e2);
        _mm256_store_ps(odd.det, h.det);
      }
      if (any_hit) {
        occluded |= h.sure;
        if (occluded == g.used) {
          out.hit = occluded;
          return tested + 1;
        }
        continue;
      }
      if (!h.sure) continue;
      // Lane k of `sure` as a mask: bit k of h.sure moved to the sign of lane k.
      const __m256i sure = _mm256_sllv_epi32(_mm256_set1_epi32(int32_t(h.sure)),
                                             _mm256_setr_epi32(31, 30, 29, 28, 27, 26, 25, 24));
      const __m256i tri = _mm256_xor_si256(_mm256_set1_epi32(int32_t(block.id[l])), bias);
      const __m256 less = _mm256_cmp_ps(h.t, best_t, _CMP_LT_OQ);
      const __m256 tie = _mm256_and_ps(_mm256_cmp_ps(h.t, best_t, _CMP_EQ_OQ),
                                       _mm256_castsi256_ps(_mm256_cmpgt_epi32(best_tri, tri)));
      const __m256 take = _mm256_and_ps(_mm256_castsi256_ps(sure), _mm256_or_ps(less, tie));
      best_t = _mm256_blendv_ps(best_t, h.t, take);
      best_e1 = _mm256_blendv_ps(best_e1, h.e1, take);
      best_e2 = _mm256_blendv_ps(best_e2, h.e2, take);
      best_det = _mm256_blendv_ps(best_det, h.det, take);
      best_tri = _mm256_castps_si256(
          _mm256_blendv_ps(_mm256_castsi256_ps(best_tri), _mm256_castsi256_ps(tri), take));
    }
  }
  if (any_hit) {
    out.hit = occluded;
    return tested;
  }
  out.hit = bits(_mm256_cmp_ps(best_t, inf, _CMP_LT_OQ));
  _mm256_store_ps(out.t, best_t);
  _mm256_store_ps(out.e1, best_e1);
  _mm256_store_ps(out.e2, best_e2);
  _mm256_store_ps(out.det, best_det);
  _mm256_store_si256(reinterpret_cast<__m256i*>(out.tri), _mm256_xor_si256(best_tri, bias));
  return tested;
}

// GCC 12's AVX-512 headers start masked intrinsics from _mm512_undefined_*(), which
// -Wmaybe-uninitialized reports once inlined (GCC bug 105593, fixed in GCC 13).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"

__attribute__((target("avx512f"))) inline __m512 max3(const __m512* v) {
  return _mm512_max_ps(_mm512_max_ps(_mm512_abs_ps(v[0]), _mm512_abs_ps(v[1])),
                       _mm512_abs_ps(v[2]));
}

// Sixteen lanes of intersect_triangle, each a (ray, triangle) pair, from the sheared corners
// x, y, z (as intersect_triangle computes them: corner − origin, then the shear): its float
// operations in its order, and what it would do with each lane (BlockHits' sure, exact, unsure).
struct Lanes16 {
  __m512 t, e1, e2, det;
  uint32_t sure, exact, unsure;
};
__attribute__((target("avx512f"))) inline Lanes16 decide16(const __m512* x, const __m512* y,
                                                           const __m512* z, __m512 tmin,
                                                           __m512 tmax, uint32_t used) {
  const __m512 e0 = _mm512_sub_ps(_mm512_mul_ps(x[2], y[1]), _mm512_mul_ps(y[2], x[1]));
  const __m512 e1 = _mm512_sub_ps(_mm512_mul_ps(x[0], y[2]), _mm512_mul_ps(y[0], x[2]));
  const __m512 e2 = _mm512_sub_ps(_mm512_mul_ps(x[1], y[0]), _mm512_mul_ps(y[1], x[0]));
  const __m512 zero = _mm512_setzero_ps();
  const __mmask16 any_zero = _mm512_cmp_ps_mask(e0, zero, _CMP_EQ_OQ) |
                             _mm512_cmp_ps_mask(e1, zero, _CMP_EQ_OQ) |
                             _mm512_cmp_ps_mask(e2, zero, _CMP_EQ_OQ);
  const __mmask16 any_neg = _mm512_cmp_ps_mask(e0, zero, _CMP_LT_OQ) |
                            _mm512_cmp_ps_mask(e1, zero, _CMP_LT_OQ) |
                            _mm512_cmp_ps_mask(e2, zero, _CMP_LT_OQ);
  const __mmask16 any_pos = _mm512_cmp_ps_mask(e0, zero, _CMP_GT_OQ) |
                            _mm512_cmp_ps_mask(e1, zero, _CMP_GT_OQ) |
                            _mm512_cmp_ps_mask(e2, zero, _CMP_GT_OQ);
  const __m512 det = _mm512_add_ps(_mm512_add_ps(e0, e1), e2);
  const __m512 abs_det = _mm512_abs_ps(det);
  const __m512 inf = _mm512_set1_ps(INFINITY);
  // As intersect_triangle: a det out of [2^-80, inf) is for its double test (unsure).
  const __mmask16 det_ok = _mm512_cmp_ps_mask(abs_det, _mm512_set1_ps(0x1p-80f), _CMP_GE_OQ) &
                           _mm512_cmp_ps_mask(abs_det, inf, _CMP_LT_OQ);
  const __mmask16 inside = __mmask16(~(any_neg & any_pos) & det_ok);
  const __m512 t =
      _mm512_div_ps(_mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(e0, z[0]), _mm512_mul_ps(e1, z[1])),
                                  _mm512_mul_ps(e2, z[2])),
                    det);
  // intersect_triangle's error bound of t, times |det| (t_error_times_det), in its order.
  const __m512 max_x = max3(x), max_y = max3(y), max_z = max3(z);
  const __m512 max_e =
      _mm512_max_ps(_mm512_max_ps(_mm512_abs_ps(e0), _mm512_abs_ps(e1)), _mm512_abs_ps(e2));
  constexpr auto gamma = [](int n) { return n * 0x1p-24f / (1.f - n * 0x1p-24f); };
  const __m512 g2 = _mm512_set1_ps(gamma(2)), g3 = _mm512_set1_ps(gamma(3)),
               g5 = _mm512_set1_ps(gamma(5));
  const __m512 delta_z = _mm512_mul_ps(g3, max_z);
  const __m512 delta_x = _mm512_mul_ps(g5, _mm512_add_ps(max_x, max_z));
  const __m512 delta_y = _mm512_mul_ps(g5, _mm512_add_ps(max_y, max_z));
  const __m512 delta_e =
      _mm512_mul_ps(_mm512_set1_ps(2.f),
                    _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(_mm512_mul_ps(g2, max_x), max_y),
                                                _mm512_mul_ps(delta_y, max_x)),
                                  _mm512_mul_ps(delta_x, max_y)));
  const __m512 bound =
      _mm512_mul_ps(_mm512_set1_ps(3.f * (1.f + 0x1p-20f)),
                    _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(_mm512_mul_ps(g3, max_e), max_z),
                                                _mm512_mul_ps(delta_e, max_z)),
                                  _mm512_mul_ps(delta_z, max_e)));
  const __m512 abs_t = _mm512_abs_ps(t);
  const __mmask16 in_range =
      _mm512_cmp_ps_mask(t, tmin, _CMP_GE_OQ) & _mm512_cmp_ps_mask(t, tmax, _CMP_LE_OQ);
  const __mmask16 finite = _mm512_cmp_ps_mask(abs_t, inf, _CMP_LT_OQ);
  const __mmask16 beyond_error =
      _mm512_cmp_ps_mask(_mm512_mul_ps(abs_t, abs_det), bound, _CMP_GT_OQ);
  // With no edge function of zero (no double edge functions) and det in range, the scalar test
  // takes the lane's float values: inside, a finite t beyond its error bound decides by its
  // range (sure if in it), any other t is computed again in double (exact).
  const uint32_t plain = uint32_t(inside & ~any_zero) & used;
  const uint32_t sure = plain & uint32_t(finite & beyond_error & in_range);
  const uint32_t exact = plain & ~uint32_t(finite & beyond_error);
  const uint32_t unsure = uint32_t(any_zero | __mmask16(~det_ok)) & used;
  return {t, e1, e2, det, sure, exact, unsure};
}

// One ray against the sixteen triangles of a block (intersect_triangle's operations on 16-wide
// registers), with the lanes whose answer is known without the scalar test (BlockHits).
__attribute__((target("avx512f"))) void block_hits_avx512(const TriangleBlock& b, const Ray& r,
                                                          float tmin, float tmax, BlockHits& out) {
  const __m512 ox = _mm512_set1_ps(r.o[r.kx]), oy = _mm512_set1_ps(r.o[r.ky]),
               oz = _mm512_set1_ps(r.o[r.kz]);
  const __m512 sx = _mm512_set1_ps(r.sx), sy = _mm512_set1_ps(r.sy), sz = _mm512_set1_ps(r.sz);
  __m512 x[3], y[3], z[3];
  for (int c = 0; c < 3; ++c) {
    const __m512 ax = _mm512_sub_ps(_mm512_load_ps(b.p[c][r.kx]), ox);
    const __m512 ay = _mm512_sub_ps(_mm512_load_ps(b.p[c][r.ky]), oy);
    const __m512 az = _mm512_sub_ps(_mm512_load_ps(b.p[c][r.kz]), oz);
    x[c] = _mm512_sub_ps(ax, _mm512_mul_ps(sx, az));
    y[c] = _mm512_sub_ps(ay, _mm512_mul_ps(sy, az));
    z[c] = _mm512_mul_ps(sz, az);
  }
  const Lanes16 l = decide16(x, y, z, _mm512_set1_ps(tmin), _mm512_set1_ps(tmax), (1u << b.n) - 1u);
  out.sure = l.sure, out.exact = l.exact, out.unsure = l.unsure;
  _mm512_store_ps(out.t, l.t);
  _mm512_store_ps(out.e1, l.e1);
  _mm512_store_ps(out.e2, l.e2);
  _mm512_store_ps(out.det, l.det);
}

// Sixteen rays of one shear class against the triangles of `blocks`, one triangle at a time: the
// transpose of block_hits_avx512, with the same operations per lane. Each lane keeps its nearest
// sure hit in registers, by closer()'s order (t, then the triangle index).
__attribute__((target("avx512f"))) int group_hits_avx512(const TriangleBlock* blocks, int nb,
                                                         RayGroup& g, bool any_hit,
                                                         GroupHits& out) {
  // Ray::shear's constants, divided as it divides them (correctly rounded in either form).
  const __m512 dz = _mm512_load_ps(g.d[2]);
  const __m512 sh[3] = {_mm512_div_ps(_mm512_load_ps(g.d[0]), dz),
                        _mm512_div_ps(_mm512_load_ps(g.d[1]), dz),
                        _mm512_div_ps(_mm512_set1_ps(1.f), dz)};
  __m512 o[3];
  for (int a = 0; a < 3; ++a) o[a] = _mm512_load_ps(g.o[a]), _mm512_store_ps(g.s[a], sh[a]);
  const __m512 tmin = _mm512_load_ps(g.tmin), tmax = _mm512_load_ps(g.tmax);
  const __m512 inf = _mm512_set1_ps(INFINITY);
  __m512 best_t = inf, best_e1 = _mm512_setzero_ps(), best_e2 = best_e1, best_det = best_e1;
  __m512i best_tri = _mm512_set1_epi32(-1);
  uint32_t occluded = 0;
  int tested = 0;
  out.odd_count = 0;
  for (int b = 0; b < nb; ++b) {
    const TriangleBlock& block = blocks[b];
    for (int l = 0; l < block.n; ++l, ++tested) {
      __m512 x[3], y[3], z[3];
      for (int c = 0; c < 3; ++c) {
        const __m512 ax = _mm512_sub_ps(_mm512_set1_ps(block.p[c][g.kx][l]), o[0]);
        const __m512 ay = _mm512_sub_ps(_mm512_set1_ps(block.p[c][g.ky][l]), o[1]);
        const __m512 az = _mm512_sub_ps(_mm512_set1_ps(block.p[c][g.kz][l]), o[2]);
        x[c] = _mm512_sub_ps(ax, _mm512_mul_ps(sh[0], az));
        y[c] = _mm512_sub_ps(ay, _mm512_mul_ps(sh[1], az));
        z[c] = _mm512_mul_ps(sh[2], az);
      }
      const Lanes16 h = decide16(x, y, z, tmin, tmax, g.used & ~occluded);
      if (h.exact | h.unsure) {  // kept for the caller: no call here, so nothing is spilled
        OddLanes& odd = out.odd[out.odd_count++];
        odd.tri = block.id[l], odd.exact = h.exact, odd.unsure = h.unsure;
        _mm512_store_ps(odd.e1, h.e1), _mm512_store_ps(odd.e2, h.e2);
        _mm512_store_ps(odd.det, h.det);
      }
      if (any_hit) {
        occluded |= h.sure;
        if (occluded == g.used) {
          out.hit = occluded;
          return tested + 1;
        }
        continue;
      }
      const __m512i tri = _mm512_set1_epi32(int(block.id[l]));
      const __mmask16 take = _mm512_mask_cmp_ps_mask(__mmask16(h.sure), h.t, best_t, _CMP_LT_OQ) |
                             (_mm512_mask_cmp_ps_mask(__mmask16(h.sure), h.t, best_t, _CMP_EQ_OQ) &
                              _mm512_cmplt_epu32_mask(tri, best_tri));
      best_t = _mm512_mask_mov_ps(best_t, take, h.t);
      best_e1 = _mm512_mask_mov_ps(best_e1, take, h.e1);
      best_e2 = _mm512_mask_mov_ps(best_e2, take, h.e2);
      best_det = _mm512_mask_mov_ps(best_det, take, h.det);
      best_tri = _mm512_mask_mov_epi32(best_tri, take, tri);
    }
  }
  if (any_hit) {
    out.hit = occluded;
    return tested;
  }
  out.hit = _mm512_cmp_ps_mask(best_t, inf, _CMP_LT_OQ);
  _mm512_store_ps(out.t, best_t);
  _mm512_store_ps(out.e1, best_e1);
  _mm512_store_ps(out.e2, best_e2);
  _mm512_store_ps(out.det, best_det);
  _mm512_store_si512(out.tri, best_tri);
  return tested;
}

uint32_t block_candidates_avx512(const TriangleBlock& b, const Ray& r, float tmin, float tmax) {
  BlockHits h;
  block_hits_avx512(b, r, tmin, tmax, h);
  return h.sure | h.exact | h.unsure;
}
#pragma GCC diagnostic pop

#else

uint32_t block_candidates_avx512(const TriangleBlock& b, const Ray&, float, float) {
  return (1u << b.n) - 1u;  // never called; every lane is a candidate
}
int group_hits_avx512(const TriangleBlock*, int, RayGroup&, bool, GroupHits& out) {
  out.hit = 0, out.odd_count = 0;  // never called
  return 0;
}
void block_hits_avx512(const TriangleBlock& b, const Ray&, float, float, BlockHits& out) {
  out.sure = out.exact = 0,
  out.unsure = (1u << b.n) - 1u;  // never called; every lane is for the scalar test
}
void block_hits_avx2(const TriangleBlock& b, const Ray&, float, float, BlockHits& out) {
  out.sure = out.exact = 0,
  out.unsure = (1u << b.n) - 1u;  // never called; every lane is for the scalar test
}
int group_hits_avx2(const TriangleBlock*, int, RayGroup&, bool, GroupHits& out) {
  out.hit = 0, out.odd_count = 0;  // never called
  return 0;
}

#endif

}  // namespace dacrt
