// The records the DACRT recursion partitions in place: one per triangle (TriangleRef, 20 bytes)
// and one per live ray (RayRef, 36 bytes). Compact records that move with their ranges are what
// make each level one streaming pass, and their sizes are what dacrt_memory_bound counts.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <glm/glm.hpp>
#include <limits>

#include "dacrt/tracer/dacrt/dacrt.h"
#include "dacrt/tracer/geometry.h"
#include "dacrt/tracer/ray.h"

namespace dacrt::kernel {

constexpr float inf = std::numeric_limits<float>::infinity();
constexpr float max_float = std::numeric_limits<float>::max();
using Simd = DacrtParams::Simd;

// What binning and partitioning read of a triangle, in one 20-byte record, so that a node streams
// through a contiguous range of them instead of gathering from scattered arrays by index. The box
// is stored as its low corner and its extent in 8-bit steps of a power of two, rounded up: a
// slightly larger box (by at most 1/64 of the triangle's own size) is still a bounding box, so
// filtering stays conservative, and the record is half the size of a float box with a centroid.
struct TriangleRef {
  float lo[3];
  uint8_t ext[3];  // hi[a] = lo[a] + ext[a] · 2^exp, evaluated as in hi()
  int8_t exp;      // in [-126, 127]
  uint32_t id;     // index into Geometry

  float step() const { return std::bit_cast<float>(uint32_t(exp + 127) << 23); }
  float hi(int a, float step) const { return lo[a] + float(ext[a]) * step; }
  // The box centre along `a`: where binning puts the triangle. Clamped to finite values (a box
  // whose extent overflows has an infinite centre, a box reaching -inf a NaN one), so that the
  // centres' box of a node stays finite; any value works for binning as long as it is this one.
  float center(int a, float step) const {
    const float c = lo[a] + 0.5f * (float(ext[a]) * step);
    return c != c ? 0.f : std::clamp(c, -max_float, max_float);
  }
  // center() on a vector of (x, y, z, unused): the same values lane by lane.
  using f4 = float __attribute__((vector_size(16)));
  static f4 clamp_centre(f4 c) {
    const f4 zero = {}, hi = zero + max_float, lo = zero - max_float;
    c = c == c ? c : zero;
    c = c < hi ? c : hi;
    return c > lo ? c : lo;
  }

  static TriangleRef encode(const Geometry& g, uint32_t i) {
    TriangleRef r;
    r.id = i;
    float hi[3], extent = 0.f;
    for (int a = 0; a < 3; ++a) {
      float p0 = g.corners[i][0][a], p1 = g.corners[i][1][a], p2 = g.corners[i][2][a];
      r.lo[a] = std::min({p0, p1, p2});
      hi[a] = std::max({p0, p1, p2});
      extent = std::max(extent, hi[a] - r.lo[a]);
    }
    if (!std::isfinite(extent)) {  // an extent past float: the box reaches infinity, conservatively
      r.exp = 127;
      r.ext[0] = r.ext[1] = r.ext[2] = 255;
      return r;
    }
    // extent < 2^k; a step of 2^(k-7) needs at most 128 steps (plus a few for rounding), and no
    // fewer than 64 for the longest side. Each count is the fewest steps that reach hi in float
    // arithmetic exactly as hi() evaluates it.
    const int k = int(std::bit_cast<uint32_t>(extent) >> 23) - 126;
    r.exp = int8_t(std::max(-126, k - 7));
    const float step = r.step();
    const float inv_step = std::bit_cast<float>(uint32_t(127 - r.exp) << 23);  // exact
    for (int a = 0; a < 3; ++a) {
      const float steps = (hi[a] - r.lo[a]) * inv_step;
      int q = int(steps);
      q += float(q) < steps;
      r.ext[a] = uint8_t(std::min(q, 255));
      while (r.hi(a, step) < hi[a] && r.ext[a] < 255) ++r.ext[a];
    }
    return r;
  }
};
static_assert(sizeof(TriangleRef) == 20);

// A ray as the recursion sees it, in one 36-byte record that moves with the ray as ranges are
// partitioned: filtering, sampling and leaves never gather from the batch's arrays. The box test's
// inverse direction and pad are recomputed (Ray::inverse, Ray::pad_for) rather than stored: a
// smaller record is less memory to stream at every level, and the vector box test divides eight
// rays at once.
struct RayRef {
  glm::vec3 o, d;  // as in the batch
  float tmin;
  float far;    // running tmax: the closest hit so far, or -inf once occluded
  uint32_t id;  // index into the batch

  bool hits(const Box& box, float magnitude) const {
    return Ray::box_hits(o, Ray::inverse(d), Ray::pad_for(o, magnitude), box, tmin, far);
  }
};
static_assert(sizeof(RayRef) == 36);

}  // namespace dacrt::kernel
