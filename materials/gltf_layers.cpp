// The layers over the glTF BRDF's base: KHR_materials_clearcoat's coat (materials/clearcoat.h)
// over KHR_materials_sheen's sheen (materials/sheen.h) over the metallic-roughness base
// (gltf_brdf.cpp), as GltfBrdf's eval, pdf and sample (see gltf_brdf.h). A material with neither
// layer goes straight to the base.
#include <algorithm>
#include <cmath>

#include "dacrt/materials/gltf_brdf.h"
#include "dacrt/materials/sampling.h"
#include "dacrt/materials/sheen.h"

namespace dacrt {

glm::vec3 GltfBrdf::eval(const glm::vec3& wo, const glm::vec3& wi) const {
  if (!layered_) return base_eval(wo, wi);
  if (wo.z <= 0.f || wi.z == 0.f) return glm::vec3(0.f);
  glm::vec3 f = base_eval(wo, wi);
  if (sheen_max_ > 0.f) {
    // (Where the lobe's albedo E exceeds 1, near grazing and smooth, the lobe is divided by it:
    // sheen.h.)
    const float e = std::max(sheen_albedo(wo.z, sheen_roughness_),
                             sheen_albedo(std::abs(wi.z), sheen_roughness_));
    f *= 1.f - sheen_max_ * std::min(e, 1.f);
    if (wi.z > 0.f)
      f += sheen_color_ * (sheen_d(glm::normalize(wo + wi).z, sheen_alpha_) *
                           sheen_visibility(wo.z, wi.z) / std::max(e, 1.f));
  }
  if (coat_.weight > 0.f) {
    f *= coat_base_weight(coat_, wo, wi);
    if (wi.z > 0.f) f += glm::vec3(coat_eval(coat_, wo, wi));
  }
  return f;
}

GltfBrdf::Layers GltfBrdf::layers(const glm::vec3& wo) const {
  // Each layer's albedo at wo, roughly: the coat's Fresnel at its normal, the sheen's table, and
  // what the base's Fresnel weights make of it, each under the layers above it.
  const float co = glm::dot(wo, coat_.normal);
  const float coat = co > 0.f ? coat_.weight * coat_fresnel(co) : 0.f;
  const float below_coat = 1.f - coat_.weight * coat_fresnel(co);
  const float sheen =
      sheen_max_ > 0.f ? sheen_max_ * std::min(1.f, sheen_albedo(wo.z, sheen_roughness_)) : 0.f;
  const float base = below_coat * (1.f - sheen) * lobes(wo).albedo;
  const float total = coat + below_coat * sheen + base;
  if (!(total > 0.f)) return {0.f, 0.f, 1.f};
  return {coat / total, below_coat * sheen / total, base / total};
}

float GltfBrdf::pdf(const glm::vec3& wo, const glm::vec3& wi) const {
  if (!layered_) return base_pdf(wo, wi);
  if (wo.z <= 0.f || wi.z == 0.f) return 0.f;
  const Layers p = layers(wo);
  float density = p.base > 0.f ? p.base * base_pdf(wo, wi) : 0.f;
  if (wi.z > 0.f) {
    if (p.sheen > 0.f) density += p.sheen * cosine_hemisphere_pdf(wi.z);
    if (p.coat > 0.f) density += p.coat * coat_pdf(coat_, wo, wi);
  }
  return density;
}

std::optional<GltfBrdf::Sample> GltfBrdf::sample(const glm::vec3& wo, float u_lobe, float u1,
                                                 float u2) const {
  if (!layered_) return base_sample(wo, u_lobe, u1, u2);
  if (wo.z <= 0.f) return std::nullopt;
  const Layers p = layers(wo);
  // The lobe u_lobe falls in (what rounding leaves past the last one goes to a lobe that is
  // there).
  enum { coat, sheen, base } lobe;
  if (u_lobe < p.coat)
    lobe = coat;
  else if (u_lobe < p.coat + p.sheen)
    lobe = sheen;
  else
    lobe = p.base > 0.f ? base : p.sheen > 0.f ? sheen : coat;
  glm::vec3 wi;
  if (lobe == coat) {
    const std::optional<glm::vec3> d = coat_sample(coat_, wo, u1, u2);
    if (!d) return std::nullopt;
    wi = *d;
  } else if (lobe == sheen) {
    wi = sample_cosine_hemisphere(u1, u2);
  } else {
    const float u = std::min((u_lobe - p.coat - p.sheen) / p.base, 0x1.fffffep-1f);
    const std::optional<Sample> s = base_sample(wo, std::max(u, 0.f), u1, u2);
    if (!s) return std::nullopt;
    wi = s->wi;
  }
  if (wi.z == 0.f) return std::nullopt;
  const float density = pdf(wo, wi);
  if (!(density > 0.f) || !std::isfinite(density)) return std::nullopt;
  return Sample{wi, eval(wo, wi) * (std::abs(wi.z) / density), density};
}

}  // namespace dacrt
