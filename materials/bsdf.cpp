// A shading point's BSDF: the glTF BRDF, mixed with a volume's layered refractive interface (see
// bsdf.h).
#include "dacrt/materials/bsdf.h"

#include <algorithm>
#include <cmath>

namespace dacrt {

Bsdf Bsdf::volume(const BrdfParams& p, float eta, bool front) {
  const float metallic = std::clamp(p.metallic, 0.f, 1.f);
  const float q = (1.f - metallic) * std::clamp(p.transmission, 0.f, 1.f);
  BrdfParams opaque = p;
  opaque.transmission = 0.f;
  opaque.metallic = q < 1.f ? std::min(1.f, metallic / (1.f - q)) : 0.f;
  return Bsdf(GltfBrdf(opaque), RoughDielectric(eta, p, front), q,
              front ? MaterialLayers(p, GltfBrdf::min_alpha) : MaterialLayers());
}

glm::vec3 Bsdf::interface_eval(const glm::vec3& wo, const glm::vec3& wi) const {
  const glm::vec3 f = dielectric_->eval(wo, wi);
  return layers_.any() ? layers_.eval(f, wo, wi) : f;
}

float Bsdf::interface_pdf(const glm::vec3& wo, const glm::vec3& wi) const {
  const float p = dielectric_->pdf(wo, wi);
  // (The interface scatters all it does not absorb: its albedo is about 1.)
  return layers_.any() ? layers_.pdf(layers_.pick(wo, 1.f), p, wo, wi) : p;
}

std::optional<GltfBrdf::Sample> Bsdf::interface_sample(const glm::vec3& wo, float u_lobe, float u1,
                                                       float u2) const {
  if (!layers_.any()) return dielectric_->sample(wo, u_lobe, u1, u2);
  const MaterialLayers::Pick pick = layers_.pick(wo, 1.f);
  const MaterialLayers::Lobe lobe = layers_.choose(pick, u_lobe);
  if (lobe != MaterialLayers::Lobe::base) {
    const std::optional<glm::vec3> wi = layers_.sample(lobe, wo, u1, u2);
    if (!wi) return std::nullopt;
    return GltfBrdf::Sample{*wi, {}, 0.f};  // (weighed by the caller)
  }
  auto s = dielectric_->sample(wo, u_lobe, u1, u2);
  // A delta (index-matched pass-through): the layers' weight on it over the base's probability.
  if (s && dielectric_->index_matched()) s->weight = layers_.eval(s->weight, wo, s->wi) / pick.base;
  return s;
}

glm::vec3 Bsdf::eval(const glm::vec3& wo, const glm::vec3& wi) const {
  if (!dielectric_) return brdf_.eval(wo, wi);
  glm::vec3 f = q_ * interface_eval(wo, wi);
  if (q_ < 1.f) f += (1.f - q_) * brdf_.eval(wo, wi);
  return f;
}

float Bsdf::pdf(const glm::vec3& wo, const glm::vec3& wi) const {
  if (!dielectric_) return brdf_.pdf(wo, wi);
  float p = q_ * interface_pdf(wo, wi);
  if (q_ < 1.f) p += (1.f - q_) * brdf_.pdf(wo, wi);
  return p;
}

std::optional<GltfBrdf::Sample> Bsdf::sample(const glm::vec3& wo, float u_lobe, float u1,
                                             float u2) const {
  if (!dielectric_) return brdf_.sample(wo, u_lobe, u1, u2);
  if (!(q_ > 0.f)) return brdf_.sample(wo, u_lobe, u1, u2);
  // The lobe number, rescaled, also chooses inside the lobe picked.
  const bool dielectric = u_lobe < q_;
  float u = dielectric ? u_lobe / q_ : (u_lobe - q_) / (1.f - q_);
  u = std::min(u, 0x1.fffffep-1f);
  auto s = dielectric ? interface_sample(wo, u, u1, u2) : brdf_.sample(wo, u, u1, u2);
  if (!s) return s;
  // A delta (index-matched pass-through): weight q · w / q, and the BRDF cannot sample it.
  if (dielectric && dielectric_->index_matched() && s->wi == -wo) return s;
  // (Without layers and metal, the dielectric's own sample is the mixture's.)
  if (q_ >= 1.f && !layers_.any()) return s;
  const float density = pdf(wo, s->wi);
  if (!(density > 0.f) || !std::isfinite(density)) return std::nullopt;
  return GltfBrdf::Sample{s->wi, eval(wo, s->wi) * (std::abs(s->wi.z) / density), density};
}

}  // namespace dacrt
