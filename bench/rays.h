// Benchmark rays: the five ray types `dacrt bench` times, generated once per batch so that every
// backend traces exactly the same rays. Header-only so that the tests can use them directly.
//   primary  the scene camera's pinhole rays, one per pixel centre
//   shadow   from primary hits to random points on emitters (or, without emitters, to a point
//            above the scene); traced with `occluded`
//   ao       from primary hits, cosine-weighted around the normal, tmax = 10 % of the scene's
//            bounding-box diagonal; traced with `occluded`
//   bounce   from primary hits, cosine-weighted around the normal, tmax = inf; `intersect`
//   random   uniform origins inside the scene's box, uniform directions, tmax = inf; `intersect`
// Secondary rays (shadow, ao, bounce) start at the primary hits found by one reference backend;
// primary misses have no surface, so they make no secondary rays. Ray i of a secondary batch
// starts at surface point i mod (number of points), so any count can be drawn from any number of
// hits. All randomness is hash-based on (seed, ray type, i): a batch depends on nothing but its
// inputs, whatever the thread count.
#pragma once

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <glm/glm.hpp>
#include <glm/gtc/constants.hpp>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "materials/sampling.h"
#include "scene/camera.h"
#include "scene/scene.h"
#include "tracer/ray.h"
#include "tracer/ray_batch.h"
#include "util/alias_table.h"
#include "util/random.h"

namespace dacrt::bench {

enum class BenchRay : uint8_t { primary, shadow, ao, bounce, random };
inline constexpr BenchRay all_bench_rays[] = {BenchRay::primary, BenchRay::shadow, BenchRay::ao,
                                              BenchRay::bounce, BenchRay::random};

constexpr std::string_view to_string(BenchRay r) {
  switch (r) {
    case BenchRay::primary:
      return "primary";
    case BenchRay::shadow:
      return "shadow";
    case BenchRay::ao:
      return "ao";
    case BenchRay::bounce:
      return "bounce";
    case BenchRay::random:
      return "random";
  }
  return "?";
}

inline std::optional<BenchRay> bench_ray_from(std::string_view name) {
  for (BenchRay r : all_bench_rays)
    if (to_string(r) == name) return r;
  return std::nullopt;
}

// Shadow and ambient-occlusion rays ask `occluded`; the others ask `intersect`.
constexpr bool uses_occluded(BenchRay r) {
  return r == BenchRay::shadow || r == BenchRay::ao;
}

// The RayBatch tag that statistics would file the rays under.
constexpr RayType batch_type(BenchRay r) {
  return r == BenchRay::primary ? RayType::primary
         : uses_occluded(r)     ? RayType::shadow
                                : RayType::bounce;
}

inline constexpr float infinity = std::numeric_limits<float>::infinity();

// Points where primary rays hit, with the unit geometric normal turned towards the camera.
struct SurfacePoints {
  std::vector<glm::vec3> point, normal;
  std::vector<uint32_t> pixel;  // the primary ray (pixel) the point came from

  size_t size() const { return point.size(); }
};

// A uniform in [0, 1) for dimension `dim` of ray `i` of ray type `r`.
inline float random01(uint64_t seed, BenchRay r, size_t i, int dim) {
  return uniform_float(seed, uint64_t(r), uint64_t(i), uint64_t(dim));
}

// Splits [0, n) over the TBB workers; `body(i)` fills element i.
template <typename Body>
void for_each_index(size_t n, const Body& body) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const auto& range) {
    for (size_t i = range.begin(); i != range.end(); ++i) body(i);
  });
}

// Resolution for about `count` pixels in the given aspect ratio (width / height; <= 0 = square).
// Neither side is over 32 768 (the limit of --width and --height), whatever the aspect.
inline glm::ivec2 resolution_for_count(size_t count, float aspect) {
  double a = aspect > 0.f ? double(aspect) : 1.0;
  auto side = [](double s) { return int(std::clamp(std::lround(s), 1l, long(1) << 15)); };
  return {side(std::sqrt(double(count) * a)), side(std::sqrt(double(count) / a))};
}

// One ray per pixel, through the pixel centre; ray i is pixel (i mod width, i / width).
inline RayBatch primary_rays(const Camera& camera, int width, int height) {
  RayBatch b;
  b.type = RayType::primary;
  b.resize(size_t(width) * size_t(height));
  for_each_index(b.size(), [&](size_t i) {
    glm::vec3 o, d;
    camera_ray(camera, width, height, float(i % size_t(width)) + 0.5f,
               float(i / size_t(width)) + 0.5f, o, d);
    b.set(i, o, d, 0.f, infinity, uint32_t(i));
  });
  return b;
}

