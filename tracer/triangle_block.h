// TriangleBlock: up to sixteen triangles in structure-of-arrays form, so that one ray is tested
// against all of them with vector instructions: sixteen lanes at once with AVX-512, eight at a
// time with AVX2. RayGroup is the transpose, sixteen rays (eight with AVX2) against one triangle
// at a time, for leaves of many rays.
//
// The vector test is a filter in front of the scalar one, not a second implementation: it performs
// intersect_triangle's float operations in the same order (IEEE results are the same in a vector
// lane), and returns every lane that test could accept, plus every lane where the scalar test
// switches to double (an edge function of exactly zero, a t that is not finite). The caller runs
// intersect_triangle on those lanes only, so hits, t, u and v are the scalar test's, bit for bit,
// with or without AVX2.
#pragma once

#include <cstdint>

#include "dacrt/tracer/geometry.h"
#include "dacrt/tracer/ray.h"
#include "dacrt/tracer/triangle.h"
#include "dacrt/util/cpu.h"

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
      const Geometry::Corners& t = g.corners[i];
      for (int c = 0; c < 3; ++c)
        for (int a = 0; a < 3; ++a) p[c][a][l] = t[size_t(c)][a];
    }
  }
};

// Bit l set: lane l's triangle may be accepted by intersect_triangle(r, ..., tmin, tmax), or has an
// edge function of exactly zero, or a t that is not finite or within its error bound of 0. Only
// call when avx512_available() (sixteen lanes per instruction).
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
// The same answers with AVX2, eight lanes per instruction. Only call when avx2_available().
void block_hits_avx2(const TriangleBlock& b, const Ray& r, float tmin, float tmax, BlockHits& out);

// Sixteen rays of one shear class (the same kx, ky, kz: Ray::shear_class) in structure-of-arrays
// form, for group_hits_avx512: the transpose of TriangleBlock, for a leaf with many rays.
struct RayGroup {
  static constexpr int lanes = 16;
  alignas(64) float o[3][lanes];  // the origins' kx, ky and kz components
  alignas(64) float d[3][lanes];  // the directions' kx, ky and kz components
  alignas(64) float tmin[lanes], tmax[lanes];
  alignas(64) float s[3][lanes];  // sx, sy, sz, as Ray::shear computes them (group_hits_avx512)
  int kx, ky, kz;
  uint32_t used;  // lanes in use; the others hold copies of lane 0
};

// A triangle's lanes that the vector test leaves to the scalar one (block_hits_avx512's `exact` and
// `unsure`), with their float e1, e2 and det (for exact_lane_hit).
struct OddLanes {
  uint32_t tri, exact, unsure;
  alignas(64) float e1[RayGroup::lanes], e2[RayGroup::lanes], det[RayGroup::lanes];
};

// Per lane of a RayGroup: its nearest `sure` hit (hit bit set; the hit is t, u = e1 / det,
// v = e2 / det on triangle tri, bit for bit intersect_triangle's), or with any_hit, whether a sure
// hit was found (hit bit set); and the lanes left to the scalar test, by triangle.
struct GroupHits {
  static constexpr int max_triangles = 64;
  alignas(64) float t[RayGroup::lanes], e1[RayGroup::lanes], e2[RayGroup::lanes],
      det[RayGroup::lanes];
  alignas(64) uint32_t tri[RayGroup::lanes];
  uint32_t hit;
  int odd_count;
  OddLanes odd[max_triangles];  // at most one per triangle
};

// Every triangle of blocks[0..nb) (nb <= 4) against the rays of g (the same operations per lane as
// block_hits_avx512), in the order of the blocks and their lanes; first sets g.s. Closest hit: out
// holds each lane's nearest sure hit by closer()'s order. any_hit: out.hit is the lanes with a
// sure hit, and triangles stop as soon as every lane has one; lanes with one are left out of the
// later triangles' odd lanes. Either way out.odd lists the lanes for the caller to decide one at a
// time. Returns how many triangles were tested. Only call when avx512_available().
int group_hits_avx512(const TriangleBlock* blocks, int nb, RayGroup& g, bool any_hit,
                      GroupHits& out);
// The same for the first eight lanes of g (g.used within bits 0..7), with AVX2. Only call when
// avx2_available().
int group_hits_avx2(const TriangleBlock* blocks, int nb, RayGroup& g, bool any_hit,
                    GroupHits& out);

// intersect_triangle's answer on an `exact` lane l (its corners p0, p1, p2), from the lane's float
// edge functions e1, e2 and det: t in double, in [tmin, tmax], with the lane's float u and v.
inline bool exact_lane_hit(float e1, float e2, float det, const Ray& r, const glm::vec3& p0,
                           const glm::vec3& p1, const glm::vec3& p2, float tmin, float tmax,
                           TriangleHit& hit) {
  const float t = float(exact_t(r, p0, p1, p2));
  if (!(t >= tmin && t <= tmax)) return false;
  hit = {t, e1 / det, e2 / det};
  return true;
}
// The same for lane l of block_hits_avx512.
inline bool exact_lane_hit(const BlockHits& bh, int l, const Ray& r, const glm::vec3& p0,
                           const glm::vec3& p1, const glm::vec3& p2, float tmin, float tmax,
                           TriangleHit& hit) {
  return exact_lane_hit(bh.e1[l], bh.e2[l], bh.det[l], r, p0, p1, p2, tmin, tmax, hit);
}

}  // namespace dacrt
