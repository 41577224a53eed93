// TriangleBlock: up to sixteen triangles in structure-of-arrays form, so that one ray is tested
// against all of them with vector instructions: sixteen lanes at once with AVX-512, eight at a
// time with AVX2.
//
// The vector test is a filter in front of the scalar one, not a second implementation: it performs
// intersect_triangle's float operations in the same order (IEEE results are the same in a vector
// lane), and returns every lane that test could accept, plus every lane where the scalar test
// switches to double (an edge function of exactly zero, a t that is not finite). The caller runs
// intersect_triangle on those lanes only, so hits, t, u and v are the scalar test's, bit for bit,
// with or without AVX2.
#pragma once

#include <cstdint>

#include "tracer/geometry.h"
#include "tracer/ray.h"
#include "tracer/triangle.h"

namespace dacrt {

struct TriangleBlock {
  static constexpr int lanes = 16;
  alignas(64) float p[3][3][lanes];  // [corner][axis][lane]
  uint32_t id[lanes];
  int n = 0;  // lanes in use

  // Loads the triangles ids[0..count), count <= 16; unused lanes are never reported.
  void load(const Geometry& g, const uint32_t* ids, int count) {
    n = count;
    for (int l = 0; l < lanes; ++l) {
      const uint32_t i = ids[l < count ? l : 0];
      id[l] = i;
      for (int c = 0; c < 3; ++c)
        for (int a = 0; a < 3; ++a) p[c][a][l] = g.p[c][a][i];
    }
  }
};

// True if this CPU runs the AVX2 kernels: block_candidates here and the DACRT box test.
bool avx2_available();
// True if this CPU runs the DACRT box test's AVX-512 (AVX512F) variant.
bool avx512_available();

// Bit l set: lane l's triangle may be accepted by intersect_triangle(r, ..., tmin, tmax), or has an
// edge function of exactly zero, or a t that is not finite or within its error bound of 0. Only
// call when avx2_available() (eight lanes per instruction).
uint32_t block_candidates(const TriangleBlock& b, const Ray& r, float tmin, float tmax);
// The same mask, sixteen lanes per instruction. Only call when avx512_available().
uint32_t block_candidates_avx512(const TriangleBlock& b, const Ray& r, float tmin, float tmax);

// block_candidates_avx512's mask in three parts, by what intersect_triangle(r, ..., tmin, tmax)
// would do with the lane:
// - `sure`: it accepts, with its float t: the hit is t[l], u = e1[l] / det[l], v = e2[l] / det[l],
//   bit for bit;
// - `exact`: the lane is inside, and it decides with t in double (exact_lane_hit, the same answer);
// - `unsure`: anything else that may hit (an edge function of zero, det out of range): the scalar
//   test itself. Lanes in none of the three are misses.
struct BlockHits {
  alignas(64) float t[TriangleBlock::lanes], e1[TriangleBlock::lanes], e2[TriangleBlock::lanes],
      det[TriangleBlock::lanes];
  uint32_t sure, exact, unsure;
};
void block_hits_avx512(const TriangleBlock& b, const Ray& r, float tmin, float tmax,
                       BlockHits& out);

// intersect_triangle's answer on an `exact` lane l of block_hits_avx512 (its corners p0, p1, p2):
// t in double, in [tmin, tmax], with the lane's float u and v.
inline bool exact_lane_hit(const BlockHits& bh, int l, const Ray& r, const glm::vec3& p0,
                           const glm::vec3& p1, const glm::vec3& p2, float tmin, float tmax,
                           TriangleHit& hit) {
  const float t = float(exact_t(r, p0, p1, p2));
  if (!(t >= tmin && t <= tmax)) return false;
  hit = {t, bh.e1[l] / bh.det[l], bh.e2[l] / bh.det[l]};
  return true;
}

}  // namespace dacrt
