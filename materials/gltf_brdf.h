// The glTF 2.0 metallic-roughness BRDF (specification, Appendix B), with KHR_materials_specular
// and KHR_materials_ior:
//   f = (1 − metallic) · [(1 − max F_d) · baseColor / π + F_d · D · V] + metallic · F_m · D · V
// D is the Trowbridge-Reitz (GGX) distribution with α = roughness², V the height-correlated Smith
// visibility G₂ / (4 |n·l| |n·v|), F_d the dielectric Fresnel (Schlick, F0 from the IOR times
// specularColor and specular, F90 = specular) and F_m the metal's (F0 = baseColor, F90 = 1).
// Sampling picks the specular lobe (visible normals, Heitz 2018) or the diffuse one (cosine) with
// a probability from the Fresnel weights at the viewing angle; pdf() is the mixture's pdf, so
// sample, eval and pdf agree exactly (tests/brdf_test.cpp checks them by χ²).
//
// KHR_materials_transmission (thin-walled, as without KHR_materials_volume) replaces the diffuse
// base by mix(diffuse, specular_btdf · baseColor, transmission): the BTDF is the specular lobe
// mirrored through the surface (half vector H_T = normalize(V + L − 2 (N·L) N)), so light passes
// without bending on average and spreads with the roughness; it is sampled as the reflection,
// mirrored.
//
// KHR_materials_anisotropy stretches D and V of the specular lobe (reflection and transmission)
// along a direction of the tangent plane (materials/anisotropy.h); an isotropic material takes
// none of it (one branch per lobe evaluation).
//
// KHR_materials_iridescence (materials/iridescence.h) puts a thin film on the base: the Fresnel
// terms of both specular lobes become mix(F, F_film, iridescence), with F_film the film's over a
// base of the lobe's F0 (the dielectric's F0, or baseColor) at the same cos θ (wo·h); 1 − max F_d,
// and the lobes' sampling weights, follow. A film of thickness 0 is no film.
//
// Layers over that base (each skipped, at no cost, where the material lacks it; a material with
// neither is exactly the BRDF above): KHR_materials_clearcoat's coat over KHR_materials_sheen's
// sheen, as materials/layers.h writes them,
//   f = coat + (1 − clearcoat · F_c(wo·n_c)) · (sheen + s(wo, wi) · f_base).
// Sampling picks the coat, the sheen or the base by their estimated albedos at wo, and pdf() is
// again the mixture's.
//
// Directions are in the local shading frame (z = normal) and point away from the surface: wo
// towards the viewer (above the surface), wi towards the light: above for reflection, below for
// transmission (zero unless the material transmits).
#pragma once

#include <glm/glm.hpp>
#include <optional>

#include "dacrt/materials/anisotropy.h"
#include "dacrt/materials/clearcoat.h"
#include "dacrt/materials/layers.h"

namespace dacrt {

struct BrdfParams {
  glm::vec3 base_color{1.f};
  float metallic = 1.f;           // glTF's default
  float roughness = 1.f;          // perceptual; α = roughness²
  float ior = 1.5f;               // KHR_materials_ior
  float specular = 1.f;           // KHR_materials_specular: specularFactor
  glm::vec3 specular_color{1.f};  // KHR_materials_specular: specularColorFactor
  float transmission = 0.f;       // KHR_materials_transmission: transmissionFactor
  float clearcoat = 0.f;            // KHR_materials_clearcoat: clearcoatFactor
  float clearcoat_roughness = 0.f;  // KHR_materials_clearcoat: clearcoatRoughnessFactor
  // The coat's normal in the local shading frame (z = the shading normal): the clearcoat normal
  // map's, or the interpolated normal where the base is normal-mapped.
  glm::vec3 clearcoat_normal{0.f, 0.f, 1.f};
  glm::vec3 sheen_color{0.f};  // KHR_materials_sheen: sheenColorFactor
  float sheen_roughness = 0.f;  // KHR_materials_sheen: sheenRoughnessFactor
  // KHR_materials_anisotropy: anisotropyStrength (× texture .b), and the direction of increased
  // roughness in the local shading frame's tangent plane (x, y; normalised here, (1, 0) where it
  // is zero or not finite).
  float anisotropy = 0.f;
  glm::vec2 anisotropy_direction{1.f, 0.f};
  float iridescence = 0.f;            // KHR_materials_iridescence: iridescenceFactor
  float iridescence_ior = 1.3f;       // KHR_materials_iridescence: iridescenceIor
  float iridescence_thickness = 400.f;  // the film's thickness in nm (0: no film)
};

class GltfBrdf {
 public:
  // α is kept at or above this: below it the lobe is narrower than float directions resolve (a
  // mirror, to within 0.1 %, that still has a finite pdf for multiple importance sampling).
  static constexpr float min_alpha = 1e-3f;

