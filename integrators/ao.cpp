// ao: ambient occlusion. At the first surface each camera ray meets, one ray in a cosine-weighted
// direction about the shading normal asks whether anything lies within --ao-distance (default: the
// scene's bounding-box diagonal, so any occluder counts). The pixel value is the unoccluded share
// of the cosine-weighted hemisphere, in [0, 1], grey: 1 on an open plane, 0 in a closed box. Rays
// that meet nothing give 0. Materials do not matter, but alpha-masked and blended surfaces are
// seen through as in `path`. The occlusion rays are the backend's shadow rays.
#include <tbb/parallel_for.h>

#include "dacrt/integrators/wavefront.h"
#include "dacrt/materials/sampling.h"
#include "dacrt/tracer/ray.h"

namespace dacrt {
namespace {

class AmbientOcclusion final : public Wavefront {
 public:
  AmbientOcclusion(const Scene& scene, const Shot& shot, Backend& backend,
                   const RenderSettings& settings)
      : Wavefront(scene, shot, backend, settings), distance_(settings.ao_distance) {
    if (!(distance_ > 0.f)) {
      const Box b = scene.bounds();
      distance_ = b.empty() ? 1.f : std::max(glm::length(b.extent()), 1e-30f);
    }
  }

 private:
  void shade(const RayBatch& rays, const HitBatch& hits) override {
    const size_t n = rays.size();
    tbb::parallel_for(size_t(0), n, [&](size_t i) { ended_[rays.path[i]] = 1; });
    select_rays(hits, n, true);
    scratch_rays(queue_.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, queue_.size(), 1024), [&](auto range) {
      for (size_t q = range.begin(); q != range.end(); ++q) {
        const uint32_t i = queue_[q], path = rays.path[i];
        const Hit h = hit_at(rays, hits, i);
        const auto [u1, u2] = random_pair(path, bsdf_u);
        const glm::vec3 wi = Frame(h.ns).to_world(sample_cosine_hemisphere(u1, u2));
        if (!(glm::dot(wi, h.ng) > 0.f)) continue;  // below the surface: occluded by it
        ShadowRay& s = scratch_shadow_[q];
        s.origin = offset_ray_origin({h.p, h.p_error}, h.ng);
        s.direction = wi;
        s.tmax = distance_;
        s.contribution = glm::vec3(1.f);
        has_shadow_[q] = 1;
      }
    });
    push_rays(rays, &queue_);
  }

  float distance_;
};

const Integrator::Registration registration{
    "ao", [](const Scene& scene, const Shot& shot, Backend& backend, const RenderSettings& settings) {
      return std::make_unique<AmbientOcclusion>(scene, shot, backend, settings);
    }};

}  // namespace
}  // namespace dacrt
