#include "dacrt/scene/scene.h"

#include <algorithm>
#include <cmath>

#include "dacrt/util/error.h"

namespace dacrt {

std::vector<std::string> Scene::unused_work() const {
  bool textured = false, alpha = false, transmission = false;
  std::vector<bool> used(materials.size(), false);
  for (uint32_t m : geometry.material) used[m] = true;
  for (size_t i = 0; i < materials.size(); ++i) {
    if (!used[i]) continue;  // a material no triangle has costs nothing
    const Material& m = materials[i];
    textured |= m.textured();
    alpha |= m.alpha_mode != Material::AlphaMode::opaque;
    transmission |= m.transmission > 0.f;
  }
  std::vector<std::string> out;
  if (!textured) out.push_back("texture lookups and uv interpolation (no textures)");
  if (colors.empty()) out.push_back("vertex colours (none)");
  if (!alpha) out.push_back("alpha tests (every material is opaque)");
  if (!transmission) out.push_back("transmission (no transmissive material)");
  return out;
}

glm::vec3 PunctualLight::irradiance_towards(const glm::vec3& to) const {
  if (type == Type::directional) return intensity;
  // In double: d² and 1 / d² over- or underflow float in scenes scaled by 1e±19 and beyond.
  const glm::dvec3 to_double(to);
  const double d2 = glm::dot(to_double, to_double);
  if (!(d2 > 0.0)) return glm::vec3(0.f);
  double falloff = 1.0 / d2;
  if (range > 0.f) {  // KHR_lights_punctual's recommended window: clamp(1 − (d/range)⁴, 0, 1)
    const double r = d2 / (double(range) * range);
    falloff *= std::clamp(1.0 - r * r, 0.0, 1.0);
  }
  if (type == Type::spot) {
    const float cd = float(glm::dot(glm::dvec3(direction), to_double) / std::sqrt(d2));
    const float scale = 1.f / std::max(1e-3f, cos_inner - cos_outer);
    const float t = std::clamp((cd - cos_outer) * scale, 0.f, 1.f);
    falloff *= t * t;
  }
  return glm::vec3(glm::dvec3(intensity) * falloff);
}

std::string Scene::Ignored::unread_extensions() const {
  std::string out;
  for (const auto& [name, kinds] : extensions) {
    std::string where;
    for (const auto& [kind, n] : kinds)
      where += (where.empty() ? "" : ", ") + std::to_string(n) + " " + kind + (n == 1 ? "" : "s");
    out += (out.empty() ? "" : ", ") + name.substr(0, 100) + " (" +
           (where.empty() ? "listed in extensionsUsed" : where) + ")";
  }
  return out;
}

MaterialCounts count_materials(const Scene& scene) {
  MaterialCounts c;
  for (uint32_t m : scene.geometry.material) c.emissive_triangles += scene.materials[m].emitter();
  for (const Material& m : scene.materials) {
    c.emissive += m.emitter();
    c.textured += m.textured();
    c.masked += m.alpha_mode == Material::AlphaMode::mask;
    c.blended += m.alpha_mode == Material::AlphaMode::blend;
    c.transmissive += m.transmission > 0.f;
  }
  return c;
}

}  // namespace dacrt