  explicit GltfBrdf(const BrdfParams& p);

  // f(wo, wi), without the cosine.
  glm::vec3 eval(const glm::vec3& wo, const glm::vec3& wi) const;
  // The solid-angle density with which sample() returns wi.
  float pdf(const glm::vec3& wo, const glm::vec3& wi) const;

  struct Sample {
    glm::vec3 wi;
    glm::vec3 weight;  // eval · cos θi / pdf
    float pdf;
  };
  // From three uniforms in [0, 1): the first picks the lobe, the other two the direction.
  std::optional<Sample> sample(const glm::vec3& wo, float u_lobe, float u1, float u2) const;

  float alpha() const { return alpha_; }
  const glm::vec3& base() const { return base_; }  // baseColor, clamped to [0, 1]
  // True when the BRDF is exactly Lambert's, baseColor / π: not metallic, no transmission, and no
  // dielectric reflection (F0 = F90 = 0, KHR_materials_specular's specularFactor 0, no
  // iridescence), no coat and no sheen. eval, pdf and sample then skip the microfacet lobe, which
  // is zero there: the same values, less work.
  bool lambertian() const { return lambertian_ && !layered_; }
  // True when a coat or a sheen lies over the base.
  bool layered() const { return layered_; }
  const MaterialLayers& layers() const { return layers_; }
  // True when the specular lobe is anisotropic (strength > 0, α < 1, and not Lambert's).
  bool anisotropic() const { return anisotropic_; }
  // True when sample() is the metallic-roughness base alone, with its specular lobe: not Lambert's,
  // no coat or sheen, isotropic, no transmission, no iridescence (the BRDF lanes' case,
  // integrators/lambert_lanes.h). What they take of it: metallic, F0 and F90 (and base, alpha).
  bool plain() const {
    return !lambertian_ && !layered_ && !anisotropic_ && transmission_ == 0.f &&
           iridescence_ == 0.f;
  }
  float metallic() const { return metallic_; }
  const glm::vec3& f0() const { return f0_; }
  float f90() const { return f90_; }

 private:
  // The base (metallic-roughness with transmission), without the layers.
  glm::vec3 base_eval(const glm::vec3& wo, const glm::vec3& wi) const;
  float base_pdf(const glm::vec3& wo, const glm::vec3& wi) const;
  std::optional<Sample> base_sample(const glm::vec3& wo, float u_lobe, float u1, float u2) const;
  // Schlick's Fresnel at cos θ (between wo and the microfacet normal): the dielectric's F, the
  // metal's, and what KHR_materials_specular's fresnel_mix leaves the diffuse base, 1 − max F_d
  // (one number: a coloured specular does not tint the diffuse).
  struct Fresnel {
    glm::vec3 dielectric, metal;
    float base;
  };
  Fresnel fresnel(float cos_theta) const;
  // KHR_materials_iridescence: the thin film's Fresnel mixed into the dielectric's and the metal's.
  void add_film(float cos_theta, glm::vec3& dielectric, glm::vec3& metal) const;
  // Probabilities of sampling the specular reflection, the diffuse and the transmission lobes
  // when looking from wo (they sum to 1).
  struct Lobes {
    float specular, diffuse, transmission;
    float albedo;  // their sum before normalising: roughly the base's albedo at wo
  };
  Lobes lobes(const glm::vec3& wo) const;
  float specular_pdf(const glm::vec3& wo, const glm::vec3& wi) const;
  // The specular lobe's D(h) · V(wo, wi), and a visible normal for wo: isotropic or anisotropic.
  float microfacet(const glm::vec3& wo, const glm::vec3& wi, const glm::vec3& h) const;
  glm::vec3 sample_microfacet_normal(const glm::vec3& wo, float u1, float u2) const;

  glm::vec3 base_;
  float metallic_, alpha_, transmission_;
  glm::vec3 f0_;  // dielectric F0
  float f90_;     // dielectric F90
  float iridescence_, film_ior_, film_thickness_;  // the thin film (iridescence_ 0: none)
  bool lambertian_;  // the base is Lambert's
  bool layered_;     // a coat or a sheen
  MaterialLayers layers_;
  bool anisotropic_;
  Anisotropy anisotropy_;  // (used only when anisotropic_)
};

}  // namespace dacrt
