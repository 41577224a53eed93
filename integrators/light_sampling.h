// Next-event estimation and multiple importance sampling, in one place for every integrator that
// samples lights: the choice between the environment map and the scene's emitters, the shadow ray
// towards an emissive triangle, a punctual light or the map, and the MIS weights (power heuristic)
// of emission that BSDF sampling finds instead.
//
// An emissive triangle is sampled by solid angle when it is large and near, by area otherwise: from
// the shading point it subtends a solid angle Ω, and for min_solid_angle < Ω < max_solid_angle the
// direction is uniform over its spherical triangle (integrators/spherical_triangle.h), pdf pmf / Ω;
// else the point is uniform on its area, pdf pmf · d² / (cos · A). Emission that BSDF sampling
// finds is weighed with the pdf of the same rule, evaluated at the bounce ray's origin (the shading
// point offset by a rounding error's width).
#pragma once

#include <array>
#include <cstdint>
#include <glm/glm.hpp>
#include <optional>
#include <span>
#include <vector>

#include "dacrt/integrators/dimensions.h"
#include "dacrt/integrators/lights.h"
#include "dacrt/materials/bsdf.h"
#include "dacrt/materials/sampling.h"
#include "dacrt/scene/environment.h"
#include "dacrt/scene/scene.h"

namespace dacrt {

// A shading point as next-event estimation and BSDF sampling see it.
struct ShadingPoint {
  glm::vec3 ng;  // geometric normal, on the side the ray arrived from
  Frame frame;   // around the shading normal, on the same side
  Bsdf brdf;
  glm::vec3 wo;            // towards the viewer, local
  glm::vec3 above, below;  // ray origins offset to either side (below only if it transmits)
  bool transmits;
  // Where a ray leaving along wi (wi_local in the frame) starts, or null if the BSDF sends no
  // light that way: the shading and geometric normals must agree on the side, and only a
  // transmissive material reaches the other one.
  const glm::vec3* origin_towards(const glm::vec3& wi, const glm::vec3& wi_local) const {
    if (wi_local.z > 0.f && glm::dot(wi, ng) > 0.f) return &above;
    if (transmits && wi_local.z < 0.f && glm::dot(wi, ng) < 0.f) return &below;
    return nullptr;
  }
};

// A contribution (or a throughput) worth a ray: positive somewhere.
inline bool carries_light(const glm::vec3& c) {
  return c.x > 0.f || c.y > 0.f || c.z > 0.f;
}

// A shadow ray that adds `contribution` (times the path's throughput) if nothing occludes it.
struct ShadowRay {
  glm::vec3 origin, direction;
  float tmax;
  glm::vec3 contribution;
};

// How next-event estimation samples an emissive triangle.
enum class TriangleSampling : uint8_t {
  area,                  // a point uniform on its area, always
  solid_angle_if_large,  // (the default) uniform in its solid angle when that is large, see above
};

class LightSampling {
 public:
  // Below this solid angle area sampling's d² / cos varies little over the triangle, and solid
  // angle does not pay for its cost (atan2, sin/cos, double): on the Lambert Cornell box (256²,
  // 64 spp) pbrt-v4's bound 3e-4 sr took 4.85 s to noise 0.00814, 0.5 sr 4.16 s to 0.00825, 12 %
  // less time for equal noise. Above the upper bound the shading point is nearly on the
  // triangle's plane (2π sr), where the sampling degenerates.
  static constexpr double min_solid_angle = 0.5, max_solid_angle = 6.22;

  // lights: the render's punctual lights (Shot::lights), which must outlive this. map: null for a
  // uniform (or black) environment, which only BSDF sampling reaches.
  LightSampling(const Scene& scene, std::span<const PunctualLight> lights, const EnvironmentMap* map,
                TriangleSampling triangles = TriangleSampling::solid_angle_if_large,
                LightPicking picking = LightPicking::automatic);

  // Nothing to sample: no shadow rays at all.
  bool empty() const { return lights_.empty() && !map_; }
  // False when every emissive triangle is sampled by area (TriangleSampling::area).
  bool solid_angle() const { return triangles_ != TriangleSampling::area; }
  // True when the choice of emitter depends on the shading point (the light tree): the callers
  // keep each path's last LightContext for the MIS weight of emission its bounce ray finds.
  bool by_point() const { return lights_.tree(); }
  const LightSampler& sampler() const { return lights_; }
  // Where next-event estimation at shading point x (surface point p) chooses from: p, and the
  // normal on the side light arrives from unless the surface transmits (both sides then).
  static LightContext context(const glm::vec3& p, const ShadingPoint& x) {
    return {p, x.transmits ? glm::vec3(0.f) : x.ng};
  }

