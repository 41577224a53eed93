// KHR_materials_anisotropy's specular lobe: the GGX (Trowbridge-Reitz) distribution stretched
// along a direction t of the tangent plane, with roughness α_t along t and α_b across it (along
// b = n × t). The extension makes α_t = mix(α, 1, strength²) and α_b = α (α = roughness²):
//   D(h)  = 1 / (π α_t α_b (h_t² / α_t² + h_b² / α_b² + h_n²)²)
//   Λ(w)  = (√(α_t² w_t² + α_b² w_b² + w_n²) / w_n − 1) / 2          (Smith, height-correlated)
//   V     = G₂ / (4 cos θo cos θi) = 1 / (2 (cos θi |(α_t o_t, α_b o_b, o_n)| + cos θo |(α_t i_t, α_b i_b, i_n)|))
// (Heitz 2014, "Understanding the Masking-Shadowing Function in Microfacet-Based BRDFs"), sampled
// by visible normals (Heitz 2018, ggx.h's sample_ggx_visible_normal with two α). With α_t = α_b
// these are ggx.h's isotropic functions. GltfBrdf (gltf_brdf.h) uses them for its base specular
// lobe (reflection and thin-walled transmission) where a material is anisotropic, and ggx.h's
// isotropic ones everywhere else; the clearcoat stays isotropic, as the extension says.
//
// Vectors are unit and in the lobe's own frame (x = t, y = b, z = n) unless a function says
// otherwise; Anisotropy::to_local takes them there from the shading frame.
#pragma once

#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>

namespace dacrt {

struct Anisotropy {
  float alpha_t = 1.f, alpha_b = 1.f;  // along t and across it
  glm::vec2 t{1.f, 0.f};  // the direction t in the shading frame's tangent plane (unit)

  // A shading-frame vector in the lobe's frame (a rotation about the normal).
  glm::vec3 to_local(const glm::vec3& v) const {
    return {t.x * v.x + t.y * v.y, -t.y * v.x + t.x * v.y, v.z};
  }
  glm::vec3 to_shading(const glm::vec3& v) const {
    return {t.x * v.x - t.y * v.y, t.y * v.x + t.x * v.y, v.z};
  }
};

// The extension's α along the direction: mix(α, 1, strength²).
inline float anisotropic_alpha(float alpha, float strength) {
  const float s2 = strength * strength;
  return alpha * (1.f - s2) + s2;
}

// The stretched lobe of isotropic α for a strength > 0 (at most 1 is used) along `direction`
// (shading frame; normalised here, (1, 0) where it is zero or not finite). True where it is
// stretched at all (α_t > α_b: not at α = 1); the lobe is then `a`.
inline bool stretched_lobe(float alpha, float strength, const glm::vec2& direction,
                           Anisotropy& a) {
  a.alpha_b = alpha;
  a.alpha_t = anisotropic_alpha(alpha, std::min(strength, 1.f));
  const float length = glm::length(direction);
  if (length > 0.f && std::isfinite(length)) a.t = direction / length;
  return a.alpha_t > a.alpha_b;
}

float ggx_d_anisotropic(const glm::vec3& h, float alpha_t, float alpha_b);
float ggx_lambda_anisotropic(const glm::vec3& w, float alpha_t, float alpha_b);  // w.z > 0
float ggx_visibility_anisotropic(const glm::vec3& wo, const glm::vec3& wi, float alpha_t,
                                 float alpha_b);  // wo.z, wi.z > 0

// In the shading frame: the lobe's D(h) · V(wo, wi), and the density of the reflection
// 2 (wo·h) h − wo of a visible normal h for wo (wo·h > 0): G₁(wo) D(h) / (4 cos θo), the visible
// normals' G₁(wo) D(h) (wo·h) / cos θo times the reflection's Jacobian 1 / (4 wo·h).
float anisotropic_dv(const Anisotropy& a, const glm::vec3& wo, const glm::vec3& wi,
                     const glm::vec3& h);
float anisotropic_reflection_pdf(const Anisotropy& a, const glm::vec3& wo, const glm::vec3& h);
// A visible normal for wo (shading frame in, shading frame out).
glm::vec3 sample_anisotropic_visible_normal(const Anisotropy& a, const glm::vec3& wo, float u1,
                                            float u2);

}  // namespace dacrt
