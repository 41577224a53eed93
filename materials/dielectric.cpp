// The rough dielectric interface of KHR_materials_volume (see dielectric.h).
#include "dacrt/materials/dielectric.h"

#include <algorithm>
#include <cmath>

namespace dacrt {

float fresnel_dielectric(float cos_i, float eta) {
  cos_i = std::clamp(cos_i, 0.f, 1.f);
  const float sin2_t = (1.f - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= 1.f) return 1.f;  // total internal reflection
  const float cos_t = std::sqrt(1.f - sin2_t);
  const float rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  const float rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  return 0.5f * (rs * rs + rp * rp);
}

float dispersive_ior(float ior, float dispersion, float wavelength_nm) {
  if (!(dispersion > 0.f)) return ior;
  // (n_d − 1) / V_d with V_d = 20 / dispersion.
  const float spread = (ior - 1.f) * dispersion / 20.f;
  return std::max(ior + spread * (523655.f / (wavelength_nm * wavelength_nm) - 1.5168f), 1.f);
}

RoughDielectric::RoughDielectric(float eta, float alpha, const glm::vec3& tint)
    : eta_(eta),
      alpha_(std::max(alpha, GltfBrdf::min_alpha)),
      tint_(glm::clamp(tint, 0.f, 1.f)),
      matched_(std::abs(eta - 1.f) < 1e-4f) {}

std::optional<glm::vec3> RoughDielectric::half_vector(const glm::vec3& wo,
                                                      const glm::vec3& wi) const {
  if (!(wo.z > 0.f) || wi.z == 0.f) return std::nullopt;
  const bool reflect = wi.z > 0.f;
  glm::vec3 h = reflect ? wo + wi : wo + eta_ * wi;
  const float len = glm::length(h);
  if (!(len > 0.f)) return std::nullopt;
  h /= len;
  if (h.z < 0.f) h = -h;
  // Both sides of the microfacet must be the ones the directions are on.
  const float oh = glm::dot(wo, h), ih = glm::dot(wi, h);
  if (!(oh > 0.f) || (reflect ? !(ih > 0.f) : !(ih < 0.f))) return std::nullopt;
  return h;
}

glm::vec3 RoughDielectric::eval(const glm::vec3& wo, const glm::vec3& wi) const {
  if (matched_) return glm::vec3(0.f);  // a delta: only sample() finds it
  const std::optional<glm::vec3> h = half_vector(wo, wi);
  if (!h) return glm::vec3(0.f);
  const float oh = glm::dot(wo, *h), ih = glm::dot(wi, *h);
  const float d = ggx_d(h->z, alpha_), vis = ggx_visibility(wo.z, std::abs(wi.z), alpha_);
  const float f = fresnel_dielectric(oh, eta_);
  if (wi.z > 0.f) return glm::vec3(f * d * vis);
  // G₂ / (4 cos_o |cos_i|) = vis, so G₂ |wo·h| |wi·h| / (cos_o |cos_i| denom) = 4 vis …
  const float denom = oh + eta_ * ih;
  return tint_ * ((1.f - f) * d * 4.f * vis * oh * std::abs(ih) / (denom * denom));
}

float RoughDielectric::pdf(const glm::vec3& wo, const glm::vec3& wi) const {
  if (matched_) return 0.f;
  const std::optional<glm::vec3> h = half_vector(wo, wi);
  if (!h) return 0.f;
  const float oh = glm::dot(wo, *h), ih = glm::dot(wi, *h);
  // The visible normals' density D_wo(h) = G₁(wo) (wo·h) D(h) / cos θo.
  const float g1 = 1.f / (1.f + ggx_lambda(wo.z, alpha_));
  const float visible = g1 * oh * ggx_d(h->z, alpha_) / wo.z;
  const float f = fresnel_dielectric(oh, eta_);
  if (wi.z > 0.f) return f * visible / (4.f * oh);  // the reflection's Jacobian 1 / (4 wo·h)
  // The refraction's Jacobian η² |wi·h| / (wo·h + η wi·h)².
  const float denom = oh + eta_ * ih;
  return (1.f - f) * visible * eta_ * eta_ * std::abs(ih) / (denom * denom);
}

std::optional<GltfBrdf::Sample> RoughDielectric::sample(const glm::vec3& wo, float u_lobe,
                                                        float u1, float u2) const {
  if (!(wo.z > 0.f)) return std::nullopt;
  if (matched_) return GltfBrdf::Sample{-wo, tint_, INFINITY};
  const glm::vec3 h = sample_ggx_visible_normal(wo, alpha_, u1, u2);
  const float oh = glm::dot(wo, h);
  if (!(oh > 0.f)) return std::nullopt;
  glm::vec3 wi;
  if (u_lobe < fresnel_dielectric(oh, eta_)) {
    wi = 2.f * oh * h - wo;
    if (!(wi.z > 0.f)) return std::nullopt;
  } else {  // Snell's law about h (no total internal reflection here: F < 1)
    const float sin2_t = (1.f - oh * oh) / (eta_ * eta_);
    const float cos_t = std::sqrt(std::max(0.f, 1.f - sin2_t));
    wi = glm::normalize(-wo / eta_ + (oh / eta_ - cos_t) * h);
    if (!(wi.z < 0.f)) return std::nullopt;
  }
  const float density = pdf(wo, wi);
  if (!(density > 0.f) || !std::isfinite(density)) return std::nullopt;
  return GltfBrdf::Sample{wi, eval(wo, wi) * (std::abs(wi.z) / density), density};
}

}  // namespace dacrt