// The surface points of the rays that hit, in ray order; misses (and degenerate triangles,
// which have no normal) are dropped.
inline SurfacePoints surface_points(const Geometry& g, const RayBatch& rays, const HitBatch& hits) {
  SurfacePoints s;
  for (size_t i = 0; i < rays.size(); ++i) {
    if (!hits.hit(i)) continue;
    uint32_t tri = hits.prim[i];
    glm::vec3 n = g.normal(tri);
    float len = glm::length(n);
    if (!(len > 0.f) || !std::isfinite(len)) continue;
    n /= len;
    if (glm::dot(n, rays.direction(i)) > 0.f) n = -n;
    // From the barycentrics rather than o + t·d: the point lies on the triangle up to rounding.
    float u = hits.u[i], v = hits.v[i];
    s.point.push_back((1.f - u - v) * g.vertex(tri, 0) + u * g.vertex(tri, 1) +
                      v * g.vertex(tri, 2));
    s.normal.push_back(n);
    s.pixel.push_back(rays.path[i]);
  }
  return s;
}

// Where shadow rays aim when the scene has no emitters: above the centre of the box by twice its
// largest side, so that every point of the scene sees it from about the same direction.
inline glm::vec3 point_above(const Box& bounds) {
  glm::vec3 e = bounds.extent();
  return bounds.center() + glm::vec3(0.f, 2.f * std::max({e.x, e.y, e.z}), 0.f);
}

// Where shadow rays end: the scene's emitters, as a renderer's next-event estimation would aim
// at them, but chosen simply (the benchmark times the backends, not a light sampler): an emissive
// triangle in proportion to its area, then a point uniform on it, or one of the punctual lights,
// each as likely as the others; half and half when the scene has both.
class ShadowTargets {
 public:
  explicit ShadowTargets(const Scene& scene) : lights_(scene.lights.size()) {
    std::vector<double> area;
    for (uint32_t tri = 0; tri < scene.geometry.size(); ++tri) {
      const double a = scene.geometry.area(tri);
      if (!scene.materials[scene.geometry.material[tri]].emissive() || !(a > 0.0)) continue;
      triangles_.push_back(tri);
      area.push_back(a);
    }
    if (!area.empty()) table_ = AliasTable(area);
  }
  bool empty() const { return triangles_.empty() && lights_ == 0; }

  struct Target {
    int light;              // index into Scene::lights, or -1 for a triangle
    uint32_t triangle;      // when light is -1
    glm::vec2 barycentric;  // of the point on the triangle
  };
  // u picks the emitter, (u1, u2) the point on a triangle. Not for an empty set.
  Target pick(float u, float u1, float u2) const {
    const float share = triangles_.empty() ? 0.f : lights_ == 0 ? 1.f : 0.5f;
    if (u >= share) {
      const float v = (u - share) / (1.f - share);
      return {int(std::min(size_t(v * float(lights_)), lights_ - 1)), 0, glm::vec2(0.f)};
    }
    const size_t entry = table_.sample(u / share);
    const float r = std::sqrt(u1);  // uniform on the triangle
    return {-1, triangles_[entry], glm::vec2(r * (1.f - u2), r * u2)};
  }

 private:
  std::vector<uint32_t> triangles_;
  AliasTable table_;  // over triangles_, by area
  size_t lights_;
};

// `count` shadow rays; ray i starts at surface point i mod |points|. The origin is offset along
// the normal facing the target and the segment ends at the sampled emitter point, itself offset
// along the emitter's normal towards the origin, so neither end can report its own triangle.
inline RayBatch shadow_rays(const Scene& scene, const ShadowTargets& targets,
                            const SurfacePoints& points, size_t count, uint64_t seed) {
  RayBatch b;
  b.type = RayType::shadow;
  if (points.size() == 0) return b;
  b.resize(count);
  const glm::vec3 above = point_above(scene.bounds());
  for_each_index(count, [&](size_t i) {
    size_t j = i % points.size();
    glm::vec3 p = points.point[j], n = points.normal[j];
    glm::vec3 target = above;
    std::optional<uint32_t> light;
    if (!targets.empty()) {
      const ShadowTargets::Target s = targets.pick(random01(seed, BenchRay::shadow, i, 0),
                                                   random01(seed, BenchRay::shadow, i, 1),
                                                   random01(seed, BenchRay::shadow, i, 2));
      if (s.light < 0) {
        const Geometry& g = scene.geometry;
        target = (1.f - s.barycentric.x - s.barycentric.y) * g.vertex(s.triangle, 0) +
                 s.barycentric.x * g.vertex(s.triangle, 1) + s.barycentric.y * g.vertex(s.triangle, 2);
        light = s.triangle;
      } else {  // a punctual light: its position, or far up its beam for a directional one
        const PunctualLight& l = scene.lights[size_t(s.light)];
        target = l.type == PunctualLight::Type::directional
                     ? p - l.direction * (2.f * glm::length(scene.bounds().extent()) + 1.f)
                     : l.position;
      }
    }
    if (glm::dot(n, target - p) < 0.f) n = -n;
    glm::vec3 o = offset_ray_origin(p, n);
    if (light) {
      glm::vec3 ln = scene.geometry.normal(*light);
      if (glm::dot(ln, o - target) < 0.f) ln = -ln;
      float len = glm::length(ln);
      if (len > 0.f) target = offset_ray_origin(target, ln / len);
    }
    glm::vec3 d = target - o;
    float dist = glm::length(d);
    if (!(dist > 0.f)) {  // the point is the target: a zero-length, never-occluded segment
      b.set(i, o, glm::vec3(0.f, 1.f, 0.f), 0.f, 0.f, points.pixel[j]);
      return;
    }
    b.set(i, o, d / dist, 0.f, dist, points.pixel[j]);
  });
  return b;
}