  // What the Lambert lanes (integrators/lambert_lanes.h) take of the emitter `pick` chooses from
  // `at`, when it is an emissive triangle they can sample: opaque, untextured, uncoated, of an
  // area within float's range, and the scene has no environment map to sample. Null otherwise (a
  // punctual light, say): emitter() then samples it. pmf: the probability of the choice.
  struct AreaEmitter {
    glm::vec3 corner[3], normal, centre, radiance;
    float radius2, area;
    bool double_sided;
  };
  const AreaEmitter* area_emitter(float pick, const LightContext& at, float& pmf) const {
    const LightSampler::Choice c = lights_.pick(pick, at);
    pmf = c.pmf;
    const std::optional<AreaEmitter>& e = area_emitters_[c.entry];
    return e ? &*e : nullptr;
  }

  // The solid angle of triangle `tri` from point o if next-event estimation samples it by solid
  // angle from there, else 0 (it samples the area).
  double sampled_solid_angle(const glm::vec3& o, uint32_t tri) const;
  // Next-event estimation's solid-angle density towards triangle `tri` from point o, the
  // triangle being met at distance t, at cosine `cos_light` to its normal; `area` its area;
  // `from`: the context of the choice made at o's shading point (by_point(); else unused).
  // (t² / area in double: at a glTF node scale of 1e30 or 1e-30 both over- or underflow float.)
  float emitter_pdf(const glm::vec3& o, uint32_t tri, float t, float cos_light, double area,
                    const LightContext& from = {}) const {
    return emitter_density((1.f - map_share_) * lights_.pmf(tri, from),
                           sampled_solid_angle(o, tri), double(t) * t, cos_light, area);
  }
  // MIS weight of emission found by BSDF sampling (solid-angle pdf bsdf_pdf) along a ray from o.
  float emitter_weight(float bsdf_pdf, uint32_t tri, const glm::vec3& o, float t, float cos_light,
                       double area, const LightContext& from = {}) const {
    return power_heuristic(bsdf_pdf, emitter_pdf(o, tri, t, cos_light, area, from));
  }
  // ... and of the environment map, along direction d.
  float environment_weight(float bsdf_pdf, const glm::vec3& d) const {
    return power_heuristic(bsdf_pdf, map_share_ * map_->pdf(d));
  }

  // One next-event sample at point p (on the surface, before offsetting) of shading point x;
  // `random(dimension)` gives the path's numbers, `random_pair(first)` those of first and first + 1
  // together (the same numbers). False when the sample carries no light.
  template <class Random, class RandomPair>
  bool sample(const glm::vec3& p, const ShadingPoint& x, Random&& random, RandomPair&& random_pair,
              ShadowRay& out) const {
    // Separate numbers for the source and the emitter: rescaling one would lose the low bits
    // the alias table needs for its probabilities to be exact.
    if (map_share_ > 0.f && (map_share_ >= 1.f || random(light_source) < map_share_)) {
      const auto [u1, u2] = random_pair(environment_u);
      const auto [u3, u4] = random_pair(environment_pixel_u);
      return environment(x, {u1, u2, u3, u4}, out);
    }
    const auto [u1, u2] = random_pair(light_u);
    return emitter(p, x, random(light_pick), u1, u2, out);
  }
  template <class Random>
  bool sample(const glm::vec3& p, const ShadingPoint& x, Random&& random, ShadowRay& out) const {
    auto pair = [&](Dimension first) {
      return std::array<float, 2>{random(first), random(Dimension(first + 1))};
    };
    return sample(p, x, random, pair, out);
  }

 private:
  // The solid-angle density of an emitter picked with probability pmf: pmf / Ω where it is sampled
  // by solid angle (omega > 0), else pmf · d² / (cos · A), for the point at squared distance dist2.
  // Next-event estimation and the MIS weight of BSDF sampling both use it, so they agree.
  static float emitter_density(float pmf, double omega, double dist2, float cos_light,
                               double area) {
    return float(omega > 0.0 ? double(pmf) / omega : pmf * (dist2 / (cos_light * area)));
  }
  bool environment(const ShadingPoint& x, const glm::vec4& u, ShadowRay& out) const;
  bool emitter(const glm::vec3& p, const ShadingPoint& x, float pick, float u1, float u2,
               ShadowRay& out) const;
  bool punctual(const glm::vec3& p, const PunctualLight& light, float pmf, const ShadingPoint& x,
                ShadowRay& out) const;

  const Scene& scene_;
  const std::span<const PunctualLight> punctual_;
  const LightSampler lights_;
  const EnvironmentMap* map_;
  const float map_share_;  // probability that next-event estimation samples the map
  const TriangleSampling triangles_;
  std::vector<std::optional<AreaEmitter>> area_emitters_;  // by LightSampler entry
};

}  // namespace dacrt
