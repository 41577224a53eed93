// RayBatch and HitBatch: the structure-of-arrays currency between integrators and backends.
// One batch holds rays of one type, so that statistics are kept per ray type.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <string_view>
#include <vector>

#include "dacrt/util/large_array.h"

namespace dacrt {

enum class RayType : uint8_t { primary, shadow, bounce };
inline constexpr int ray_type_count = 3;

constexpr std::string_view to_string(RayType type) {
  switch (type) {
    case RayType::primary:
      return "primary";
    case RayType::shadow:
      return "shadow";
    case RayType::bounce:
      return "bounce";
  }
  return "?";
}

struct RayBatch {
  RayType type = RayType::primary;
  Array<float> ox, oy, oz, dx, dy, dz, tmin, tmax;
  Array<uint32_t> path;  // index back to the path (or pixel) that made the ray

  size_t size() const { return ox.size(); }
  void resize(size_t n) {
    for (auto* a : {&ox, &oy, &oz, &dx, &dy, &dz, &tmin, &tmax}) a->resize(n);
    path.resize(n);
  }
  void clear() { resize(0); }

  void set(size_t i, const glm::vec3& o, const glm::vec3& d, float t0, float t1, uint32_t p) {
    ox[i] = o.x, oy[i] = o.y, oz[i] = o.z;
    dx[i] = d.x, dy[i] = d.y, dz[i] = d.z;
    tmin[i] = t0, tmax[i] = t1, path[i] = p;
  }
  void push(const glm::vec3& o, const glm::vec3& d, float t0, float t1, uint32_t p) {
    resize(size() + 1);
    set(size() - 1, o, d, t0, t1, p);
  }
  glm::vec3 origin(size_t i) const { return {ox[i], oy[i], oz[i]}; }
  glm::vec3 direction(size_t i) const { return {dx[i], dy[i], dz[i]}; }
};

struct HitBatch {
  static constexpr uint32_t miss = ~0u;
  Array<float> t, u, v;  // u, v: barycentric weights of corners 1 and 2
  Array<uint32_t> prim;  // triangle index into Geometry, or `miss`

  size_t size() const { return prim.size(); }
  void resize(size_t n) {
    t.resize(n), u.resize(n), v.resize(n);
    prim.resize(n);
  }
  bool hit(size_t i) const { return prim[i] != miss; }
};

}  // namespace dacrt
