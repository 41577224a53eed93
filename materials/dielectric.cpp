// The rough dielectric interface of KHR_materials_volume (see dielectric.h).
#include "dacrt/materials/dielectric.h"

#include <algorithm>
#include <cmath>

#include "dacrt/materials/iridescence.h"
#include "dacrt/materials/sampling.h"

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

RoughDielectric::RoughDielectric(float eta, const BrdfParams& p, bool front)
    : RoughDielectric(eta, std::clamp(p.roughness, 0.f, 1.f) * std::clamp(p.roughness, 0.f, 1.f),
                      p.base_color) {
  const float r = (eta - 1.f) / (eta + 1.f);
  f0_ = r * r;
  specular_ = std::clamp(p.specular, 0.f, 1.f);
  if (!(specular_ >= 0.f)) specular_ = 0.f;  // (NaN)
  f0_glTF_ = glm::min(f0_ * glm::max(p.specular_color, 0.f), glm::vec3(1.f));
  if (front && p.iridescence_thickness > 0.f && p.iridescence > 0.f) {
    iridescence_ = std::min(p.iridescence, 1.f);
    film_ior_ = p.iridescence_ior;
    film_thickness_ = p.iridescence_thickness;
  }
  plain_ = specular_ == 1.f && p.specular_color == glm::vec3(1.f) && iridescence_ == 0.f;
  if (p.anisotropy > 0.f)
    anisotropic_ = stretched_lobe(alpha_, p.anisotropy, p.anisotropy_direction, anisotropy_);
}

RoughDielectric::Split RoughDielectric::split(float cos_oh) const {
  const float f = fresnel_dielectric(cos_oh, eta_);
  if (plain_) return {glm::vec3(f), 1.f - f, f};
  glm::vec3 r(1.f);  // (total internal reflection)
  if (f < 1.f) {
    const float x = f0_ < 1.f ? std::clamp((f - f0_) / (1.f - f0_), 0.f, 1.f) : 1.f;
    r = specular_ * (f0_glTF_ + (1.f - f0_glTF_) * x);
    if (iridescence_ > 0.f)
      r = glm::mix(r,
                   thin_film_fresnel(cos_oh, 1.f, film_ior_, film_thickness_, specular_ * f0_glTF_),
                   iridescence_);
  }
  const float refract = 1.f - std::max({r.x, r.y, r.z}), reflect = luminance(r);
  const float total = reflect + refract;
  return {r, refract, total > 0.f ? reflect / total : 1.f};
}

float RoughDielectric::d(const glm::vec3& h) const {
  if (anisotropic_)
    return ggx_d_anisotropic(anisotropy_.to_local(h), anisotropy_.alpha_t, anisotropy_.alpha_b);
  return ggx_d(h.z, alpha_);
}

float RoughDielectric::visibility(const glm::vec3& wo, const glm::vec3& wi) const {
  const glm::vec3 up(wi.x, wi.y, std::abs(wi.z));
  if (anisotropic_)
    return ggx_visibility_anisotropic(anisotropy_.to_local(wo), anisotropy_.to_local(up),
                                      anisotropy_.alpha_t, anisotropy_.alpha_b);
  return ggx_visibility(wo.z, up.z, alpha_);
}

float RoughDielectric::g1(const glm::vec3& wo) const {
  if (anisotropic_)
    return 1.f / (1.f + ggx_lambda_anisotropic(anisotropy_.to_local(wo), anisotropy_.alpha_t,
                                               anisotropy_.alpha_b));
  return 1.f / (1.f + ggx_lambda(wo.z, alpha_));
}

glm::vec3 RoughDielectric::sample_normal(const glm::vec3& wo, float u1, float u2) const {
  if (anisotropic_) return sample_anisotropic_visible_normal(anisotropy_, wo, u1, u2);
  return sample_ggx_visible_normal(wo, alpha_, u1, u2);
}

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
  const float dh = d(*h), vis = visibility(wo, wi);
  const Split f = split(oh);
  if (wi.z > 0.f) return f.reflect * (dh * vis);
  // G₂ / (4 cos_o |cos_i|) = vis, so G₂ |wo·h| |wi·h| / (cos_o |cos_i| denom) = 4 vis …
  const float denom = oh + eta_ * ih;
  return tint_ * (f.refract * dh * 4.f * vis * oh * std::abs(ih) / (denom * denom));
}

float RoughDielectric::pdf(const glm::vec3& wo, const glm::vec3& wi) const {
  if (matched_) return 0.f;
  const std::optional<glm::vec3> h = half_vector(wo, wi);
  if (!h) return 0.f;
  const float oh = glm::dot(wo, *h), ih = glm::dot(wi, *h);
  // The visible normals' density D_wo(h) = G₁(wo) (wo·h) D(h) / cos θo.
  const float visible = g1(wo) * oh * d(*h) / wo.z;
  const float p = split(oh).p_reflect;
  if (wi.z > 0.f) return p * visible / (4.f * oh);  // the reflection's Jacobian 1 / (4 wo·h)
  // The refraction's Jacobian η² |wi·h| / (wo·h + η wi·h)².
  const float denom = oh + eta_ * ih;
  return (1.f - p) * visible * eta_ * eta_ * std::abs(ih) / (denom * denom);
}

std::optional<GltfBrdf::Sample> RoughDielectric::sample(const glm::vec3& wo, float u_lobe, float u1,
                                                        float u2) const {
  if (!(wo.z > 0.f)) return std::nullopt;
  if (matched_) return GltfBrdf::Sample{-wo, tint_, INFINITY};
  const glm::vec3 h = sample_normal(wo, u1, u2);
  const float oh = glm::dot(wo, h);
  if (!(oh > 0.f)) return std::nullopt;
  glm::vec3 wi;
  if (u_lobe < split(oh).p_reflect) {
    wi = 2.f * oh * h - wo;
    if (!(wi.z > 0.f)) return std::nullopt;
  } else {  // Snell's law about h (no total internal reflection here: the reflection takes it)
    const float sin2_t = (1.f - oh * oh) / (eta_ * eta_);
    if (sin2_t >= 1.f) return std::nullopt;
    const float cos_t = std::sqrt(1.f - sin2_t);
    wi = glm::normalize(-wo / eta_ + (oh / eta_ - cos_t) * h);
    if (!(wi.z < 0.f)) return std::nullopt;
  }
  const float density = pdf(wo, wi);
  if (!(density > 0.f) || !std::isfinite(density)) return std::nullopt;
  return GltfBrdf::Sample{wi, eval(wo, wi) * (std::abs(wi.z) / density), density};
}

}  // namespace dacrt
