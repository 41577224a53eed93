// The glTF metallic-roughness BRDF (see gltf_brdf.h).
#include "dacrt/materials/gltf_brdf.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/constants.hpp>

#include "dacrt/materials/iridescence.h"
#include "dacrt/materials/sampling.h"

namespace dacrt {

float ggx_d(float cos_h, float alpha) {
  if (cos_h <= 0.f) return 0.f;
  const float a2 = alpha * alpha, t = cos_h * cos_h * (a2 - 1.f) + 1.f;
  return a2 / (glm::pi<float>() * t * t);
}

// Λ(θ) = (√(1 + α² tan²θ) − 1) / 2, written without the tangent so that it stays finite near
// grazing angles: √(α² + (1 − α²) cos²θ) / cos θ = √(1 + α² tan²θ).
float ggx_lambda(float cos_theta, float alpha) {
  const float a2 = alpha * alpha, c2 = cos_theta * cos_theta;
  return 0.5f * (std::sqrt(a2 + (1.f - a2) * c2) / cos_theta - 1.f);
}

// G₂ = 1 / (1 + Λ(o) + Λ(i)), and G₂ / (4 cos_o cos_i) simplifies to this.
float ggx_visibility(float cos_o, float cos_i, float alpha) {
  const float a2 = alpha * alpha;
  const float so = std::sqrt(a2 + (1.f - a2) * cos_o * cos_o);
  const float si = std::sqrt(a2 + (1.f - a2) * cos_i * cos_i);
  return 0.5f / (cos_i * so + cos_o * si);
}

glm::vec3 sample_ggx_visible_normal(const glm::vec3& wo, float alpha_x, float alpha_y, float u1,
                                    float u2) {
  // The view direction in the frame where the distribution is the unit hemisphere.
  const glm::vec3 v = glm::normalize(glm::vec3(alpha_x * wo.x, alpha_y * wo.y, wo.z));
  const float len2 = v.x * v.x + v.y * v.y;
  const glm::vec3 t1 =
      len2 > 0.f ? glm::vec3(-v.y, v.x, 0.f) / std::sqrt(len2) : glm::vec3(1.f, 0.f, 0.f);
  const glm::vec3 t2 = glm::cross(v, t1);
  // A uniform point on the disk, squeezed onto the part of it the visible hemisphere projects to.
  const float r = std::sqrt(u1), phi = glm::two_pi<float>() * u2;
  const float p1 = r * std::cos(phi);
  const float s = 0.5f * (1.f + v.z);
  const float p2 = (1.f - s) * std::sqrt(std::max(0.f, 1.f - p1 * p1)) + s * r * std::sin(phi);
  const glm::vec3 n = p1 * t1 + p2 * t2 + std::sqrt(std::max(0.f, 1.f - p1 * p1 - p2 * p2)) * v;
  // Back to the ellipsoid's frame.
  return glm::normalize(glm::vec3(alpha_x * n.x, alpha_y * n.y, std::max(0.f, n.z)));
}

GltfBrdf::GltfBrdf(const BrdfParams& p)
    : base_(glm::clamp(p.base_color, 0.f, 1.f)),
      metallic_(std::clamp(p.metallic, 0.f, 1.f)),
      alpha_(std::max(min_alpha,
                      std::clamp(p.roughness, 0.f, 1.f) * std::clamp(p.roughness, 0.f, 1.f))),
      transmission_(std::clamp(p.transmission, 0.f, 1.f)),
      layers_(p, min_alpha) {  // (made in place: a copy of it cost a store-forwarding stall)
  // KHR_materials_ior's F0 = ((ior − 1) / (ior + 1))², times specularColor (at most 1) and
  // specular; F90 = specular (KHR_materials_specular).
  const float ior = std::min(p.ior, 1e6f);  // "infinite" IORs (spec-gloss conversions): F0 → 1
  const float r = (ior - 1.f) / (ior + 1.f);
  const float specular = std::clamp(p.specular, 0.f, 1.f);
  f0_ = glm::min(r * r * glm::max(p.specular_color, 0.f), glm::vec3(1.f)) * specular;
  f90_ = specular;
  // KHR_materials_iridescence (NaN counts as 0; a film of thickness 0 is no film).
  iridescence_ = p.iridescence_thickness > 0.f ? std::clamp(p.iridescence, 0.f, 1.f) : 0.f;
  if (!(iridescence_ > 0.f)) iridescence_ = 0.f;
  film_ior_ = p.iridescence_ior;
  film_thickness_ = p.iridescence_thickness;
  lambertian_ = metallic_ == 0.f && transmission_ == 0.f && f90_ == 0.f && f0_ == glm::vec3(0.f) &&
                iridescence_ == 0.f;
  layered_ = layers_.any();  // the layers (materials/layers.h)
  // KHR_materials_anisotropy: α_t = mix(α, 1, strength²) along the direction, α_b = α across
  // (an isotropic material stops at the first test).
  anisotropic_ = false;
  if (p.anisotropy > 0.f && !lambertian_)
    anisotropic_ = stretched_lobe(alpha_, p.anisotropy, p.anisotropy_direction, anisotropy_);
}

float GltfBrdf::microfacet(const glm::vec3& wo, const glm::vec3& wi, const glm::vec3& h) const {
  if (anisotropic_) return anisotropic_dv(anisotropy_, wo, wi, h);
  return ggx_d(h.z, alpha_) * ggx_visibility(wo.z, wi.z, alpha_);
}

glm::vec3 GltfBrdf::sample_microfacet_normal(const glm::vec3& wo, float u1, float u2) const {
  if (anisotropic_) return sample_anisotropic_visible_normal(anisotropy_, wo, u1, u2);
  return sample_ggx_visible_normal(wo, alpha_, u1, u2);
}

// wi mirrored through the surface plane.
static glm::vec3 mirrored(const glm::vec3& wi) {
  return {wi.x, wi.y, -wi.z};
}

glm::vec3 GltfBrdf::base_eval(const glm::vec3& wo, const glm::vec3& wi) const {
  if (wo.z <= 0.f) return glm::vec3(0.f);
  if (lambertian_) return wi.z > 0.f ? base_ * glm::one_over_pi<float>() : glm::vec3(0.f);
  if (wi.z < 0.f) {  // through the surface: the dielectric base's transmitted part
    if (!(transmission_ > 0.f)) return glm::vec3(0.f);
    const glm::vec3 m = mirrored(wi), h = glm::normalize(wo + m);
    const float btdf = microfacet(wo, m, h);
    return (1.f - metallic_) * transmission_ * fresnel(glm::dot(wo, h)).base * btdf * base_;
  }
  if (wi.z == 0.f) return glm::vec3(0.f);
  const glm::vec3 h = glm::normalize(wo + wi);
  const float specular = microfacet(wo, wi, h);
  const Fresnel f = fresnel(glm::dot(wo, h));
  const glm::vec3 dielectric =
      (1.f - transmission_) * f.base * base_ * glm::one_over_pi<float>() + f.dielectric * specular;
  return (1.f - metallic_) * dielectric + metallic_ * f.metal * specular;
}

GltfBrdf::Fresnel GltfBrdf::fresnel(float cos_theta) const {
  const float m = 1.f - std::clamp(cos_theta, 0.f, 1.f), m2 = m * m, w = m2 * m2 * m;
  glm::vec3 fd = f0_ + (f90_ - f0_) * w, fm = base_ + (1.f - base_) * w;
  if (iridescence_ > 0.f) add_film(cos_theta, fd, fm);
  return {fd, fm, 1.f - std::max({fd.x, fd.y, fd.z})};
}

void GltfBrdf::add_film(float cos_theta, glm::vec3& dielectric, glm::vec3& metal) const {
  // (Each only where its lobe is there; outside the film is air: the spec ignores a clearcoat.)
  if (metallic_ < 1.f)
    dielectric = glm::mix(dielectric,
                          thin_film_fresnel(cos_theta, 1.f, film_ior_, film_thickness_, f0_),
                          iridescence_);
  if (metallic_ > 0.f)
    metal = glm::mix(metal, thin_film_fresnel(cos_theta, 1.f, film_ior_, film_thickness_, base_),
                     iridescence_);
}

GltfBrdf::Lobes GltfBrdf::lobes(const glm::vec3& wo) const {
  // The lobes' Fresnel weights as if the microfacet normal were the macro normal.
  const Fresnel f = fresnel(wo.z);
  const float specular =
      (1.f - metallic_) * luminance(f.dielectric) + metallic_ * luminance(f.metal);
  const float base = (1.f - metallic_) * f.base * luminance(base_);
  const float diffuse = (1.f - transmission_) * base, transmission = transmission_ * base;
  const float total = specular + diffuse + transmission;
  if (!(total > 0.f)) return {0.5f, 0.5f, 0.f, 0.f};  // black: any will do
  return {specular / total, diffuse / total, transmission / total, total};
}

float GltfBrdf::specular_pdf(const glm::vec3& wo, const glm::vec3& wi) const {
  const glm::vec3 h = glm::normalize(wo + wi);
  if (glm::dot(wo, h) <= 0.f) return 0.f;
  // Visible normals: D_wo(h) = G₁(wo) max(0, wo·h) D(h) / cos θo, and the reflection's Jacobian
  // 1 / (4 wo·h).
  if (anisotropic_) return anisotropic_reflection_pdf(anisotropy_, wo, h);
  const float g1 = 1.f / (1.f + ggx_lambda(wo.z, alpha_));
  return g1 * ggx_d(h.z, alpha_) / (4.f * wo.z);
}

float GltfBrdf::base_pdf(const glm::vec3& wo, const glm::vec3& wi) const {
  if (wo.z <= 0.f || wi.z == 0.f) return 0.f;
  if (lambertian_) return wi.z > 0.f ? cosine_hemisphere_pdf(wi.z) : 0.f;
  const Lobes p = lobes(wo);
  if (wi.z < 0.f)
    return p.transmission > 0.f ? p.transmission * specular_pdf(wo, mirrored(wi)) : 0.f;
  return p.specular * specular_pdf(wo, wi) + p.diffuse * cosine_hemisphere_pdf(wi.z);
}

std::optional<GltfBrdf::Sample> GltfBrdf::base_sample(const glm::vec3& wo, float u_lobe, float u1,
                                                      float u2) const {
  if (wo.z <= 0.f) return std::nullopt;
  if (lambertian_) {
    const glm::vec3 wi = sample_cosine_hemisphere(u1, u2);
    if (!(wi.z > 0.f)) return std::nullopt;
    return Sample{wi, base_, cosine_hemisphere_pdf(wi.z)};  // eval · cos / pdf = baseColor
  }
  glm::vec3 wi;
  const Lobes p = lobes(wo);
  // (Without transmission, everything past the specular lobe is diffuse, whatever the rounding of
  // specular + diffuse.)
  if (u_lobe >= p.specular && (u_lobe < p.specular + p.diffuse || !(p.transmission > 0.f))) {
    wi = sample_cosine_hemisphere(u1, u2);
  } else {
    const glm::vec3 h = sample_microfacet_normal(wo, u1, u2);
    wi = 2.f * glm::dot(wo, h) * h - wo;
    if (wi.z <= 0.f) return std::nullopt;
    if (u_lobe >= p.specular) wi = mirrored(wi);  // transmission
  }
  if (wi.z == 0.f) return std::nullopt;
  const float density = base_pdf(wo, wi);
  if (!(density > 0.f) || !std::isfinite(density)) return std::nullopt;
  return Sample{wi, base_eval(wo, wi) * (std::abs(wi.z) / density), density};
}

}  // namespace dacrt
