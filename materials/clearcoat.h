// KHR_materials_clearcoat's coat: a GGX dielectric (IOR 1.5: Schlick's Fresnel with F0 = 0.04,
// F90 = 1) of its own roughness around its own normal (clearcoatNormalTexture's, else the
// interpolated normal), layered over the material (materials/layers.h does the layering) as the
// extension's fresnel_coat writes it: with F_c = F(wo·n_c) at the viewing direction,
//   f = clearcoat · F_c · D_c · V_c + (1 − clearcoat · F_c) · f_base
// and the base's emission, seen through the coat, is likewise multiplied by 1 − clearcoat · F_c.
// (One Fresnel for the pair, taken at wo: eval is not reciprocal, f(wo, wi) ≠ f(wi, wo), which a
// path tracer that always evaluates towards the viewer does not need; a white smooth coat over
// a white mirror still reflects everything, F_c + (1 − F_c).)
// The coat lobe is sampled by visible normals (Heitz 2018) in the coat normal's frame; directions
// below the shading surface are rejected (eval is 0 there), so the pdf stays the lobe's density.
#pragma once

#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>
#include <optional>

#include "dacrt/materials/ggx.h"
#include "dacrt/materials/sampling.h"

namespace dacrt {

struct Coat {
  float weight = 0.f;                // clearcoatFactor (× texture .r)
  float alpha = 0.f;                 // clearcoatRoughness², at least GltfBrdf::min_alpha
  glm::vec3 normal{0.f, 0.f, 1.f};  // in the shading frame, unit, z > 0
};

// Schlick's Fresnel of the coat (F0 = 0.04, F90 = 1) at cos θ (≤ 0 counts as grazing: 1).
inline float coat_fresnel(float cos_theta) {
  const float m = 1.f - std::clamp(cos_theta, 0.f, 1.f), m2 = m * m;
  return 0.04f + 0.96f * (m2 * m2 * m);
}

// What the coat leaves the layers below it, and the emission under it: 1 − clearcoat · F(wo·n_c).
inline float coat_base_weight(const Coat& c, const glm::vec3& wo) {
  return 1.f - c.weight * coat_fresnel(glm::dot(wo, c.normal));
}

// The coat lobe clearcoat · F(wo·n_c) · D · V (without the cosine), for wi above the shading
// surface.
inline float coat_eval(const Coat& c, const glm::vec3& wo, const glm::vec3& wi) {
  const float co = glm::dot(wo, c.normal), ci = glm::dot(wi, c.normal);
  if (co <= 0.f || ci <= 0.f || wi.z <= 0.f) return 0.f;
  const glm::vec3 h = glm::normalize(wo + wi);
  return c.weight * coat_fresnel(co) * ggx_d(glm::dot(h, c.normal), c.alpha) *
         ggx_visibility(co, ci, c.alpha);
}

// The density of coat_sample's directions (visible normals of the coat, reflected).
inline float coat_pdf(const Coat& c, const glm::vec3& wo, const glm::vec3& wi) {
  const float co = glm::dot(wo, c.normal);
  if (co <= 0.f || glm::dot(wi, c.normal) <= 0.f) return 0.f;
  const glm::vec3 h = glm::normalize(wo + wi);
  if (glm::dot(wo, h) <= 0.f) return 0.f;
  const float g1 = 1.f / (1.f + ggx_lambda(co, c.alpha));
  return g1 * ggx_d(glm::dot(h, c.normal), c.alpha) / (4.f * co);
}

// A direction from the coat lobe, or nothing (wo below the coat, or wi below the surface).
inline std::optional<glm::vec3> coat_sample(const Coat& c, const glm::vec3& wo, float u1,
                                            float u2) {
  if (glm::dot(wo, c.normal) <= 0.f) return std::nullopt;
  const bool tilted = c.normal != glm::vec3(0.f, 0.f, 1.f);
  const Frame frame(c.normal);
  const glm::vec3 wo_c = tilted ? frame.to_local(wo) : wo;
  const glm::vec3 h_c = sample_ggx_visible_normal(wo_c, c.alpha, u1, u2);
  const glm::vec3 h = tilted ? frame.to_world(h_c) : h_c;
  const glm::vec3 wi = 2.f * glm::dot(wo, h) * h - wo;
  if (wi.z <= 0.f || glm::dot(wi, c.normal) <= 0.f) return std::nullopt;
  return wi;
}

}  // namespace dacrt
