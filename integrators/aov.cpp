// albedo, normal, depth: what the camera rays see first, as the image's colour (the same values
// `--aov` writes as layers beside any integrator's image; these integrators trace no other ray).
//   albedo  the material's base colour × base-colour texture × vertex colour (linear RGB);
//   normal  the shading normal (normal-mapped, on the side facing the camera), world space, its
//           X, Y, Z in R, G, B, from −1 to 1;
//   depth   the distance along the camera's view axis, in scene units, in R, G and B.
// Each is averaged over the pixel's samples; rays that meet nothing give 0.
#include <tbb/parallel_for.h>

#include "dacrt/integrators/wavefront.h"

namespace dacrt {
namespace {

enum class Value { albedo, normal, depth };

class FirstHitValue final : public Wavefront {
 public:
  FirstHitValue(const Scene& scene, const Shot& shot, Backend& backend,
                const RenderSettings& settings, Value value)
      : Wavefront(scene, shot, backend, settings), value_(value) {}

 private:
  void shade(const RayBatch& rays, const HitBatch& hits) override {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, rays.size(), 1024), [&](auto range) {
      for (size_t i = range.begin(); i != range.end(); ++i) {
        const uint32_t path = rays.path[i];
        ended_[path] = 1;
        if (!hits.hit(i)) continue;
        const FirstHit f = first_hit_at(rays, hits, uint32_t(i));
        paths_.radiance[path] = value_ == Value::albedo   ? f.albedo
                                : value_ == Value::normal ? f.normal
                                                          : glm::vec3(f.depth);
      }
    });
  }

  const Value value_;
};

template <Value value>
std::unique_ptr<Integrator> make(const Scene& scene, const Shot& shot, Backend& backend,
                                 const RenderSettings& s) {
  return std::make_unique<FirstHitValue>(scene, shot, backend, s, value);
}

const Integrator::Registration albedo{"albedo", make<Value::albedo>};
const Integrator::Registration normal{"normal", make<Value::normal>};
const Integrator::Registration depth{"depth", make<Value::depth>};

}  // namespace
}  // namespace dacrt
