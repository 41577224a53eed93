// Ray: one ray of a batch, prepared for the intersection kernels that every backend of ours shares:
// the watertight triangle test's shear constants (Woop, Benthin, Wald, "Watertight Ray/Triangle
// Intersection", JCGT 2013) and the conservative box test used for ray filtering.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <glm/glm.hpp>

#include "tracer/aabb.h"
#include "tracer/ray_batch.h"

namespace dacrt {

struct Ray {
  glm::vec3 o, d;
  int kx, ky, kz;    // axis permutation: kz is the largest |d| component
  float sx, sy, sz;  // shear constants

  // A ray is live if its interval is ordered and everything is finite and non-zero in length.
  // NaN, inf, zero-direction and tmin > tmax rays never hit anything.
  static bool valid(const glm::vec3& o, const glm::vec3& d, float tmin, float tmax) {
    bool finite = std::isfinite(o.x) && std::isfinite(o.y) && std::isfinite(o.z) &&
                  std::isfinite(d.x) && std::isfinite(d.y) && std::isfinite(d.z);
    return finite && (d.x != 0.f || d.y != 0.f || d.z != 0.f) && tmin <= tmax &&
           !std::isnan(tmin) && !std::isnan(tmax);
  }

  // 1/d, with components too small to invert replaced by ±1e-30 first (so never inf or NaN).
  static glm::vec3 inverse(const glm::vec3& d) {
    glm::vec3 inv;
    for (int k = 0; k < 3; ++k) {
      float dk = std::abs(d[k]) < 1e-30f ? std::copysign(1e-30f, d[k]) : d[k];
      inv[k] = 1.f / dk;
    }
    return inv;
  }

  // How far the box test grows boxes, in world units, for a ray from `o`; `magnitude` is the
  // largest absolute coordinate of the geometry (Box::magnitude). The triangle test rounds: it may
  // report a hit for a point a few ulps of |o| + |p| outside the triangle, at a t a few ulps off.
  // Its hit point is still within that distance of the triangle (the weights are a convex
  // combination), so the box test grows every box by far more (2^-16 relative): a box is never
  // culled while a triangle inside it could report a hit, and filtering never changes the answer.
  static float pad_for(const glm::vec3& o, float magnitude) {
    float om = std::max({std::abs(o.x), std::abs(o.y), std::abs(o.z)});
    return 0x1p-16f * (om + magnitude);
  }

  // What the triangle test reads: o, d and the shear.
  static Ray shear(const glm::vec3& o, const glm::vec3& d) {
    Ray r;
    r.o = o;
    r.d = d;
    glm::vec3 a = glm::abs(d);
    r.kz = a.x >= a.y ? (a.x >= a.z ? 0 : 2) : (a.y >= a.z ? 1 : 2);
    r.kx = r.kz == 2 ? 0 : r.kz + 1;
    r.ky = r.kx == 2 ? 0 : r.kx + 1;
    if (d[r.kz] < 0.f) std::swap(r.kx, r.ky);  // keep the winding of the sheared triangle
    r.sx = d[r.kx] / d[r.kz];
    r.sy = d[r.ky] / d[r.kz];
    r.sz = 1.f / d[r.kz];
    return r;
  }

  static Ray shear(const RayBatch& b, size_t i) { return shear(b.origin(i), b.direction(i)); }

  // Conservative slab test: true if a ray may touch `box`, grown by `pad`, within [tmin, tmax].
  // `inv_d` is the direction's inverse (Ray::inverse), `pad` from Ray::pad_for.
  static bool box_hits(const glm::vec3& o, const glm::vec3& inv_d, float pad, const Box& box,
                       float tmin, float tmax) {
    float near = tmin, far = tmax;
    for (int k = 0; k < 3; ++k) {
      float a = (box.lo[k] - pad - o[k]) * inv_d[k];
      float b = (box.hi[k] + pad - o[k]) * inv_d[k];
      near = std::max(near, std::min(a, b));
      far = std::min(far, std::max(a, b));
    }
    return near <= far;
  }
};

// Moves a point on a surface off it along the geometric normal `n` (pointing to the side the new
// ray leaves from), by an amount that scales with the point's magnitude: a few ulps in integer
// steps of the float representation far from the origin, a small fixed step near it.
// After Wächter and Binder, "A Fast and Robust Method for Avoiding Self-Intersection",
// Ray Tracing Gems, chapter 6.
inline glm::vec3 offset_ray_origin(const glm::vec3& p, const glm::vec3& n) {
  constexpr float near_origin = 1.f / 32.f;
  constexpr float float_scale = 1.f / 65536.f;
  constexpr float int_scale = 256.f;
  glm::vec3 out;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(p[k]) < near_origin) {
      out[k] = p[k] + float_scale * n[k];
      continue;
    }
    // Unsigned arithmetic on the bit pattern: moving away from zero adds to the magnitude bits.
    int32_t step = int32_t(int_scale * n[k]);
    if (p[k] < 0.f) step = -step;
    out[k] = std::bit_cast<float>(std::bit_cast<uint32_t>(p[k]) + uint32_t(step));
  }
  return out;
}

}  // namespace dacrt
