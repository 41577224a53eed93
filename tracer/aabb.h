// Box: an axis-aligned bounding box. Boxes are built from exact vertex coordinates (min/max never
// rounds); the conservative ray test that uses them lives in ray.h.
#pragma once

#include <algorithm>
#include <glm/glm.hpp>
#include <limits>

namespace dacrt {

struct Box {
  glm::vec3 lo{std::numeric_limits<float>::infinity()};
  glm::vec3 hi{-std::numeric_limits<float>::infinity()};

  bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
  void extend(const glm::vec3& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  void extend(const Box& b) {
    lo = glm::min(lo, b.lo);
    hi = glm::max(hi, b.hi);
  }
  glm::vec3 extent() const { return empty() ? glm::vec3(0.f) : hi - lo; }
  glm::vec3 center() const { return 0.5f * (lo + hi); }
  int longest_axis() const {
    glm::vec3 e = extent();
    return e.x >= e.y ? (e.x >= e.z ? 0 : 2) : (e.y >= e.z ? 1 : 2);
  }
  float half_area() const {
    glm::vec3 e = extent();
    return e.x * e.y + e.y * e.z + e.z * e.x;
  }
  // Largest absolute coordinate: the scale of rounding errors for anything inside the box.
  float magnitude() const {
    if (empty()) return 0.f;
    glm::vec3 m = glm::max(glm::abs(lo), glm::abs(hi));
    return std::max({m.x, m.y, m.z});
  }
};

}  // namespace dacrt
