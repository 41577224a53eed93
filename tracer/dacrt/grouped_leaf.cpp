// A leaf of many rays, sixteen rays at a time against one triangle at a time (group_hits_avx512):
// the rays' records are read sixteen per AVX-512 instruction and sorted into six buckets by their
// shear class (Ray::shear_class), and each full bucket is one RayGroup. With AVX2 only, eight rays
// at a time (group_hits_avx2), bucketed one by one. The lanes the vector test
// leaves to the scalar one are decided one at a time, as leaf() decides them, and each ray's
// closest hit is recorded once, with closer(): the answers are leaf()'s, bit for bit.
#include <bit>
#include <cstddef>

#include "dacrt/tracer/dacrt/box_simd.h"
#include "dacrt/tracer/dacrt/traversal.h"
#include "dacrt/tracer/triangle.h"
#include "dacrt/tracer/triangle_block.h"

#ifdef DACRT_X86
#include <immintrin.h>
#endif

namespace dacrt::kernel {

#ifdef DACRT_X86

namespace {

constexpr int lanes = RayGroup::lanes;

// Each lane's closest hit among its lanes that the vector test left to the scalar one (closest
// hits), or the lanes they occlude (any hit): out.odd decided one at a time, as leaf() decides
// them. `ray` maps lanes to records; lanes already in out.hit are skipped with any_hit.
struct OddHits {
  alignas(64) float t[lanes];
  alignas(64) uint32_t tri[lanes];
  float u[lanes], v[lanes];
  uint32_t hit;

  void decide(const Geometry& g, const RayGroup& group, const GroupHits& out, const RayRef* rays,
              const uint32_t* ray, bool any_hit) {
    hit = 0;
    for (int l = 0; l < lanes; ++l) t[l] = inf, tri[l] = HitBatch::miss;
    for (int k = 0; k < out.odd_count; ++k) {
      const OddLanes& odd = out.odd[k];
      const uint32_t id = odd.tri;
      const glm::vec3 p0 = g.vertex(id, 0), p1 = g.vertex(id, 1), p2 = g.vertex(id, 2);
      uint32_t left = (odd.exact | odd.unsure) & ~(any_hit ? out.hit | hit : 0u);
      for (; left; left &= left - 1) {
        const int l = std::countr_zero(left);
        const RayRef& r = rays[ray[l]];
        // Ray::shear(r.o, r.d): the group's axes and shear constants are its values.
        Ray s;
        s.o = r.o, s.d = r.d, s.kx = group.kx, s.ky = group.ky, s.kz = group.kz;
        s.sx = group.s[0][l], s.sy = group.s[1][l], s.sz = group.s[2][l];
        TriangleHit h;
        const bool found =
            odd.exact >> l & 1u
                ? exact_lane_hit(odd.e1[l], odd.e2[l], odd.det[l], s, p0, p1, p2, r.tmin, r.far, h)
                : intersect_triangle(s, p0, p1, p2, r.tmin, r.far, h);
        if (!found) continue;
        hit |= 1u << l;
        if (!any_hit && closer(h.t, id, t[l], &tri[l]))
          t[l] = h.t, tri[l] = id, u[l] = h.u, v[l] = h.v;
      }
    }
  }
};

}  // namespace

// GCC 12's AVX-512 headers start masked intrinsics from _mm512_undefined_*(), which
// -Wmaybe-uninitialized reports once inlined (GCC bug 105593, fixed in GCC 13).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"

namespace {

// Field k (a float of the record: o 0-2, d 3-5, tmin 6, far 7) of the records base + at / 9.
__attribute__((target("avx512f"))) inline __m512 field(const float* base, __m512i at, int k) {
  return _mm512_i32gather_ps(_mm512_add_epi32(at, _mm512_set1_epi32(k)), base, 4);
}
__attribute__((target("avx512f"))) inline __m512 field(const float* base, __m512i at, int k,
                                                       __mmask16 m) {
  return _mm512_mask_i32gather_ps(_mm512_setzero_ps(), m,
                                  _mm512_add_epi32(at, _mm512_set1_epi32(k)), base, 4);
}

// One leaf's groups: the records of [rb, re), read from base (record rb + i at base + 9 i).
struct Groups {
  Traversal& t;
  const TriangleBlock* blocks;
  int nb;
  uint32_t rb;
  const float* base;
  bool any_hit;
  RayGroup group;
  GroupHits out;
  OddHits odd;

