// Geometry: every triangle of a scene, flattened to world space: its three corners side by side
// (36 bytes, so a triangle read anywhere costs one or two cache lines, not one per coordinate).
// All backends read the same arrays; a triangle's index here is the `prim` a hit reports.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "dacrt/tracer/aabb.h"

namespace dacrt {

struct Geometry {
  using Corners = std::array<glm::vec3, 3>;
  std::vector<Corners> corners;  // corners[triangle][corner]
  std::vector<uint32_t> material;

  size_t size() const { return material.size(); }

  void reserve(size_t n) {
    corners.reserve(n);
    material.reserve(n);
  }
  void resize(size_t n, uint32_t mat = 0) {
    corners.resize(n);
    material.resize(n, mat);
  }

  void add(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, uint32_t mat) {
    corners.push_back({a, b, c});
    material.push_back(mat);
  }

  const glm::vec3& vertex(size_t tri, int corner) const { return corners[tri][size_t(corner)]; }


  // Unnormalised geometric normal, (p1 - p0) x (p2 - p0): counter-clockwise is the front face.
  glm::vec3 normal(size_t tri) const {
    glm::vec3 a = vertex(tri, 0);
    return glm::cross(vertex(tri, 1) - a, vertex(tri, 2) - a);
  }

  // The cross product of the edges in double: finite and non-zero for every triangle of float
  // corners that has an area (in float, it overflows for edges beyond ~1e19 and underflows below
  // ~1e-19, and the edges of a triangle spanning ±2e38 are themselves infinite).
  glm::dvec3 normal_double(size_t tri) const {
    const glm::dvec3 a(vertex(tri, 0));
    return glm::cross(glm::dvec3(vertex(tri, 1)) - a, glm::dvec3(vertex(tri, 2)) - a);
  }
  // The unit geometric normal, at any scale (NaN for a triangle of no area, which nothing hits).
  // In float where the squared length is a normal float (per hit: double costs time), else in
  // double.
  glm::vec3 unit_normal(size_t tri) const {
    const glm::vec3 n = normal(tri);
    const float l2 = glm::dot(n, n);
    if (l2 >= 0x1p-100f && l2 < 0x1p100f) return n / std::sqrt(l2);
    const glm::dvec3 nd = normal_double(tri);
    return glm::vec3(nd / std::sqrt(glm::dot(nd, nd)));
  }
  // Its area, at any scale (in float it would overflow beyond ~1e19 and underflow below ~1e-19).
  double area(size_t tri) const {
    const glm::vec3 n = normal(tri);
    const float l2 = glm::dot(n, n);
    if (l2 >= 0x1p-100f && l2 < 0x1p100f) return 0.5 * double(std::sqrt(l2));
    return 0.5 * glm::length(normal_double(tri));
  }

  Box bounds() const {
    Box b;
    for (size_t i = 0; i < size(); ++i)
      for (int k = 0; k < 3; ++k) b.extend(vertex(i, k));
    return b;
  }
};

static_assert(sizeof(Geometry::Corners) == 36, "a triangle's nine floats, unpadded");

}  // namespace dacrt
