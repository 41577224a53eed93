// Benchmark rays: the five ray types `dacrt bench` times, generated once per batch so that every
// backend traces exactly the same rays. Part of the dacrt_bench library, which the CLI and the
// tests both link, so that the tests can use them directly.
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

#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>
#include <limits>
#include <optional>
#include <string_view>
#include <vector>

#include "dacrt/scene/camera.h"
#include "dacrt/scene/scene.h"
#include "dacrt/tracer/ray_batch.h"
#include "dacrt/util/alias_table.h"

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

std::optional<BenchRay> bench_ray_from(std::string_view name);

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

// Resolution for about `count` pixels in the given aspect ratio (width / height; <= 0 = square).
// Neither side is over 32 768 (the limit of --width and --height), whatever the aspect.
glm::ivec2 resolution_for_count(size_t count, float aspect);

// One ray per pixel, through the pixel centre; ray i is pixel (i mod width, i / width).
RayBatch primary_rays(const Camera& camera, int width, int height);

// The surface points of the rays that hit, in ray order; misses (and degenerate triangles,
// which have no normal) are dropped.
SurfacePoints surface_points(const Geometry& g, const RayBatch& rays, const HitBatch& hits);

// Where shadow rays aim when the scene has no emitters: above the centre of the box by twice its
// largest side, so that every point of the scene sees it from about the same direction.
glm::vec3 point_above(const Box& bounds);

// Where shadow rays end: the scene's emitters, as a renderer's next-event estimation would aim
// at them, but chosen simply (the benchmark times the backends, not a light sampler): an emissive
// triangle in proportion to its area, then a point uniform on it, or one of the punctual lights,
// each as likely as the others; half and half when the scene has both.
class ShadowTargets {
 public:
  explicit ShadowTargets(const Scene& scene);
  bool empty() const { return triangles_.empty() && lights_ == 0; }

  struct Target {
    int light;              // index into Scene::lights, or -1 for a triangle
    uint32_t triangle;      // when light is -1
    glm::vec2 barycentric;  // of the point on the triangle
  };
  // u picks the emitter, (u1, u2) the point on a triangle. Not for an empty set.
  Target pick(float u, float u1, float u2) const;

 private:
  std::vector<uint32_t> triangles_;
  AliasTable table_;  // over triangles_, by area
  size_t lights_;
};

// `count` shadow rays; ray i starts at surface point i mod |points|. The origin is offset along
// the normal facing the target and the segment ends at the sampled emitter point, itself offset
// along the emitter's normal towards the origin, so neither end can report its own triangle.
RayBatch shadow_rays(const Scene& scene, const ShadowTargets& targets, const SurfacePoints& points,
                     size_t count, uint64_t seed);

RayBatch ao_rays(const Scene& scene, const SurfacePoints& points, size_t count, uint64_t seed);

RayBatch bounce_rays(const SurfacePoints& points, size_t count, uint64_t seed);

// `count` rays with uniform origins in the box and uniform directions: no coherence at all. A
// side of the box thinner than 1 % of its longest is widened to that, centred: in a flat scene's
// box every origin would lie on the plane of its triangles, where a hit at t = 0 is decided by
// the rounding of each backend's t (half of them one way, half the other) and says nothing.
RayBatch random_rays(const Box& bounds, size_t count, uint64_t seed);

}  // namespace dacrt::bench
