// What the fuzz target and the suite's fuzz test do with a scene that loads: trace rays through it
// with dacrt and compare every answer with the oracle (brute force), closest hits and occlusion.
// Loading alone never reaches the kernel, where hostile geometry (extents past float, NaN-free
// but huge or tiny coordinates, degenerate triangles) has crashed before.
#pragma once

#include <cstdint>
#include <cstring>
#include <vector>

#include "dacrt/scene/scene.h"
#include "dacrt/tracer/backend.h"
#include "dacrt/util/random.h"

namespace dacrt {

// Rays from around the scene's bounds (and through its centre) in hashed directions; the number
// of rays whose dacrt answer differs from brute's. Scenes of more than `max_triangles` are traced
// by dacrt alone (brute would take too long for a fuzzing run): 0 unless it crashes.
inline size_t trace_check(const Geometry& g, size_t rays = 256, size_t max_triangles = 20000) {
  const Box b = g.bounds();
  RayBatch batch;
  batch.type = RayType::bounce;
  batch.resize(rays);
  for (size_t i = 0; i < rays; ++i) {
    auto u = [&](uint64_t dim) { return uniform_float(0x5eed, i, dim, 0, 0); };
    glm::vec3 o, d;
    for (int a = 0; a < 3; ++a) {
      // Mostly inside the bounds, some at their corners, some at the origin.
      const float lo = b.empty() ? -1.f : b.lo[a], hi = b.empty() ? 1.f : b.hi[a];
      o[a] = i % 7 == 0 ? 0.f : i % 5 == 0 ? (u(a) < 0.5f ? lo : hi) : lo + (hi - lo) * u(a);
      d[a] = 2.f * u(3 + a) - 1.f;
    }
    batch.set(i, o, d, 0.f, i % 3 == 0 ? 1.f : INFINITY, uint32_t(i));
  }
  HitBatch got, expected;
  std::vector<uint8_t> occluded(rays), occluded_expected(rays);
  auto dacrt = Backend::create("dacrt", g);
  dacrt->intersect(batch, got);
  dacrt->occluded(batch, occluded);
  if (g.size() > max_triangles) return 0;
  auto brute = Backend::create("brute", g);
  brute->intersect(batch, expected);
  brute->occluded(batch, occluded_expected);
  size_t wrong = 0;
  for (size_t i = 0; i < rays; ++i)
    wrong += got.prim[i] != expected.prim[i] ||
             std::memcmp(&got.t[i], &expected.t[i], sizeof(float)) != 0 ||
             occluded[i] != occluded_expected[i];
  return wrong;
}

}  // namespace dacrt
