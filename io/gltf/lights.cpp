// glTF lights: KHR_lights_punctual's point, spot and directional lights, placed by their node.
#include "io/gltf/internal.h"

namespace dacrt::gltf {

// KHR_lights_punctual: {"extensions": {"KHR_lights_punctual": {"light": index}}} on a node.
std::optional<PunctualLight> load_light(const Gltf& gltf, const tinygltf::Node& node,
                                        const glm::mat4& world, int index) {
  auto ext = node.extensions.find("KHR_lights_punctual");
  if (ext == node.extensions.end()) return std::nullopt;
  const std::string where = "node " + str(index);
  if (!ext->second.IsObject() || !ext->second.Has("light") || !ext->second.Get("light").IsNumber())
    gltf.fail(where + ": KHR_lights_punctual has no light index");
  const double light = ext->second.Get("light").GetNumberAsDouble();
  if (!(light >= 0.0 && light < double(gltf.model.lights.size())) || light != std::floor(light))
    gltf.fail(where + " refers to light " + std::to_string(light) + ", which does not exist (" +
              str(gltf.model.lights.size()) + " lights)");
  const tinygltf::Light& src = gltf.model.lights[size_t(light)];
  const std::string what = "light " + str(int(light));
  PunctualLight l;
  l.name = src.name;
  if (src.type == "point")
    l.type = PunctualLight::Type::point;
  else if (src.type == "spot")
    l.type = PunctualLight::Type::spot;
  else if (src.type == "directional")
    l.type = PunctualLight::Type::directional;
  else
    gltf.fail(what + ": type \"" + src.type + "\" is not point, spot or directional");
  glm::vec3 color(1.f);
  if (!src.color.empty()) {
    if (src.color.size() != 3)
      gltf.fail(what + ": color has " + str(src.color.size()) + " numbers");
    color = glm::vec3(src.color[0], src.color[1], src.color[2]);
  }
  if (!finite(color) || glm::any(glm::lessThan(color, glm::vec3(0.f))))
    gltf.fail(what + ": color is not 3 finite numbers >= 0");
  if (!(src.intensity >= 0.0) || !std::isfinite(src.intensity))
    gltf.fail(what + ": intensity is not a finite number >= 0");
  if (!(src.range >= 0.0) || !std::isfinite(src.range))
    gltf.fail(what + ": range is not a finite number > 0");
  l.intensity = color * float(src.intensity);
  l.range = float(src.range);
  if (l.type == PunctualLight::Type::spot) {
    const double inner = src.spot.innerConeAngle, outer = src.spot.outerConeAngle;
    if (!(inner >= 0.0 && inner < outer && outer <= 0.5 * M_PI))
      gltf.fail(what +
                ": spot cone angles must satisfy 0 <= innerConeAngle < outerConeAngle <= pi/2");
    l.cos_inner = float(std::cos(inner)), l.cos_outer = float(std::cos(outer));
  }
  l.position = glm::vec3(world[3]);
  l.direction = unit_or(-glm::vec3(world[2]), glm::vec3(0.f));
  if (l.direction == glm::vec3(0.f) && l.type != PunctualLight::Type::point)
    gltf.fail(where + " gives " + what + " a degenerate transform (zero scale)");
  return l;
}

}  // namespace dacrt::gltf
