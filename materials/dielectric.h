// RoughDielectric: the refractive interface of a KHR_materials_volume material, a rough
// dielectric BSDF (Walter, Marschner, Li, Torrance, "Microfacet Models for Refraction through
// Rough Surfaces", EGSR 2007) with the GGX distribution of materials/gltf_brdf.h:
//   reflection  f_r = F(wo·h) D(h) G₂ / (4 |cos θo| |cos θi|),           h = normalize(wo + wi)
//   refraction  f_t = tint (1 − F(wo·h)) D(h) G₂ |wo·h| |wi·h|
//                     / (|cos θo| |cos θi| (wo·h + η wi·h)²),             h = −normalize(wo + η wi)
// F is the exact unpolarised Fresnel reflectance of the interface (1 under total internal
// reflection), η = η_below / η_above the relative IOR of the side wi refracts into over the side
// wo is on. f_t is the BSDF of radiance (pbrt-v4's TransportMode::Radiance): it carries the 1/η²
// by which radiance changes across the interface, so f(wo, wi) / η_wo² = f(wi, wo) / η_wi².
// Sampling draws a visible normal for wo (Heitz 2018), then reflects with probability F(wo·h) and
// refracts otherwise; pdf() is that density, so eval, pdf and sample agree (tests/dielectric_test.cpp
// checks them by χ²). An index-matched interface (η = 1 to within 1e-4) is a pass-through:
// wi = −wo with weight tint, a delta (eval 0, pdf ∞), whatever the roughness.
//
// The glTF material's other lobes act on the interface as they do on the opaque BRDF:
// - KHR_materials_specular: the reflectance is the exact F mapped onto the glTF base's Schlick
//   endpoints, R = specular · (F0' + (1 − F0') · (F − F0) / (1 − F0)) per channel, with F0 the
//   interface's ((η − 1)/(η + 1))² and F0' = min(F0 · specularColor, 1): specular 1 and colour 1
//   are F exactly, specular 0 reflects nothing and refracts everything. Refraction takes
//   1 − max(R). Under total internal reflection R is 1 whatever the factors (light cannot leave).
// - KHR_materials_iridescence (front faces: the film is on the outside): R = mix(R, R_film,
//   iridescence), R_film the thin film's over a base of F0' · specular (materials/iridescence.h).
// - KHR_materials_anisotropy: D and G are the stretched GGX of materials/anisotropy.h, for
//   reflection and refraction alike.
// Sampling reflects with probability lum(R) / (lum(R) + 1 − max R), which is F without them.
//
// Directions are in the local frame (z = normal) with wo above (z > 0); wi is above for
// reflection and below for refraction.
#pragma once

#include <glm/glm.hpp>
#include <optional>

#include "dacrt/materials/anisotropy.h"
#include "dacrt/materials/gltf_brdf.h"

namespace dacrt {

// The unpolarised Fresnel reflectance of an interface of relative IOR eta (transmitted side over
// incident side) for light arriving at cosine cos_i (≥ 0) to the normal; 1 under total internal
// reflection.
float fresnel_dielectric(float cos_i, float eta);

// KHR_materials_dispersion: the IOR at wavelength λ (nm) of a material of IOR n_d (at 587.6 nm)
// and dispersion 20 / V_d (Abbe number V_d), by the extension's two-term Cauchy formula:
//   n(λ) = max(n_d + (n_d − 1) / V_d · (523655 / λ² − 1.5168), 1).
float dispersive_ior(float ior, float dispersion, float wavelength_nm);
// The wavelengths that stand for dacrt's R, G and B channels when a path follows one of them
// through a dispersive material (an approximation: dacrt is RGB, not spectral).
inline constexpr float channel_wavelength[3] = {630.f, 532.f, 465.f};

class RoughDielectric {
 public:
  // eta: η_below / η_above; alpha: GGX α (kept at GltfBrdf::min_alpha or above); tint: what
  // refraction is multiplied by (glTF's baseColor), clamped to [0, 1].
  RoughDielectric(float eta, float alpha, const glm::vec3& tint);
  // The interface of a glTF material p (its roughness, baseColor as the tint, specular, and
  // anisotropy in the shading frame; its iridescence where `front`, arriving from outside).
  RoughDielectric(float eta, const BrdfParams& p, bool front);

  glm::vec3 eval(const glm::vec3& wo, const glm::vec3& wi) const;  // without the cosine
  float pdf(const glm::vec3& wo, const glm::vec3& wi) const;
  // u_lobe chooses reflection (below F) or refraction; u1, u2 the visible normal.
  std::optional<GltfBrdf::Sample> sample(const glm::vec3& wo, float u_lobe, float u1,
                                         float u2) const;

  float eta() const { return eta_; }
  bool index_matched() const { return matched_; }

 private:
  // The microfacet normal (h.z > 0) of the pair, or nullopt where the BSDF is zero.
  std::optional<glm::vec3> half_vector(const glm::vec3& wo, const glm::vec3& wi) const;
  // What the interface reflects (per channel) and refracts at cos θ = wo·h, and the probability
  // of sampling the reflection.
  struct Split {
    glm::vec3 reflect;
    float refract, p_reflect;
  };
  Split split(float cos_oh) const;
  // The microfacet distribution D(h), the visibility G₂ / (4 cos_o |cos_i|), G₁(wo), and a
  // visible normal: isotropic or stretched.
  float d(const glm::vec3& h) const;
  float visibility(const glm::vec3& wo, const glm::vec3& wi) const;
  float g1(const glm::vec3& wo) const;
  glm::vec3 sample_normal(const glm::vec3& wo, float u1, float u2) const;

  float eta_, alpha_;
  glm::vec3 tint_;
  bool matched_;
  // KHR_materials_specular and _iridescence (plain_: neither, R = F).
  bool plain_ = true;
  float f0_ = 0.f, specular_ = 1.f;
  glm::vec3 f0_glTF_{0.f};  // F0' = min(F0 · specularColor, 1)
  float iridescence_ = 0.f, film_ior_ = 1.3f, film_thickness_ = 0.f;
  bool anisotropic_ = false;
  Anisotropy anisotropy_;
};

}  // namespace dacrt
