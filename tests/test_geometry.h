// Geometry and ray generators shared by the backend tests: the five kinds of triangle sets the
// oracle comparison runs on, and rays that stress them; and the box and camera the render tests
// build their scenes from.
#pragma once

#include <atomic>
#include <cmath>
#include <glm/glm.hpp>
#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "dacrt/scene/camera.h"
#include "dacrt/tracer/backend.h"
#include "dacrt/tracer/geometry.h"
#include "dacrt/tracer/ray.h"
#include "dacrt/tracer/ray_batch.h"
#include "dacrt/util/random.h"

namespace dacrt::test {

inline glm::vec3 random_in(Pcg32& rng, const glm::vec3& lo, const glm::vec3& hi) {
  return lo + (hi - lo) * glm::vec3(rng.uniform(), rng.uniform(), rng.uniform());
}

inline glm::vec3 random_direction(Pcg32& rng) {
  float z = 1.f - 2.f * rng.uniform(), phi = 2.f * glm::pi<float>() * rng.uniform();
  float r = std::sqrt(std::max(0.f, 1.f - z * z));
  return {r * std::cos(phi), r * std::sin(phi), z};
}

// An axis-aligned box from -1 to 1, wound so its faces point inwards.
inline Geometry inward_box() {
  Geometry g;
  const glm::vec3 c[8] = {{-1, -1, -1}, {1, -1, -1}, {-1, 1, -1}, {1, 1, -1},
                          {-1, -1, 1},  {1, -1, 1},  {-1, 1, 1},  {1, 1, 1}};
  const int faces[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 2, 6, 4},
                           {1, 5, 7, 3}, {0, 4, 5, 1}, {2, 3, 7, 6}};
  for (const auto& f : faces) {
    g.add(c[f[0]], c[f[1]], c[f[2]], 0);
    g.add(c[f[0]], c[f[2]], c[f[3]], 0);
  }
  return g;
}

// A perspective camera at `eye` looking at `target`, +y up, of vertical field of view `yfov`.
inline Camera looking_at(const glm::vec3& eye, const glm::vec3& target, float yfov) {
  Camera cam;
  cam.yfov = yfov;
  cam.to_world = glm::inverse(glm::lookAt(eye, target, glm::vec3(0, 1, 0)));
  return cam;
}

// Random triangles of random sizes in the unit cube.
inline Geometry random_soup(size_t n, uint64_t seed) {
  Pcg32 rng(seed);
  Geometry g;
  for (size_t i = 0; i < n; ++i) {
    glm::vec3 c = random_in(rng, glm::vec3(0.f), glm::vec3(1.f));
    float s = 0.02f + 0.1f * rng.uniform();
    g.add(c + s * random_direction(rng), c + s * random_direction(rng),
          c + s * random_direction(rng), uint32_t(i % 3));
  }
  return g;
}

// A closed UV sphere: shared edges and vertices everywhere, optionally jittered radially (the
// jitter moves shared vertices consistently, so the mesh stays closed).
inline Geometry sphere(int rings, int segments, const glm::vec3& center, float radius,
                       float jitter = 0.f, uint64_t seed = 1) {
  auto vertex = [&](int ring, int seg) {
    if (ring == 0) return center + glm::vec3(0, radius, 0);
    if (ring == rings) return center - glm::vec3(0, radius, 0);
    seg %= segments;
    float theta = glm::pi<float>() * ring / rings, phi = 2.f * glm::pi<float>() * seg / segments;
    float r = radius * (1.f + jitter * (uniform_float(seed, ring, seg) - 0.5f));
    return center + r * glm::vec3(std::sin(theta) * std::cos(phi), std::cos(theta),
                                  std::sin(theta) * std::sin(phi));
  };
  Geometry g;
  for (int ring = 0; ring < rings; ++ring)
    for (int seg = 0; seg < segments; ++seg) {
      glm::vec3 a = vertex(ring, seg), b = vertex(ring, seg + 1);
      glm::vec3 c = vertex(ring + 1, seg), d = vertex(ring + 1, seg + 1);
      if (ring != 0) g.add(a, b, c, 0);
      if (ring != rings - 1) g.add(b, d, c, 0);
    }
  return g;
}

// An n × n grid of unit quads in the z = 0 plane, two triangles each.
inline Geometry quad_grid(int n, float cell = 1.f) {
  Geometry g;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      glm::vec3 a(x * cell, y * cell, 0), b((x + 1) * cell, y * cell, 0);
      glm::vec3 c(x * cell, (y + 1) * cell, 0), d((x + 1) * cell, (y + 1) * cell, 0);
      g.add(a, b, d, 0);
      g.add(a, d, c, 0);
    }
  return g;
}

