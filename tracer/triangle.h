// The watertight ray/triangle test shared by every backend of ours (Woop, Benthin, Wald, JCGT
// 2013): the triangle is translated to the ray origin and sheared so the ray becomes +z; the 2D
// edge functions then decide inside/outside exactly the same way for two triangles sharing an edge,
// so no ray slips between them. Edge functions that round to exactly zero are recomputed in double.
#pragma once

#include <algorithm>
#include <glm/glm.hpp>

#include "dacrt/tracer/ray.h"

namespace dacrt {

struct TriangleHit {
  float t, u, v;  // u, v: barycentric weights of corners 1 and 2
};

// The Woop test's t in double precision from the float inputs (NaN if the sheared triangle is
// degenerate in double too), clamped to the t range in which the ray is inside the triangle's
// bounding box (NaN if it never is). A hit point is a convex combination of the corners, so its
// exact t lies in that range, and clamping changes no t that means anything. It matters for a ray
// lying (up to rounding) in the triangle's plane: the sheared triangle is then a segment, e0, e1,
// e2 and det are rounding noise, and their ratio may be any t, of either sign: 0.57 for a triangle
// wholly behind the origin, -0 for one at t = 1 (tests/stress_test.cpp). Such a t is far from the
// triangle, where DACRT's box test (padded for rounding only) rightly culls the triangle's box,
// so DACRT and brute force disagreed.
inline double exact_t(const Ray& r, const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2) {
  const glm::dvec3 o(r.o), a = glm::dvec3(p0) - o, b = glm::dvec3(p1) - o, c = glm::dvec3(p2) - o;
  const double dz = r.d[r.kz], sx = r.d[r.kx] / dz, sy = r.d[r.ky] / dz;
  const double ax = a[r.kx] - sx * a[r.kz], ay = a[r.ky] - sy * a[r.kz];
  const double bx = b[r.kx] - sx * b[r.kz], by = b[r.ky] - sy * b[r.kz];
  const double cx = c[r.kx] - sx * c[r.kz], cy = c[r.ky] - sy * c[r.kz];
  const double e0 = cx * by - cy * bx, e1 = ax * cy - ay * cx, e2 = bx * ay - by * ax;
  const double det = e0 + e1 + e2;
  if (det == 0.0) return NAN;
  const double t = (e0 * a[r.kz] + e1 * b[r.kz] + e2 * c[r.kz]) / dz / det;
  double lo = -INFINITY, hi = INFINITY;  // where the ray is inside the triangle's bounding box
  for (int k = 0; k < 3; ++k) {
    const double box_lo = std::min({a[k], b[k], c[k]}), box_hi = std::max({a[k], b[k], c[k]});
    if (r.d[k] == 0.f) {
      if (box_lo > 0.0 || box_hi < 0.0) return NAN;  // parallel to the slab, outside it
      continue;
    }
    const double t0 = box_lo / r.d[k], t1 = box_hi / r.d[k];
    lo = std::max(lo, std::min(t0, t1)), hi = std::min(hi, std::max(t0, t1));
  }
  if (lo > hi) {  // a ray that misses the box, unless only by the rounding of the divisions
    if (lo - hi > 0x1p-40 * std::max(std::abs(lo), std::abs(hi))) return NAN;
    hi = lo;
  }
  return std::clamp(t, lo, hi);  // NaN stays NaN
}

// The whole test in double from the float inputs, for a triangle whose float edge functions
// overflow or underflow: corners beyond ~1e12 or within ~1e-12 of the ray's origin in the
// sheared frame (a glTF node scale of 1e30 or 1e-30; a triangle spanning ±3e38, whose differences
// to the origin overflow float). Double holds the products of any two float coordinates, so the
// inside test is as watertight as the float one; the shear constants are the float ones, so it
// places shared edges where the float test does. t is exact_t's.
inline bool intersect_triangle_wide(const Ray& r, const glm::vec3& p0, const glm::vec3& p1,
                                    const glm::vec3& p2, float tmin, float tmax, TriangleHit& hit) {
  const glm::dvec3 o(r.o), a = glm::dvec3(p0) - o, b = glm::dvec3(p1) - o, c = glm::dvec3(p2) - o;
  const double sx = r.sx, sy = r.sy;
  const double ax = a[r.kx] - sx * a[r.kz], ay = a[r.ky] - sy * a[r.kz];
  const double bx = b[r.kx] - sx * b[r.kz], by = b[r.ky] - sy * b[r.kz];
  const double cx = c[r.kx] - sx * c[r.kz], cy = c[r.ky] - sy * c[r.kz];
  const double e0 = cx * by - cy * bx, e1 = ax * cy - ay * cx, e2 = bx * ay - by * ax;
  if ((e0 < 0.0 || e1 < 0.0 || e2 < 0.0) && (e0 > 0.0 || e1 > 0.0 || e2 > 0.0)) return false;
  const double det = e0 + e1 + e2;
  if (det == 0.0 || !std::isfinite(det)) return false;
  const float t = float(exact_t(r, p0, p1, p2));
  if (!(t >= tmin && t <= tmax)) return false;
  hit.t = t;
  hit.u = float(e1 / det);
  hit.v = float(e2 / det);
  return true;
}

// The error bound of the float test's t (Pharr, Jakob and Humphreys, "Physically Based
// Rendering", 3rd ed., section 3.9.6), times |det|: from the largest magnitudes of the sheared
// corners' x, y and z and of the edge functions. A float t with |t| |det| above it has the sign
// (and the range test) of the exact t; the factor 1 + 2^-20 covers the rounding of the product
// |t| |det| and of this sum. The vector test (tracer/triangle_block.cpp) repeats these operations in
// the same order.
inline float t_error_times_det(float max_x, float max_y, float max_z, float max_e) {
  constexpr auto gamma = [](int n) { return n * 0x1p-24f / (1.f - n * 0x1p-24f); };
  const float delta_z = gamma(3) * max_z;
  const float delta_x = gamma(5) * (max_x + max_z), delta_y = gamma(5) * (max_y + max_z);
  const float delta_e = 2.f * (gamma(2) * max_x * max_y + delta_y * max_x + delta_x * max_y);
  return (3.f * (1.f + 0x1p-20f)) *
         (gamma(3) * max_e * max_z + delta_e * max_z + delta_z * max_e);
}

// Accepts hits with tmin <= t <= tmax, from either side. Degenerate triangles never hit.
inline bool intersect_triangle(const Ray& r, const glm::vec3& p0, const glm::vec3& p1,
                               const glm::vec3& p2, float tmin, float tmax, TriangleHit& hit) {
  const glm::vec3 a = p0 - r.o, b = p1 - r.o, c = p2 - r.o;
  const float ax = a[r.kx] - r.sx * a[r.kz], ay = a[r.ky] - r.sy * a[r.kz];
  const float bx = b[r.kx] - r.sx * b[r.kz], by = b[r.ky] - r.sy * b[r.kz];
  const float cx = c[r.kx] - r.sx * c[r.kz], cy = c[r.ky] - r.sy * c[r.kz];

  float e0 = cx * by - cy * bx;  // weight of corner 0
  float e1 = ax * cy - ay * cx;  // weight of corner 1
  float e2 = bx * ay - by * ax;  // weight of corner 2
  if (e0 == 0.f || e1 == 0.f || e2 == 0.f) {
    e0 = float(double(cx) * double(by) - double(cy) * double(bx));
    e1 = float(double(ax) * double(cy) - double(ay) * double(cx));
    e2 = float(double(bx) * double(ay) - double(by) * double(ax));
  }
  const float det = e0 + e1 + e2;
  // det is twice the sheared triangle's area, of the size of its coordinates squared: out of
  // [2^-80, inf), the float edge functions (or t's numerator, of their size cubed) over- or
  // underflowed, or the triangle is degenerate. (NaN, from inf - inf, is out too.)
  if (!(std::abs(det) >= 0x1p-80f && std::abs(det) < INFINITY))
    return intersect_triangle_wide(r, p0, p1, p2, tmin, tmax, hit);
  if ((e0 < 0.f || e1 < 0.f || e2 < 0.f) && (e0 > 0.f || e1 > 0.f || e2 > 0.f)) return false;

  const float az = r.sz * a[r.kz], bz = r.sz * b[r.kz], cz = r.sz * c[r.kz];
  const float t = (e0 * az + e1 * bz + e2 * cz) / det;
  // A t within its own rounding error of 0 cannot tell which side of the origin the hit is on (a
  // ray leaving a long sliver could hit it again at a tiny t), and a t that overflowed (corners
  // beyond ~1e12) is no t at all. Only then, t is computed again in double from the input
  // coordinates, and decides; inside or outside stays the float test's decision, so watertightness
  // is untouched. The error bound (t_error_times_det) is evaluated for hits only.
  // The bound is evaluated before the range is checked: a t within its error of 0 may be out of
  // range while the exact one is not, and rejecting it then would make the answer depend on the
  // tmax a backend has reached (a fuzzing finding, tests/fuzz/disagree-2.gltf).
  bool exact = !std::isfinite(t);
  if (!exact) {
    const float max_z = std::max({std::abs(az), std::abs(bz), std::abs(cz)});
    const float max_x = std::max({std::abs(ax), std::abs(bx), std::abs(cx)});
    const float max_y = std::max({std::abs(ay), std::abs(by), std::abs(cy)});
    const float max_e = std::max({std::abs(e0), std::abs(e1), std::abs(e2)});
    exact = !(std::abs(t) * std::abs(det) > t_error_times_det(max_x, max_y, max_z, max_e));
    if (!exact && !(t >= tmin && t <= tmax)) return false;
  }
  if (exact) {
    // The rounded t is compared, as in the float path: two hits whose double t round to the same
    // float must both pass a tmax equal to it, or which one wins the tie would depend on the order
    // the triangles are visited in (a fuzzing finding: tests/fuzz/disagree-1.gltf).
    const float t_exact = float(exact_t(r, p0, p1, p2));
    if (!(t_exact >= tmin && t_exact <= tmax)) return false;
    hit.t = t_exact;
    hit.u = e1 / det;
    hit.v = e2 / det;
    return true;
  }
  hit.t = t;
  hit.u = e1 / det;
  hit.v = e2 / det;
  return true;
}

// The order every backend uses to pick among hits: nearest t, then the lower triangle index. With
// it the closest hit is unique, whatever order the triangles are visited in. The best hit's
// triangle is read only for a tie: in DACRT's leaves it lives in the batch, out of the rays'
// order, and reading it for every hit found was a cache miss each.
inline bool closer(float t, uint32_t prim, float best_t, const uint32_t* best_prim) {
  return t < best_t || (t == best_t && prim < *best_prim);
}

}  // namespace dacrt