  // Tests the records ray[0..n) of class cls as one group, and records their answers.
  __attribute__((target("avx512f"))) void run(int cls, const uint32_t* ray, int n) {
    const int8_t* axes = Ray::class_axes[cls];
    group.kx = axes[0], group.ky = axes[1], group.kz = axes[2];
    group.used = (1u << n) - 1u;
    // Unused lanes repeat lane 0 (their answers are never read).
    const __m512i index =
        _mm512_mask_loadu_epi32(_mm512_set1_epi32(int(ray[0])), __mmask16(group.used), ray);
    const __m512i at = _mm512_mullo_epi32(_mm512_sub_epi32(index, _mm512_set1_epi32(int(rb))),
                                          _mm512_set1_epi32(9));
    for (int a = 0; a < 3; ++a) {
      _mm512_store_ps(group.o[a], field(base, at, axes[a]));
      _mm512_store_ps(group.d[a], field(base, at, 3 + axes[a]));
    }
    _mm512_store_ps(group.tmin, field(base, at, 6));
    _mm512_store_ps(group.tmax, field(base, at, 7));
    answer(ray, n, group_hits_avx512(blocks, nb, group, any_hit, out));
  }

  // The same for at most eight records, tested with AVX2 (their fields copied one by one).
  void run8(int cls, const uint32_t* ray, int n) {
    const int8_t* axes = Ray::class_axes[cls];
    group.kx = axes[0], group.ky = axes[1], group.kz = axes[2];
    group.used = (1u << n) - 1u;
    for (int l = 0; l < 8; ++l) {
      const RayRef& r = t.rays[ray[l < n ? l : 0]];  // unused lanes repeat lane 0
      for (int a = 0; a < 3; ++a) group.o[a][l] = r.o[axes[a]], group.d[a][l] = r.d[axes[a]];
      group.tmin[l] = r.tmin, group.tmax[l] = r.far;
    }
    answer(ray, n, group_hits_avx2(blocks, nb, group, any_hit, out));
  }

