// The watertight ray/triangle test shared by every backend of ours (Woop, Benthin, Wald, JCGT
// 2013): the triangle is translated to the ray origin and sheared so the ray becomes +z; the 2D
// edge functions then decide inside/outside exactly the same way for two triangles sharing an edge,
// so no ray slips between them. Edge functions that round to exactly zero are recomputed in double.
#pragma once

#include <glm/glm.hpp>

#include "tracer/ray.h"

namespace dacrt {

struct TriangleHit {
  float t, u, v;  // u, v: barycentric weights of corners 1 and 2
};

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
  if ((e0 < 0.f || e1 < 0.f || e2 < 0.f) && (e0 > 0.f || e1 > 0.f || e2 > 0.f)) return false;
  const float det = e0 + e1 + e2;
  if (det == 0.f || !std::isfinite(det)) return false;

  const float az = r.sz * a[r.kz], bz = r.sz * b[r.kz], cz = r.sz * c[r.kz];
  const float t = (e0 * az + e1 * bz + e2 * cz) / det;
  if (!(t >= tmin && t <= tmax)) return false;
  hit.t = t;
  hit.u = e1 / det;
  hit.v = e2 / det;
  return true;
}

// The order every backend uses to pick among hits: nearest t, then the lower triangle index. With
// it the closest hit is unique, whatever order the triangles are visited in.
inline bool closer(float t, uint32_t prim, float best_t, uint32_t best_prim) {
  return t < best_t || (t == best_t && prim < best_prim);
}

}  // namespace dacrt
