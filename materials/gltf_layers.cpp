// The layers over a base (see layers.h), and the glTF BRDF's eval, pdf and sample through them
// (gltf_brdf.h). A material with neither layer goes straight to the base.
#include <algorithm>
#include <cmath>

#include "dacrt/materials/gltf_brdf.h"
#include "dacrt/materials/layers.h"
#include "dacrt/materials/sampling.h"
#include "dacrt/materials/sheen.h"

namespace dacrt {

MaterialLayers::MaterialLayers(const BrdfParams& p, float min_alpha) {
  const float coat_roughness = std::clamp(p.clearcoat_roughness, 0.f, 1.f);
  // (The default normal, (0, 0, 1) on every uncoated hit, is its own normalisation: the same
  // vector without a square root and a division per hit.)
  const glm::vec3& n = p.clearcoat_normal;
  coat_ = {std::clamp(p.clearcoat, 0.f, 1.f), std::max(min_alpha, coat_roughness * coat_roughness),
           n.z > 0.f ? (n.x == 0.f && n.y == 0.f && n.z == 1.f ? n : glm::normalize(n))
                     : glm::vec3(0, 0, 1)};
  if (!(coat_.weight > 0.f)) coat_.weight = 0.f;  // (NaN too)
  sheen_color_ = glm::clamp(p.sheen_color, 0.f, 1.f);
  sheen_max_ = std::max({sheen_color_.x, sheen_color_.y, sheen_color_.z});
  if (!(sheen_max_ > 0.f)) sheen_max_ = 0.f;
  sheen_roughness_ = std::clamp(p.sheen_roughness, 0.f, 1.f);
  sheen_alpha_ = sheen_alpha(sheen_roughness_);
}

float MaterialLayers::sheen_e(const glm::vec3& wo, const glm::vec3& wi) const {
  return std::max(sheen_albedo(wo.z, sheen_roughness_),
                  sheen_albedo(std::abs(wi.z), sheen_roughness_));
}

glm::vec3 MaterialLayers::eval(const glm::vec3& f_base, const glm::vec3& wo,
                               const glm::vec3& wi) const {
  glm::vec3 f = f_base;
  if (sheen_max_ > 0.f) {
    const float e = sheen_e(wo, wi);
    f *= std::max(0.f, 1.f - sheen_max_ * e);
    if (wi.z > 0.f)
      f += sheen_color_ * (sheen_d(glm::normalize(wo + wi).z, sheen_alpha_) *
                           sheen_visibility(wo.z, wi.z, sheen_alpha_) / std::max(e, 1.f));
  }
  if (coat_.weight > 0.f) {
    f *= coat_base_weight(coat_, wo);
    if (wi.z > 0.f) f += glm::vec3(coat_eval(coat_, wo, wi));
  }
  return f;
}

MaterialLayers::Pick MaterialLayers::pick(const glm::vec3& wo, float base_albedo) const {
  // Each layer's albedo at wo, roughly: the coat's Fresnel at its normal, the sheen's table, and
  // what the base's estimate makes of it, each under the layers above it.
  const float co = glm::dot(wo, coat_.normal);
  const float coat = co > 0.f ? coat_.weight * coat_fresnel(co) : 0.f;
  const float below_coat = 1.f - coat_.weight * coat_fresnel(co);
  const float sheen =
      sheen_max_ > 0.f ? sheen_max_ * std::min(1.f, sheen_albedo(wo.z, sheen_roughness_)) : 0.f;
  const float base = below_coat * (1.f - sheen) * base_albedo;
  const float total = coat + below_coat * sheen + base;
  if (!(total > 0.f)) return {0.f, 0.f, 1.f};
  return {coat / total, below_coat * sheen / total, base / total};
}

float MaterialLayers::pdf(const Pick& p, float base_pdf, const glm::vec3& wo,
                          const glm::vec3& wi) const {
  float density = p.base > 0.f ? p.base * base_pdf : 0.f;
  if (wi.z > 0.f) {
    if (p.sheen > 0.f) density += p.sheen * cosine_hemisphere_pdf(wi.z);
    if (p.coat > 0.f) density += p.coat * coat_pdf(coat_, wo, wi);
  }
  return density;
}

MaterialLayers::Lobe MaterialLayers::choose(const Pick& p, float& u_lobe) const {
  // (What rounding leaves past the last lobe goes to a lobe that is there.)
  if (u_lobe < p.coat) return Lobe::coat;
  if (u_lobe < p.coat + p.sheen) return Lobe::sheen;
  if (!(p.base > 0.f)) return p.sheen > 0.f ? Lobe::sheen : Lobe::coat;
  u_lobe = std::clamp((u_lobe - p.coat - p.sheen) / p.base, 0.f, 0x1.fffffep-1f);
  return Lobe::base;
}

std::optional<glm::vec3> MaterialLayers::sample(Lobe lobe, const glm::vec3& wo, float u1,
                                                float u2) const {
  if (lobe == Lobe::coat) return coat_sample(coat_, wo, u1, u2);
  return sample_cosine_hemisphere(u1, u2);
}

glm::vec3 GltfBrdf::eval(const glm::vec3& wo, const glm::vec3& wi) const {
  if (!layered_) return base_eval(wo, wi);
  if (wo.z <= 0.f || wi.z == 0.f) return glm::vec3(0.f);
  return layers_.eval(base_eval(wo, wi), wo, wi);
}

float GltfBrdf::pdf(const glm::vec3& wo, const glm::vec3& wi) const {
  if (!layered_) return base_pdf(wo, wi);
  if (wo.z <= 0.f || wi.z == 0.f) return 0.f;
  return layers_.pdf(layers_.pick(wo, lobes(wo).albedo), base_pdf(wo, wi), wo, wi);
}

std::optional<GltfBrdf::Sample> GltfBrdf::sample(const glm::vec3& wo, float u_lobe, float u1,
                                                 float u2) const {
  if (!layered_) return base_sample(wo, u_lobe, u1, u2);
  if (wo.z <= 0.f) return std::nullopt;
  const MaterialLayers::Pick p = layers_.pick(wo, lobes(wo).albedo);
  const MaterialLayers::Lobe lobe = layers_.choose(p, u_lobe);
  glm::vec3 wi;
  if (lobe == MaterialLayers::Lobe::base) {
    const std::optional<Sample> s = base_sample(wo, u_lobe, u1, u2);
    if (!s) return std::nullopt;
    wi = s->wi;
  } else {
    const std::optional<glm::vec3> d = layers_.sample(lobe, wo, u1, u2);
    if (!d) return std::nullopt;
    wi = *d;
  }
  if (wi.z == 0.f) return std::nullopt;
  const float density = layers_.pdf(p, base_pdf(wo, wi), wo, wi);
  if (!(density > 0.f) || !std::isfinite(density)) return std::nullopt;
  return Sample{wi, layers_.eval(base_eval(wo, wi), wo, wi) * (std::abs(wi.z) / density), density};
}

}  // namespace dacrt
