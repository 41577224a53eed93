#include "bench/rays.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <glm/gtc/constants.hpp>

#include "dacrt/materials/sampling.h"
#include "dacrt/tracer/ray.h"
#include "dacrt/util/random.h"

namespace dacrt::bench {

namespace {

// A uniform in [0, 1) for dimension `dim` of ray `i` of ray type `r`.
float random01(uint64_t seed, BenchRay r, size_t i, int dim) {
  return uniform_float(seed, uint64_t(r), uint64_t(i), uint64_t(dim));
}

// Splits [0, n) over the TBB workers; `body(i)` fills element i.
template <typename Body>
void for_each_index(size_t n, const Body& body) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const auto& range) {
    for (size_t i = range.begin(); i != range.end(); ++i) body(i);
  });
}

}  // namespace

std::optional<BenchRay> bench_ray_from(std::string_view name) {
  for (BenchRay r : all_bench_rays)
    if (to_string(r) == name) return r;
  return std::nullopt;
}

glm::ivec2 resolution_for_count(size_t count, float aspect) {
  double a = aspect > 0.f ? double(aspect) : 1.0;
  auto side = [](double s) { return int(std::clamp(std::lround(s), 1l, long(1) << 15)); };
  return {side(std::sqrt(double(count) * a)), side(std::sqrt(double(count) / a))};
}

RayBatch primary_rays(const Camera& camera, int width, int height) {
  RayBatch b;
  b.type = RayType::primary;
  b.resize(size_t(width) * size_t(height));
  const CameraProjection projection(camera, width, height);
  for_each_index(b.size(), [&](size_t i) {
    glm::vec3 o, d;
    projection.ray(float(i % size_t(width)) + 0.5f, float(i / size_t(width)) + 0.5f, o, d);
    b.set(i, o, d, 0.f, infinity, uint32_t(i));
  });
  return b;
}

SurfacePoints surface_points(const Geometry& g, const RayBatch& rays, const HitBatch& hits) {
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

glm::vec3 point_above(const Box& bounds) {
  glm::vec3 e = bounds.extent();
  return bounds.center() + glm::vec3(0.f, 2.f * std::max({e.x, e.y, e.z}), 0.f);
}

ShadowTargets::ShadowTargets(const Scene& scene) : lights_(scene.lights.size()) {
  std::vector<double> area;
  for (uint32_t tri = 0; tri < scene.geometry.size(); ++tri) {
    const double a = scene.geometry.area(tri);
    if (!scene.materials[scene.geometry.material[tri]].emitter() || !(a > 0.0)) continue;
    triangles_.push_back(tri);
    area.push_back(a);
  }
  if (!area.empty()) table_ = AliasTable(area);
}

ShadowTargets::Target ShadowTargets::pick(float u, float u1, float u2) const {
  const float share = triangles_.empty() ? 0.f : lights_ == 0 ? 1.f : 0.5f;
  if (u >= share) {
    const float v = (u - share) / (1.f - share);
    return {int(std::min(size_t(v * float(lights_)), lights_ - 1)), 0, glm::vec2(0.f)};
  }
  const size_t entry = table_.sample(u / share);
  const float r = std::sqrt(u1);  // uniform on the triangle
  return {-1, triangles_[entry], glm::vec2(r * (1.f - u2), r * u2)};
}

RayBatch shadow_rays(const Scene& scene, const ShadowTargets& targets, const SurfacePoints& points,
                     size_t count, uint64_t seed) {
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
                 s.barycentric.x * g.vertex(s.triangle, 1) +
                 s.barycentric.y * g.vertex(s.triangle, 2);
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

namespace {

// `count` cosine-weighted rays around the surface normals (ray i from point i mod |points|),
// with the given tmax: ambient occlusion (10 % of the diagonal) or diffuse bounces (inf).
RayBatch hemisphere_rays(BenchRay kind, const SurfacePoints& points, size_t count, float tmax,
                         uint64_t seed) {
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
float ao_distance(const Box& bounds) {
  return 0.1f * glm::length(bounds.extent());
}

}  // namespace

RayBatch ao_rays(const Scene& scene, const SurfacePoints& points, size_t count, uint64_t seed) {
  return hemisphere_rays(BenchRay::ao, points, count, ao_distance(scene.bounds()), seed);
}

RayBatch bounce_rays(const SurfacePoints& points, size_t count, uint64_t seed) {
  return hemisphere_rays(BenchRay::bounce, points, count, infinity, seed);
}

namespace {

// A uniform direction on the unit sphere.
glm::vec3 uniform_sphere(float u1, float u2) {
  float z = 1.f - 2.f * u1, phi = 2.f * glm::pi<float>() * u2;
  float r = std::sqrt(std::max(0.f, 1.f - z * z));
  return {r * std::cos(phi), r * std::sin(phi), z};
}

}  // namespace

RayBatch random_rays(const Box& bounds, size_t count, uint64_t seed) {
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