// `count` cosine-weighted rays around the surface normals (ray i from point i mod |points|),
// with the given tmax: ambient occlusion (10 % of the diagonal) or diffuse bounces (inf).
inline RayBatch hemisphere_rays(BenchRay kind, const SurfacePoints& points, size_t count,
                                float tmax, uint64_t seed) {
  RayBatch b;
  b.type = batch_type(kind);
  if (points.size() == 0) return b;
  b.resize(count);
  for_each_index(count, [&](size_t i) {
    size_t j = i % points.size();
    const glm::vec3& n = points.normal[j];
    glm::vec3 local =
        sample_cosine_hemisphere(random01(seed, kind, i, 0), random01(seed, kind, i, 1));
    glm::vec3 d = glm::normalize(Frame(n).to_world(local));
    b.set(i, offset_ray_origin(points.point[j], n), d, 0.f, tmax, points.pixel[j]);
  });
  return b;
}

// tmax of ambient-occlusion rays: 10 % of the diagonal of the scene's box.
inline float ao_distance(const Box& bounds) {
  return 0.1f * glm::length(bounds.extent());
}

inline RayBatch ao_rays(const Scene& scene, const SurfacePoints& points, size_t count,
                        uint64_t seed) {
  return hemisphere_rays(BenchRay::ao, points, count, ao_distance(scene.bounds()), seed);
}

inline RayBatch bounce_rays(const SurfacePoints& points, size_t count, uint64_t seed) {
  return hemisphere_rays(BenchRay::bounce, points, count, infinity, seed);
}

// A uniform direction on the unit sphere.
inline glm::vec3 uniform_sphere(float u1, float u2) {
  float z = 1.f - 2.f * u1, phi = 2.f * glm::pi<float>() * u2;
  float r = std::sqrt(std::max(0.f, 1.f - z * z));
  return {r * std::cos(phi), r * std::sin(phi), z};
}

// `count` rays with uniform origins in the box and uniform directions: no coherence at all. A
// side of the box thinner than 1 % of its longest is widened to that, centred: in a flat scene's
// box every origin would lie on the plane of its triangles, where a hit at t = 0 is decided by
// the rounding of each backend's t (half of them one way, half the other) and says nothing.
inline RayBatch random_rays(const Box& bounds, size_t count, uint64_t seed) {
  RayBatch b;
  b.type = RayType::bounce;
  b.resize(count);
  glm::vec3 lo = bounds.empty() ? glm::vec3(0.f) : bounds.lo;
  glm::vec3 hi = bounds.empty() ? glm::vec3(0.f) : bounds.hi;
  const float min_side = 0.01f * std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
  for (int k = 0; k < 3; ++k)
    if (hi[k] - lo[k] < min_side) {
      const float centre = 0.5f * (lo[k] + hi[k]);
      lo[k] = centre - 0.5f * min_side, hi[k] = centre + 0.5f * min_side;
    }
  const glm::vec3 ext = hi - lo;
  for_each_index(count, [&](size_t i) {
    auto u = [&](int dim) { return random01(seed, BenchRay::random, i, dim); };
    glm::vec3 o = glm::min(lo + ext * glm::vec3(u(0), u(1), u(2)), hi);
    b.set(i, o, uniform_sphere(u(3), u(4)), 0.f, infinity, uint32_t(i));
  });
  return b;
}

}  // namespace dacrt::bench
