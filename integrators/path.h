// The path tracer's shading stages, shared by `path` and `direct` (integrators/path.cpp,
// integrators/direct.cpp): the same estimator, `direct` with one scattering event.
#pragma once

#include "dacrt/integrators/lambert_lanes.h"
#include "dacrt/integrators/media.h"
#include "dacrt/integrators/wavefront.h"

namespace dacrt {

class PathTracer final : public Wavefront {
 public:
  PathTracer(const Scene& scene, const Shot& shot, Backend& backend, const RenderSettings& settings);

 private:
  void shade(const RayBatch& rays, const HitBatch& hits) override;
  void escaped(const RayBatch& rays, uint32_t i);
  void emitted(const RayBatch& rays, const HitBatch& hits, uint32_t i);
  bool survives(uint32_t path, const VertexDraw& random);
  // A group's vertices whose BSDF sampling the BRDF lanes do (integrators/lambert_lanes.h):
  // material fills lane k and sets its bit in `deferred`; shade then samples them all and writes
  // their bounce rays (from above[k]).
  struct BrdfGroup {
    BrdfIn in;
    BrdfOut out;
    glm::vec3 above[BrdfIn::lanes];
    uint32_t deferred;
  };
  void material(const RayBatch& rays, const HitBatch& hits, uint32_t i, size_t q,
                const VertexDraw& random, BrdfGroup* group = nullptr, int k = 0);
  void sample_brdf_lanes(const RayBatch& rays, size_t first, size_t lanes, BrdfGroup& group);
  // Slot q's bounce ray (of path `path`): the ray in the scratch queue, its pdf for MIS, the
  // path going on.
  void bounce(size_t q, uint32_t path, const glm::vec3& origin, const glm::vec3& direction,
              float pdf);
  // Before the stages: a path at depth 0 starts outside every volume; one inside an absorbing
  // volume loses what the medium absorbed over the segment it just travelled (Beer–Lambert).
  void attenuate(const RayBatch& rays, const HitBatch& hits, uint32_t i);

  // Russian roulette keeps a path with probability min(1, max(β) / roulette_floor) (survives).
  static constexpr float roulette_floor = 0.5f;

  // A uniform environment sampled as a light (RenderSettings::sample_environment): a constant
  // map standing for it, made before map_ (null: not sampled).
  const std::unique_ptr<const EnvironmentMap> uniform_map_;
  const EnvironmentMap* map_;  // null: uniform (or black) environment, reached by BSDF sampling
  const LightSampling lights_;
  bool emitters_ = false;  // any emissive material: the emitted stage runs
  // Lambert lanes (integrators/lambert_lanes.h): by material, whether they shade its hits, and
  // its albedo; lambert_ says if they run at all (some material is theirs, no environment map).
  bool lambert_ = false;
  LambertScene lambert_scene_{};
  std::vector<uint8_t> lambert_material_;
  std::vector<glm::vec3> lambert_albedo_;
  // The lanes of rays [first, first + lanes) of a batch that the Lambert lanes shade (their
  // paths' state, shadow and bounce rays written), as a mask; the others are for the stages above.
  uint32_t shade_lambert_lanes(const RayBatch& rays, const HitBatch& hits, size_t first,
                               size_t lanes, const VertexNumbers* numbers, LambertIn& in,
                               LambertOut& out);
  // KHR_materials_volume (integrators/media.h): the scene's volumes, and by slot the stack of
  // those each path is in (only when there are volumes).
  const Media media_;
  std::vector<MediumStack> stacks_;
  // With the light tree (LightSampling::by_point), by slot: where the path's last vertex chose
  // its emitter from, for the MIS weight of the emission its bounce ray finds.
  std::vector<LightContext> light_from_;
  std::vector<Dimension> dims_;  // what a vertex draws (shade draws them for 16 rays at a time)
  uint32_t drawn_;               // their mask
};

}  // namespace dacrt
