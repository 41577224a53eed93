// Ray: one ray of a batch, prepared for the intersection kernels that every backend of ours shares:
// the watertight triangle test's shear constants (Woop, Benthin, Wald, "Watertight Ray/Triangle
// Intersection", JCGT 2013) and the conservative box test used for ray filtering.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <glm/glm.hpp>

#include "dacrt/tracer/aabb.h"
#include "dacrt/tracer/ray_batch.h"

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

  // The shear's axis permutation of a direction, by its class: 2 kz + 1 if d[kz] < 0, where kz is
  // the largest |d| component; kx and ky follow kz cyclically, swapped for a negative d[kz] (to
  // keep the winding of the sheared triangle).
  static constexpr int8_t class_axes[6][3] = {{1, 2, 0}, {2, 1, 0}, {2, 0, 1},
                                              {0, 2, 1}, {0, 1, 2}, {1, 0, 2}};  // kx, ky, kz
  static int shear_class(const glm::vec3& d) {
    const glm::vec3 a = abs_of(d);
    // a.x >= a.y ? (a.x >= a.z ? 0 : 2) : (a.y >= a.z ? 1 : 2), by a table (directions are
    // random: branches would be mispredicted half the time).
    constexpr int8_t largest[8] = {2, 2, 2, 0, 1, 2, 1, 0};  // by xy + 2 xz + 4 yz
    const int kz = largest[int(a.x >= a.y) | int(a.x >= a.z) << 1 | int(a.y >= a.z) << 2];
    return 2 * kz + int(d[kz] < 0.f);
  }

  // What the triangle test reads: o, d and the shear.
  static Ray shear(const glm::vec3& o, const glm::vec3& d) {
    Ray r;
    r.o = o;
    r.d = d;
    const int8_t* k = class_axes[shear_class(d)];
    r.kx = k[0], r.ky = k[1], r.kz = k[2];
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

// One float step towards +inf or -inf (pbrt-v4's NextFloatUp / NextFloatDown), for finite v.
inline float next_float_up(float v) {
  if (v == 0.f) return 0x1p-149f;  // -0 too
  const uint32_t bits = std::bit_cast<uint32_t>(v);
  return std::bit_cast<float>(v > 0.f ? bits + 1u : bits - 1u);
}
inline float next_float_down(float v) {
  return -next_float_up(-v);
}

// A point of a surface for rays to leave from: the point and how far, per component, a ray's
// origin must move off the surface: a bound on the point's distance from the exact point of the
// triangle it stands for, plus a margin for intersectors less exact than ours.
struct SpawnPoint {
  glm::vec3 p, error;
};

// The point of triangle (a, b, c) at the barycentric weights (u, v) of b and c that a hit reports,
// for spawning rays from (Pharr, Jakob and Humphreys, "Physically Based Rendering", 3rd ed.,
// section 3.9, and pbrt-v4's error intervals).
// - It is a + u (b - a) + v (c - a): the only rounding of the size of |p| is the last addition,
//   half an ulp, where (1 - u - v) a + u b + v c rounds four products of the corners' size (and
//   the weights' sum is not 1 after 1 - u - v rounds): several ulps of |p| off the plane.
// - The weights first move towards the centroid's by a distance of 16 ulps of the corners'
//   magnitude (at most half-way): a point on an edge is also on the neighbour's plane, within its
//   rounding, and at an inside corner (a closed box's) a ray leaving along the neighbour or towards
//   the light can start behind it and escape. 16 ulps off the edge, the rounding cannot put the
//   point behind a neighbour at 90° or more unless the triangle is a sliver (the distance to
//   the edge is at least the move times h / 3D, h the height, D the diameter: 1/6 for the
//   isosceles right triangles of a quad mesh).
// - The error is γ₁ |p| (the last addition) + γ₄ (|u (b - a)| + |v (c - a)|) (the edges, the
//   products, their sum), a little rounded up, plus a margin of 2^-18 of the triangle's largest
//   edge component, in every component: a triangle test rounds t near 0 by a few ulps of the
//   triangle's size (Embree's in float; ours in double, 2^-50 or so), and the error bound alone
//   is 0 across a plane of constant coordinate (y = 0 for a floor at the origin: the offset was
//   then one denormal, and the double t's rounding let shadow rays find the floor again).
template <typename Vec>
SpawnPoint spawn_point_of_edges(const Vec& a, const Vec& b, const Vec& c, const Vec& e1,
                                const Vec& e2, float u_in, float v_in) {
  using Real = typename Vec::value_type;
  auto max3 = [](const Vec& x) { return std::max(std::max(x.x, x.y), x.z); };
  Real u = Real(u_in), v = Real(v_in);
  const Real du = Real(1) / Real(3) - u, dv = Real(1) / Real(3) - v;
  const Real move = Real(16 * 0x1p-24) * max3(glm::max(glm::max(abs_of(a), abs_of(b)), abs_of(c)));
  const Real distance = max3(abs_of(du * e1 + dv * e2));  // max norm: no square to overflow
  if (distance > Real(0)) {                               // 0 or NaN: degenerate, no move
    const Real k = std::min(Real(0.5), move / distance);
    u += k * du, v += k * dv;
  }
  const Vec ue1 = u * e1, ve2 = v * e2;
  const glm::vec3 p(a + (ue1 + ve2));
  const Real margin = Real(0x1p-18) * max3(glm::max(abs_of(e1), abs_of(e2)));
  const Vec error = Real(4.1 * 0x1p-24) * (abs_of(ue1) + abs_of(ve2)) + margin;
  return {p, 1.01f * 0x1p-24f * abs_of(p) + glm::vec3(error)};
}

// The same from float corners. A triangle whose edges overflow float (corners beyond ±1.7e38)
// is done in double, from the same corners.
inline SpawnPoint spawn_point(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, float u,
                              float v) {
  const glm::vec3 e1 = b - a, e2 = c - a;
  if (std::isfinite(e1.x + e1.y + e1.z + e2.x + e2.y + e2.z))
    return spawn_point_of_edges(a, b, c, e1, e2, u, v);
  const glm::dvec3 ad(a), bd(b), cd(c);
  return spawn_point_of_edges(ad, bd, cd, bd - ad, cd - ad, u, v);
}

// Moves a spawn point off its surface along the geometric normal `n` (unit, pointing to the side
// the new ray leaves from), past the point's error bound: by dot(|n|, error) along n, then one
// float step further away in every component where n is not 0, so that the rounding of the sum
// cannot bring it back (pbrt-v4's OffsetRayOrigin). The point is then strictly on n's side of its
// triangle's plane, at any scale and distance from the origin, by a few ulps of the corners: a
// fixed number of ulps of |p| (Wächter and Binder below, 256 of them) was up to 2^-15 |p|, 3 units
// at 10^5 from the origin, and rays spawned in a box 2 wide started outside it.
inline glm::vec3 offset_ray_origin(const SpawnPoint& s, const glm::vec3& n) {
  const float d = glm::dot(abs_of(n), s.error);
  glm::vec3 out = s.p + d * n;
  for (int k = 0; k < 3; ++k) {
    if (n[k] > 0.f) out[k] = next_float_up(out[k]);
    if (n[k] < 0.f) out[k] = next_float_down(out[k]);
  }
  return out;
}

// How much of a shadow segment that ends at a point of a surface is left out at that end, as a
// fraction of its length: the spawn offset puts the end strictly off the surface, but a triangle
// test rounds t by a few ulps of t there (our test computes t exactly only near 0), so a segment
// that stops a few ulps of its length before the surface may still find it. pbrt-v4's
// ShadowEpsilon.
constexpr float shadow_epsilon = 1e-4f;

// Moves a point on a surface off it along the geometric normal `n` (pointing to the side the new
// ray leaves from), by an amount that scales with the point's magnitude: a few ulps in integer
// steps of the float representation far from the origin, a small fixed step near it.
// After Wächter and Binder, "A Fast and Robust Method for Avoiding Self-Intersection",
// Ray Tracing Gems, chapter 6. For points whose triangle is not known (the benchmarks' rays):
// the integrators use spawn_point and the offset above.
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
