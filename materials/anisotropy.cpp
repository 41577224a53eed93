// The anisotropic GGX lobe of KHR_materials_anisotropy (see anisotropy.h).
#include "dacrt/materials/anisotropy.h"

#include <cmath>
#include <glm/gtc/constants.hpp>

#include "dacrt/materials/ggx.h"

namespace dacrt {

float ggx_d_anisotropic(const glm::vec3& h, float alpha_t, float alpha_b) {
  if (h.z <= 0.f) return 0.f;
  const float x = h.x / alpha_t, y = h.y / alpha_b, t = x * x + y * y + h.z * h.z;
  return 1.f / (glm::pi<float>() * alpha_t * alpha_b * t * t);
}

// |(α_t w_t, α_b w_b, w_n)|: √(1 + α² tan²θ) cos θ with α the distribution's along w's azimuth.
static float stretched_length(const glm::vec3& w, float alpha_t, float alpha_b) {
  return glm::length(glm::vec3(alpha_t * w.x, alpha_b * w.y, w.z));
}

float ggx_lambda_anisotropic(const glm::vec3& w, float alpha_t, float alpha_b) {
  return 0.5f * (stretched_length(w, alpha_t, alpha_b) / w.z - 1.f);
}

float ggx_visibility_anisotropic(const glm::vec3& wo, const glm::vec3& wi, float alpha_t,
                                 float alpha_b) {
  return 0.5f / (wi.z * stretched_length(wo, alpha_t, alpha_b) +
                 wo.z * stretched_length(wi, alpha_t, alpha_b));
}

float anisotropic_dv(const Anisotropy& a, const glm::vec3& wo, const glm::vec3& wi,
                     const glm::vec3& h) {
  return ggx_d_anisotropic(a.to_local(h), a.alpha_t, a.alpha_b) *
         ggx_visibility_anisotropic(a.to_local(wo), a.to_local(wi), a.alpha_t, a.alpha_b);
}

float anisotropic_reflection_pdf(const Anisotropy& a, const glm::vec3& wo, const glm::vec3& h) {
  const glm::vec3 o = a.to_local(wo);
  const float g1 = 1.f / (1.f + ggx_lambda_anisotropic(o, a.alpha_t, a.alpha_b));
  return g1 * ggx_d_anisotropic(a.to_local(h), a.alpha_t, a.alpha_b) / (4.f * wo.z);
}

glm::vec3 sample_anisotropic_visible_normal(const Anisotropy& a, const glm::vec3& wo, float u1,
                                            float u2) {
  return a.to_shading(sample_ggx_visible_normal(a.to_local(wo), a.alpha_t, a.alpha_b, u1, u2));
}

}  // namespace dacrt
