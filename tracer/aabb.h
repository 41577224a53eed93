// Box: an axis-aligned bounding box. Boxes are built from exact vertex coordinates (min/max never
// rounds); the conservative ray test that uses them lives in ray.h.
#pragma once

#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>
#include <limits>

namespace dacrt {

// |v| per component. glm::abs is a compare and a branch per component (x >= 0 ? x : -x); this is
// one sign-clearing instruction each, and the same values (up to the sign of a zero).
template <typename Vec>
Vec abs_of(const Vec& v) {
  return {std::abs(v.x), std::abs(v.y), std::abs(v.z)};
}

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
    glm::vec3 m = glm::max(abs_of(lo), abs_of(hi));
    return std::max({m.x, m.y, m.z});
  }
};

}  // namespace dacrt
