// A shading point's BSDF: the glTF BRDF, mixed with a volume's refractive interface (see bsdf.h).
#include "dacrt/materials/bsdf.h"

#include <algorithm>
#include <cmath>

namespace dacrt {

Bsdf Bsdf::volume(const BrdfParams& p, float eta) {
  const float metallic = std::clamp(p.metallic, 0.f, 1.f);
  const float q = (1.f - metallic) * std::clamp(p.transmission, 0.f, 1.f);
  BrdfParams opaque = p;
  opaque.transmission = 0.f;
  opaque.metallic = q < 1.f ? std::min(1.f, metallic / (1.f - q)) : 0.f;
  const float roughness = std::clamp(p.roughness, 0.f, 1.f);
  return Bsdf(GltfBrdf(opaque), RoughDielectric(eta, roughness * roughness, p.base_color), q);
}

glm::vec3 Bsdf::eval(const glm::vec3& wo, const glm::vec3& wi) const {
  if (!dielectric_) return brdf_.eval(wo, wi);
  glm::vec3 f = q_ * dielectric_->eval(wo, wi);
  if (q_ < 1.f) f += (1.f - q_) * brdf_.eval(wo, wi);
  return f;
}

float Bsdf::pdf(const glm::vec3& wo, const glm::vec3& wi) const {
  if (!dielectric_) return brdf_.pdf(wo, wi);
  float p = q_ * dielectric_->pdf(wo, wi);
  if (q_ < 1.f) p += (1.f - q_) * brdf_.pdf(wo, wi);
  return p;
}

std::optional<GltfBrdf::Sample> Bsdf::sample(const glm::vec3& wo, float u_lobe, float u1,
                                             float u2) const {
  if (!dielectric_) return brdf_.sample(wo, u_lobe, u1, u2);
  if (q_ >= 1.f) return dielectric_->sample(wo, u_lobe, u1, u2);
  if (!(q_ > 0.f)) return brdf_.sample(wo, u_lobe, u1, u2);
  // The lobe number, rescaled, also chooses inside the lobe picked.
  const bool dielectric = u_lobe < q_;
  const float u = dielectric ? u_lobe / q_ : (u_lobe - q_) / (1.f - q_);
  auto s = dielectric ? dielectric_->sample(wo, std::min(u, 0x1.fffffep-1f), u1, u2)
                      : brdf_.sample(wo, std::min(u, 0x1.fffffep-1f), u1, u2);
  if (!s) return s;
  // A delta (index-matched pass-through): weight q · tint / q, and the BRDF cannot sample it.
  if (dielectric && dielectric_->index_matched()) return s;
  const float density = pdf(wo, s->wi);
  if (!(density > 0.f) || !std::isfinite(density)) return std::nullopt;
  return GltfBrdf::Sample{s->wi, eval(wo, s->wi) * (std::abs(s->wi.z) / density), density};
}

}  // namespace dacrt