  // The odd lanes decided one at a time, and each record's answer: `tested` triangles for each.
  void answer(const uint32_t* ray, int n, int tested) {
    t.stats.triangle_tests += uint64_t(tested) * uint64_t(n);
    odd.decide(t.k.geometry, group, out, t.rays, ray, any_hit);
    for (int l = 0; l < n; ++l) {
      RayRef& ref = t.rays[ray[l]];
      if (any_hit) {
        if ((out.hit | odd.hit) >> l & 1u) t.occlude(ref);
        continue;
      }
      // The vector lanes' hit and the odd lanes' hit, each against the ray's closest so far.
      if (out.hit >> l & 1u)
        t.keep_if_closer(ref, out.tri[l],
                         {out.t[l], out.e1[l] / out.det[l], out.e2[l] / out.det[l]});
      if (odd.tri[l] != HitBatch::miss)
        t.keep_if_closer(ref, odd.tri[l], {odd.t[l], odd.u[l], odd.v[l]});
    }
  }
};

}  // namespace

__attribute__((target("avx512f"))) void Traversal::grouped_leaf(const TriangleBlock* blocks, int nb,
                                                                uint32_t rb, uint32_t re) {
  static_assert(sizeof(RayRef) == 9 * sizeof(float) && offsetof(RayRef, d) == 12 &&
                offsetof(RayRef, tmin) == 24 && offsetof(RayRef, far) == 28);
  // Offsets within the leaf fit 32 bits (at most 2^27 rays).
  Groups groups{
      *this, blocks, nb, rb, reinterpret_cast<const float*>(rays + rb), occluded != nullptr,
      {},    {},     {}};
  const __m512i iota = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  const __m512i at = _mm512_mullo_epi32(iota, _mm512_set1_epi32(9));
  alignas(64) uint32_t bucket[6][2 * lanes];  // record indices, by class; at most 31 wait
  int count[6] = {};
  for (uint32_t r = rb; r < re; r += lanes) {
    const __mmask16 m = __mmask16(re - r >= uint32_t(lanes) ? 0xffffu : (1u << (re - r)) - 1u);
    const float* p = groups.base + 9 * size_t(r - rb);
    // The records four iterations on (gathers do not start the hardware's stream prefetch).
    for (int line = 0; line < 9 * lanes; line += 16)
      _mm_prefetch(reinterpret_cast<const char*>(p + 4 * 9 * lanes + line), _MM_HINT_T0);
    const __m512 dx = field(p, at, 3, m), dy = field(p, at, 4, m), dz = field(p, at, 5, m);
    // Live: far >= tmin (an occluded ray's far is -inf).
    const __mmask16 live =
        _mm512_mask_cmp_ps_mask(m, field(p, at, 7, m), field(p, at, 6, m), _CMP_GE_OQ);
    // Ray::shear_class, sixteen at a time: the same comparisons.
    const __m512 ax = _mm512_abs_ps(dx), ay = _mm512_abs_ps(dy), az = _mm512_abs_ps(dz);
    const __mmask16 xy = _mm512_cmp_ps_mask(ax, ay, _CMP_GE_OQ),
                    xz = _mm512_cmp_ps_mask(ax, az, _CMP_GE_OQ),
                    yz = _mm512_cmp_ps_mask(ay, az, _CMP_GE_OQ);
    const __mmask16 kz0 = xy & xz, kz1 = __mmask16(~xy) & yz, kz2 = __mmask16(~(kz0 | kz1));
    const __m512 dkz = _mm512_mask_blend_ps(kz1, _mm512_mask_blend_ps(kz0, dz, dx), dy);
    const __mmask16 negative = _mm512_cmp_ps_mask(dkz, _mm512_setzero_ps(), _CMP_LT_OQ);
    const __m512i cls =
        _mm512_or_epi32(_mm512_or_epi32(_mm512_maskz_mov_epi32(kz1, _mm512_set1_epi32(2)),
                                        _mm512_maskz_mov_epi32(kz2, _mm512_set1_epi32(4))),
                        _mm512_maskz_mov_epi32(negative, _mm512_set1_epi32(1)));
    const __m512i ids = _mm512_add_epi32(iota, _mm512_set1_epi32(int(r)));
    for (int c = 0; c < 6; ++c) {
      const __mmask16 in = live & _mm512_cmpeq_epi32_mask(cls, _mm512_set1_epi32(c));
      if (!in) continue;
      _mm512_mask_compressstoreu_epi32(bucket[c] + count[c], in, ids);
      count[c] += std::popcount(uint32_t(in));
      if (count[c] >= lanes) {
        groups.run(c, bucket[c], lanes);
        count[c] -= lanes;
        for (int j = 0; j < count[c]; ++j) bucket[c][j] = bucket[c][lanes + j];
      }
    }
  }
  for (int c = 0; c < 6; ++c)
    if (count[c] > 0) groups.run(c, bucket[c], count[c]);
}

// grouped_leaf with AVX2: eight rays at a time, bucketed by their class one by one.
void Traversal::grouped_leaf_avx2(const TriangleBlock* blocks, int nb, uint32_t rb, uint32_t re) {
  Groups groups{
      *this, blocks, nb, rb, reinterpret_cast<const float*>(rays + rb), occluded != nullptr,
      {},    {},     {}};
  uint32_t bucket[6][8];  // record indices, by class
  int count[6] = {};
  for (uint32_t r = rb; r < re; ++r) {
    const RayRef& ref = rays[r];
    if (!(ref.far >= ref.tmin)) continue;  // occluded already
    const int c = Ray::shear_class(ref.d);
    bucket[c][count[c]++] = r;
    if (count[c] == 8) groups.run8(c, bucket[c], 8), count[c] = 0;
  }
  for (int c = 0; c < 6; ++c)
    if (count[c] > 0) groups.run8(c, bucket[c], count[c]);
}

#pragma GCC diagnostic pop

#else

void Traversal::grouped_leaf(const TriangleBlock*, int, uint32_t, uint32_t) {}  // never called
void Traversal::grouped_leaf_avx2(const TriangleBlock*, int, uint32_t, uint32_t) {}

#endif

}  // namespace dacrt::kernel
