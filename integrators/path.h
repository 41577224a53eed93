// The path tracer's shading stages, shared by `path` and `direct` (integrators/path.cpp,
// integrators/direct.cpp): the same estimator, `direct` with one scattering event.
#pragma once

#include "integrators/wavefront.h"

namespace dacrt {

class PathTracer final : public Wavefront {
 public:
  PathTracer(const Scene& scene, Backend& backend, const RenderSettings& settings);

 private:
  void shade(const RayBatch& rays, const HitBatch& hits) override;
  void escaped(const RayBatch& rays, uint32_t i);
  void emitted(const RayBatch& rays, const HitBatch& hits, uint32_t i);
  bool survives(uint32_t path, const VertexDraw& random);
  void material(const RayBatch& rays, const HitBatch& hits, uint32_t i, size_t q,
                const VertexDraw& random);

  const EnvironmentMap* map_;  // null: uniform (or black) environment, reached by BSDF sampling
  const LightSampling lights_;
  bool emitters_ = false;  // any emissive material: the emitted stage runs
  std::vector<Dimension> dims_;  // what a vertex draws (shade draws them for 16 rays at a time)
  uint32_t drawn_;               // their mask
};

}  // namespace dacrt
