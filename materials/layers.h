// MaterialLayers: KHR_materials_clearcoat's coat (materials/clearcoat.h) over KHR_materials_sheen's
// sheen (materials/sheen.h) over a base, as the extensions layer them:
//   f = coat + (1 − clearcoat · F_c(wo·n_c)) · (sheen + s(wo, wi) · f_base),
//   s(wo, wi) = 1 − max(sheenColor) · max(E(cos θo), E(|cos θi|))
// The base is the glTF BRDF's (materials/gltf_brdf.h) or a volume's refractive interface
// (materials/bsdf.h): both layer through this, so a coat or a sheen costs and weighs the same on
// opaque, thin-walled and volume materials. The layers' own lobes reflect only (0 for wi below the
// surface); a transmitted wi is weighted by s at its mirror image, |cos θi|.
// Where the sheen lobe's albedo E exceeds 1 (sheenRoughness below about 0.25, within a few degrees
// of grazing: sheen.h) the specification's sum would reflect more than arrives; there, and only
// there, the sheen lobe is divided by E and the base weighted 0, so the layer stays energy
// conserving (tests/brdf_layers_test.cpp measures the formula against the specification's).
// Sampling picks the coat, the sheen or the base by their estimated albedos at wo (pick()), and
// pdf() is the mixture's.
#pragma once

#include <algorithm>
#include <glm/glm.hpp>
#include <optional>

#include "dacrt/materials/clearcoat.h"

namespace dacrt {

struct BrdfParams;

class MaterialLayers {
 public:
  MaterialLayers() = default;
  // The coat and the sheen of p (neither when its factors are 0); `min_alpha` is the least GGX α.
  MaterialLayers(const BrdfParams& p, float min_alpha);

  bool any() const { return coat_.weight > 0.f || sheen_max_ > 0.f; }

  // f from the base's value f_base at (wo, wi); wo above the surface.
  glm::vec3 eval(const glm::vec3& f_base, const glm::vec3& wo, const glm::vec3& wi) const;

  // The probabilities of sampling the coat, the sheen and the base from wo (summing to 1), from
  // their albedos there (the base's, base_albedo, as the base estimates it).
  struct Pick {
    float coat, sheen, base;
  };
  Pick pick(const glm::vec3& wo, float base_albedo) const;
  // The mixture's density from the base's density at (wo, wi).
  float pdf(const Pick& p, float base_pdf, const glm::vec3& wo, const glm::vec3& wi) const;

  enum class Lobe { coat, sheen, base };
  // The lobe u_lobe falls in, and u_lobe rescaled to [0, 1) within it (for the base's own pick).
  Lobe choose(const Pick& p, float& u_lobe) const;
  // A direction from the coat's or the sheen's lobe.
  std::optional<glm::vec3> sample(Lobe lobe, const glm::vec3& wo, float u1, float u2) const;

  // What the coat leaves the base's emission seen from wo: 1 − clearcoat · F(wo·n_c).
  float emission_weight(const glm::vec3& wo) const {
    return coat_.weight > 0.f ? coat_base_weight(coat_, wo) : 1.f;
  }

 private:
  // The sheen's albedo for the pair, max(E(cos θo), E(|cos θi|)).
  float sheen_e(const glm::vec3& wo, const glm::vec3& wi) const;

  Coat coat_;
  glm::vec3 sheen_color_{0.f};
  float sheen_max_ = 0.f, sheen_roughness_ = 0.f, sheen_alpha_ = 1.f;
};

}  // namespace dacrt