// Long, thin triangles spanning the unit cube in random directions (poor boxes, many overlaps).
inline Geometry slivers(size_t n, uint64_t seed) {
  Pcg32 rng(seed);
  Geometry g;
  for (size_t i = 0; i < n; ++i) {
    glm::vec3 a = random_in(rng, glm::vec3(0.f), glm::vec3(1.f));
    glm::vec3 b = random_in(rng, glm::vec3(0.f), glm::vec3(1.f));
    glm::vec3 w = 0.002f * random_direction(rng);
    g.add(a, b, a + w, 0);
  }
  return g;
}

// Triangles of different shapes that all share one centroid exactly: corners c+u, c+v, c-u-v on a
// 1/64 lattice, so every sum is exact and binning cannot separate them.
inline Geometry one_centroid(size_t n, uint64_t seed) {
  Pcg32 rng(seed);
  Geometry g;
  const glm::vec3 c(0.5f);
  auto lattice = [&] {
    return glm::vec3(float(int(rng.below(51)) - 25), float(int(rng.below(51)) - 25),
                     float(int(rng.below(51)) - 25)) /
           64.f;
  };
  for (size_t i = 0; i < n; ++i) {
    glm::vec3 u = lattice(), v = lattice();
    g.add(c + u, c + v, c - u - v, 0);
  }
  return g;
}

// Triangles of different shapes whose bounding boxes all share one centre exactly (what the DACRT
// kernel bins on): corners c+u, c-u and c+w with |w| <= |u| on every axis, on a lattice of exact
// binary fractions.
inline Geometry one_box_center(size_t n, uint64_t seed) {
  Pcg32 rng(seed);
  Geometry g;
  const glm::vec3 c(0.5f);
  for (size_t i = 0; i < n; ++i) {
    glm::vec3 u, w;
    for (int a = 0; a < 3; ++a) {
      u[a] = float(int(rng.below(51)) - 25) / 64.f;
      w[a] = u[a] * float(int(rng.below(5)) - 2) / 2.f;  // -u, -u/2, 0, u/2, u
    }
    g.add(c + u, c - u, c + w, 0);
  }
  return g;
}

// Random rays: origins in the box grown by half its size, uniform directions.
inline RayBatch random_rays(const Geometry& g, size_t n, uint64_t seed, RayType type) {
  Pcg32 rng(seed);
  Box b = g.bounds();
  glm::vec3 grow = 0.5f * b.extent() + glm::vec3(0.1f);
  RayBatch rays;
  rays.type = type;
  rays.resize(n);
  for (size_t i = 0; i < n; ++i) {
    float tmax = rng.uniform() < 0.2f ? 0.3f + rng.uniform() : INFINITY;
    rays.set(i, random_in(rng, b.lo - grow, b.hi + grow), random_direction(rng), 0.f, tmax,
             uint32_t(i));
  }
  return rays;
}

// Rays from a random point (by barycentrics) of a random triangle, tmin 0: exactly on the
// triangle, or, with `offset`, moved off it by offset_ray_origin to the side the ray leaves from,
// as the integrator spawns rays.
inline RayBatch surface_rays(const Geometry& g, size_t n, uint64_t seed, bool offset = false) {
  Pcg32 rng(seed);
  RayBatch rays;
  rays.type = RayType::bounce;
  rays.resize(n);
  for (size_t i = 0; i < n; ++i) {
    uint32_t tri = rng.below(uint32_t(g.size()));
    float u = rng.uniform(), v = rng.uniform();
    if (u + v > 1.f) u = 1.f - u, v = 1.f - v;
    glm::vec3 p = (1.f - u - v) * g.vertex(tri, 0) + u * g.vertex(tri, 1) + v * g.vertex(tri, 2);
    glm::vec3 d = random_direction(rng), normal = g.normal(tri);
    if (offset && glm::dot(normal, normal) > 0.f) {
      normal = glm::normalize(normal);
      p = offset_ray_origin(p, glm::dot(normal, d) < 0.f ? -normal : normal);
    }
    rays.set(i, p, d, 0.f, INFINITY, uint32_t(i));
  }
  return rays;
}

