#include "dacrt/scene/surface.h"

#include <cmath>
#include <optional>

#include "dacrt/materials/clearcoat.h"
#include "dacrt/materials/sampling.h"

namespace dacrt {
namespace {

glm::vec2 texcoord(const Scene& scene, uint32_t tri, uint32_t set, float u, float v) {
  if (set >= scene.texcoords.size()) return glm::vec2(0.f);
  const std::vector<glm::vec2>& uv = scene.texcoords[set];
  return uv.empty() ? glm::vec2(0.f) : interpolate(&uv[3 * size_t(tri)], u, v);
}

glm::vec4 lookup(const Scene& scene, const TextureRef& ref, uint32_t tri, float u, float v,
                 bool srgb) {
  const Texture& t = scene.textures[size_t(ref.texture)];
  return sample(scene.images[t.image], t, ref.apply(texcoord(scene, tri, ref.texcoord, u, v)),
                srgb);
}

// The tangent and bitangent at (u, v) around the unit normal n, or nothing where the triangle
// has no tangents (no uvs to make them). The bitangent is cross(n, t) · w, glTF's convention.
struct TangentFrame {
  glm::vec3 tangent, bitangent;
};
std::optional<TangentFrame> tangent_frame(const Scene& scene, uint32_t tri, float u, float v,
                                          const glm::vec3& n) {
  if (scene.tangents.empty()) return std::nullopt;
  const glm::vec4 t = interpolate(&scene.tangents[3 * size_t(tri)], u, v);
  glm::vec3 tangent = glm::vec3(t) - n * glm::dot(n, glm::vec3(t));
  const float len = glm::length(tangent);
  if (!(len > 0.f) || !std::isfinite(len)) return std::nullopt;
  tangent /= len;
  return TangentFrame{tangent, glm::cross(n, tangent) * (t.w < 0.f ? -1.f : 1.f)};
}

// The normal map's normal around n, or n where the triangle has no tangents.
glm::vec3 normal_mapped(const Scene& scene, const TextureRef& map, float scale, uint32_t tri,
                        float u, float v, const glm::vec3& n) {
  const std::optional<TangentFrame> frame = tangent_frame(scene, tri, u, v, n);
  if (!frame) return n;
  const glm::vec4 texel = lookup(scene, map, tri, u, v, false);
  const float x = (2.f * texel.x - 1.f) * scale;
  const float y = (2.f * texel.y - 1.f) * scale;
  const glm::vec3 mapped =
      frame->tangent * x + frame->bitangent * y + n * (2.f * texel.z - 1.f);
  const float mapped_len = glm::length(mapped);
  if (!(mapped_len > 0.f) || !std::isfinite(mapped_len)) return n;
  return mapped / mapped_len;
}

// KHR_materials_anisotropy at the point: the strength (× texture .b) into s.brdf, and the
// direction (the texture's .rg × 2 − 1, normalised, else the tangent; rotated by
// anisotropyRotation) in the tangent frame around the interpolated normal s.normal, or in an
// arbitrary frame around it where the triangle has no tangents.
void anisotropy_at(const Scene& scene, const Material& m, uint32_t tri, float u, float v,
                   SurfacePoint& s) {
  const glm::vec2 r = m.anisotropy_rotation;
  glm::vec2 d = r;  // (1, 0) rotated
  if (m.anisotropy_texture) {
    const glm::vec4 texel = lookup(scene, m.anisotropy_texture, tri, u, v, false);
    s.brdf.anisotropy *= texel.z;
    const glm::vec2 x = 2.f * glm::vec2(texel) - 1.f;
    const float len = glm::length(x);
    if (len > 0.f) d = glm::vec2(r.x * x.x - r.y * x.y, r.y * x.x + r.x * x.y) / len;
  }
  const std::optional<TangentFrame> frame = tangent_frame(scene, tri, u, v, s.normal);
  if (frame) {
    s.anisotropy_direction = frame->tangent * d.x + frame->bitangent * d.y;
  } else {
    const Frame arbitrary(s.normal);
    s.anisotropy_direction = arbitrary.s * d.x + arbitrary.t * d.y;
  }
}

// KHR_materials_clearcoat: the emission under a coat, seen from `towards`, is darkened by
// 1 − clearcoat · F(towards · n_c), with the coat's factor and normal there
// (materials/clearcoat.h).
float coat_emission_weight(const Scene& scene, const Material& m, uint32_t tri, float u, float v,
                           const glm::vec3& towards) {
  float c = m.clearcoat;
  if (m.clearcoat_texture) c *= lookup(scene, m.clearcoat_texture, tri, u, v, false).r;
  glm::vec3 n = scene.geometry.unit_normal(tri);
  if (!scene.normals.empty()) {
    const glm::vec3 interpolated = interpolate(&scene.normals[3 * size_t(tri)], u, v);
    const float len = glm::length(interpolated);
    if (len > 0.f) n = interpolated / len;
  }
  if (m.clearcoat_normal_texture)
    n = normal_mapped(scene, m.clearcoat_normal_texture, m.clearcoat_normal_scale, tri, u, v, n);
  // (The back of a double-sided emitter is seen through the coat on its side.)
  return 1.f - c * coat_fresnel(std::abs(glm::dot(towards, n)));
}

}  // namespace

SurfacePoint surface_at(const Scene& scene, uint32_t tri, float u, float v, const glm::vec3& ng) {
  const Material& m = scene.materials[scene.geometry.material[tri]];
  SurfacePoint s{ng, m.brdf(), m.emission, ng};
  if (!scene.normals.empty()) {
    const glm::vec3 n = interpolate(&scene.normals[3 * size_t(tri)], u, v);
    const float len = glm::length(n);
    if (len > 0.f) s.normal = s.coat_normal = n / len;
  }
  if (!scene.colors.empty()) {
    const glm::vec3 c(interpolate(&scene.colors[3 * size_t(tri)], u, v));
    s.brdf.base_color *= c;
    if (m.unlit) s.emission *= c;
  }
  if (m.anisotropic()) anisotropy_at(scene, m, tri, u, v, s);
  if (!m.textured()) return s;
  if (m.base_color_texture)
    s.brdf.base_color *= glm::vec3(lookup(scene, m.base_color_texture, tri, u, v, true));
  if (m.metallic_roughness_texture) {
    const glm::vec4 c = lookup(scene, m.metallic_roughness_texture, tri, u, v, false);
    s.brdf.roughness *= c.g;
    s.brdf.metallic *= c.b;
  }
  if (m.transmission_texture && m.transmission > 0.f)
    s.brdf.transmission *= lookup(scene, m.transmission_texture, tri, u, v, false).r;
  if (m.emissive_texture && m.emissive())
    s.emission *= glm::vec3(lookup(scene, m.emissive_texture, tri, u, v, true));
  if (m.unlit) return s;  // (its base colour texture is its emissive one)
  if (m.specular > 0.f) {  // KHR_materials_specular
    if (m.specular_texture) s.brdf.specular *= lookup(scene, m.specular_texture, tri, u, v, false).a;
    if (m.specular_color_texture)
      s.brdf.specular_color *= glm::vec3(lookup(scene, m.specular_color_texture, tri, u, v, true));
  }
  if (m.clearcoat > 0.f) {  // KHR_materials_clearcoat
    if (m.clearcoat_texture)
      s.brdf.clearcoat *= lookup(scene, m.clearcoat_texture, tri, u, v, false).r;
    if (m.clearcoat_roughness_texture)
      s.brdf.clearcoat_roughness *= lookup(scene, m.clearcoat_roughness_texture, tri, u, v, false).g;
    if (m.clearcoat_normal_texture)
      s.coat_normal = normal_mapped(scene, m.clearcoat_normal_texture, m.clearcoat_normal_scale,
                                    tri, u, v, s.coat_normal);
  }
  if (m.sheen()) {  // KHR_materials_sheen
    if (m.sheen_color_texture)
      s.brdf.sheen_color *= glm::vec3(lookup(scene, m.sheen_color_texture, tri, u, v, true));
    if (m.sheen_roughness_texture)
      s.brdf.sheen_roughness *= lookup(scene, m.sheen_roughness_texture, tri, u, v, false).a;
  }
  if (m.iridescence > 0.f) {  // KHR_materials_iridescence
    if (m.iridescence_texture)
      s.brdf.iridescence *= lookup(scene, m.iridescence_texture, tri, u, v, false).r;
    if (m.iridescence_thickness_texture) {
      const float g = lookup(scene, m.iridescence_thickness_texture, tri, u, v, false).g;
      s.brdf.iridescence_thickness =
          glm::mix(m.iridescence_thickness_min, m.iridescence_thickness_max, g);
    }
  }
  if (m.normal_texture)
    s.normal = normal_mapped(scene, m.normal_texture, m.normal_scale, tri, u, v, s.normal);
  return s;
}

float alpha_at(const Scene& scene, uint32_t tri, float u, float v) {
  const Material& m = scene.materials[scene.geometry.material[tri]];
  float alpha = m.alpha;
  if (!scene.colors.empty()) alpha *= interpolate(&scene.colors[3 * size_t(tri)], u, v).a;
  if (m.base_color_texture) alpha *= lookup(scene, m.base_color_texture, tri, u, v, true).a;
  return alpha;
}

float coverage_at(const Scene& scene, uint32_t tri, float u, float v) {
  const Material& m = scene.materials[scene.geometry.material[tri]];
  switch (m.alpha_mode) {
    case Material::AlphaMode::opaque:
      return 1.f;
    case Material::AlphaMode::mask:
      return alpha_at(scene, tri, u, v) >= m.alpha_cutoff ? 1.f : 0.f;
    case Material::AlphaMode::blend:
      return alpha_at(scene, tri, u, v);
  }
  return 1.f;
}

void prefetch_surface(const Scene& scene, uint32_t tri, float u, float v) {
  const Material& m = scene.materials[scene.geometry.material[tri]];
  for (const TextureRef* ref : m.sampled_textures()) {
    if (!ref || !*ref) continue;
    const Texture& t = scene.textures[size_t(ref->texture)];
    prefetch(scene.images[t.image], t, ref->apply(texcoord(scene, tri, ref->texcoord, u, v)));
  }
}

glm::vec3 emission_at(const Scene& scene, uint32_t tri, float u, float v,
                      const glm::vec3& towards) {
  const Material& m = scene.materials[scene.geometry.material[tri]];
  glm::vec3 e = m.emission;
  if (m.unlit && !scene.colors.empty())  // an unlit surface's vertex colours
    e *= glm::vec3(interpolate(&scene.colors[3 * size_t(tri)], u, v));
  if (m.emissive_texture && m.emissive())
    e *= glm::vec3(lookup(scene, m.emissive_texture, tri, u, v, true));
  // (Where the emission is black, as most of a mostly dark emissive texture is, the coat's
  // weight is not worked out.)
  if (m.clearcoat > 0.f && !m.unlit && e != glm::vec3(0.f))
    e *= coat_emission_weight(scene, m, tri, u, v, towards);
  return e;
}

}  // namespace dacrt
