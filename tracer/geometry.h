// Geometry: every triangle of a scene, flattened to world space, as structure-of-arrays.
// All backends read the same arrays; a triangle's index here is the `prim` a hit reports.
#pragma once

#include <array>
#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "tracer/aabb.h"

namespace dacrt {

struct Geometry {
  // p[corner][axis][triangle]
  std::array<std::array<std::vector<float>, 3>, 3> p;
  std::vector<uint32_t> material;

  size_t size() const { return material.size(); }

  void reserve(size_t n) {
    for (auto& corner : p)
      for (auto& axis : corner) axis.reserve(n);
    material.reserve(n);
  }

  void add(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, uint32_t mat) {
    const glm::vec3* corners[3] = {&a, &b, &c};
    for (int k = 0; k < 3; ++k)
      for (int axis = 0; axis < 3; ++axis) p[k][axis].push_back((*corners[k])[axis]);
    material.push_back(mat);
  }

  glm::vec3 vertex(size_t tri, int corner) const {
    return {p[corner][0][tri], p[corner][1][tri], p[corner][2][tri]};
  }

  // Unnormalised geometric normal, (p1 - p0) x (p2 - p0): counter-clockwise is the front face.
  glm::vec3 normal(size_t tri) const {
    glm::vec3 a = vertex(tri, 0);
    return glm::cross(vertex(tri, 1) - a, vertex(tri, 2) - a);
  }

  float area(size_t tri) const { return 0.5f * glm::length(normal(tri)); }

  Box bounds() const {
    Box b;
    for (size_t i = 0; i < size(); ++i)
      for (int k = 0; k < 3; ++k) b.extend(vertex(i, k));
    return b;
  }
};

}  // namespace dacrt