// Rays towards quad_grid(8, 0.125f) (the z = 0 plane, x and y in [0, 1]) that every backend must
// survive: rays 0 and 1 hit it at t = 1 (the second with tmin == tmax == 1), every other one
// is NaN, infinite, zero-length or inactive somewhere, or ends before the plane, and misses.
inline RayBatch degenerate_rays() {
  RayBatch rays;
  const float nan = std::nanf(""), inf = INFINITY;
  const glm::vec3 o(0.5f, 0.5f, 1.f), down(0.f, 0.f, -1.f);
  rays.push(o, down, 0.f, inf, 0);                          // a good ray
  rays.push(o, down, 1.f, 1.f, 1);                          // tmin == tmax == the hit
  rays.push(glm::vec3(nan, 0.5f, 1.f), down, 0.f, inf, 2);  // NaN origin
  rays.push(o, glm::vec3(0.f, nan, -1.f), 0.f, inf, 3);     // NaN direction
  rays.push(glm::vec3(inf, 0.5f, 1.f), down, 0.f, inf, 4);  // inf origin
  rays.push(o, glm::vec3(0.f, 0.f, -inf), 0.f, inf, 5);     // inf direction
  rays.push(o, glm::vec3(0.f), 0.f, inf, 6);                // zero direction
  rays.push(o, down, 2.f, 1.f, 7);                          // tmin > tmax
  rays.push(o, down, nan, inf, 8);                          // NaN tmin
  rays.push(o, down, 0.f, nan, 9);                          // NaN tmax
  rays.push(o, down, 0.f, 0.5f, 10);                        // ends before the plane
  rays.push(o, down, inf, inf, 11);                         // starts at infinity
  rays.push(o, down, -inf, -inf, 12);                       // ends at minus infinity
  return rays;
}

// Rays along ±x, ±y, ±z (zero direction components), from a grid of origins around the box.
inline RayBatch axis_rays(const Geometry& g, size_t n, uint64_t seed) {
  Pcg32 rng(seed);
  Box b = g.bounds();
  RayBatch rays;
  rays.type = RayType::primary;
  rays.resize(n);
  for (size_t i = 0; i < n; ++i) {
    int axis = int(rng.below(3));
    float sign = rng.below(2) ? 1.f : -1.f;
    glm::vec3 d(0.f);
    d[axis] = sign;
    glm::vec3 o = random_in(rng, b.lo, b.hi);
    // Snap some origins onto box and grid coordinates so rays run exactly along faces and edges.
    if (rng.below(4) == 0)
      for (int k = 0; k < 3; ++k) o[k] = std::round(o[k] * 4.f) / 4.f;
    o[axis] = sign > 0 ? b.lo[axis] - 1.f : b.hi[axis] + 1.f;
    rays.set(i, o, d, 0.f, INFINITY, uint32_t(i));
  }
  return rays;
}

// Rays whose largest direction components tie exactly: two components (or all three) of equal
// magnitude, the others smaller, from anywhere in the geometry's box and around it. The shear
// (Ray::shear) must pick its axis among the tied ones as every backend does.
inline RayBatch diagonal_rays(const Geometry& g, size_t n, uint64_t seed) {
  Pcg32 rng(seed);
  Box b = g.bounds();
  const glm::vec3 margin = 0.5f * (b.hi - b.lo);
  RayBatch rays;
  rays.type = RayType::bounce;
  rays.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const float m = 1.f + rng.uniform();
    const int odd = int(rng.below(4));  // the component that does not tie (3: none)
    glm::vec3 d;
    for (int k = 0; k < 3; ++k) {
      const float sign = rng.below(2) ? 1.f : -1.f;
      d[k] = sign * (k == odd ? m * rng.uniform() : m);
    }
    rays.set(i, random_in(rng, b.lo - margin, b.hi + margin), d, 0.f, INFINITY, uint32_t(i));
  }
  return rays;
}

// A hit filter for backend tests: every other triangle is tested, and there a hit counts where
// u + v < 0.6 (a mask) or for about half of the (ray, triangle) pairs (a coin): a function of
// (ray, triangle, u, v) alone, as backends require.
class TestFilter final : public HitFilter {
 public:
  explicit TestFilter(size_t triangles) : HitFilter(every_other(triangles)) {}
  bool accept(const RayBatch&, uint32_t ray, uint32_t tri, float u, float v) const override {
    calls.fetch_add(1, std::memory_order_relaxed);
    return u + v < 0.6f || (hash(ray, tri) & 1) != 0;
  }
  mutable std::atomic<size_t> calls{0};

 private:
  static std::vector<uint8_t> every_other(size_t n) {
    std::vector<uint8_t> tested(n, 0);
    for (size_t i = 0; i < n; i += 2) tested[i] = 1;
    return tested;
  }
};

}  // namespace dacrt::test
