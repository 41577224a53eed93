// glTF lights: KHR_lights_punctual's point, spot and directional lights, placed by their node.
#include <limits>

#include "dacrt/io/gltf/internal.h"

namespace dacrt::gltf {

// KHR_lights_punctual: {"extensions": {"KHR_lights_punctual": {"light": index}}} on a node.
std::optional<PunctualLight> load_light(const Gltf& gltf, const tinygltf::Node& node,
                                        const glm::dmat4& world, int index) {
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
  else {  // not one the extension defines (the schema checked it is a string)
    gltf.unknown_lights.insert(int(light));
    return std::nullopt;
  }
  // Each number must hold in float, as the renderer keeps it: 1e39 is finite in the file and
  // infinite as float, which would make every sample of the light NaN.
  glm::dvec3 color(1.0);
  if (!src.color.empty()) {
    if (src.color.size() != 3)
      gltf.fail(what + ": color has " + str(src.color.size()) + " numbers");
    color = glm::dvec3(src.color[0], src.color[1], src.color[2]);
  }
  for (int c = 0; c < 3; ++c)
    if (!(color[c] >= 0.0) || !as_float(color[c]))
      gltf.fail(what + ": color " + num(color[c]) + " is not a number in [0, 3.4e38] (float)");
  if (!(src.intensity >= 0.0) || !as_float(src.intensity))
    gltf.fail(what + ": intensity " + num(src.intensity) +
              " is not a number in [0, 3.4e38] (float)");
  l.intensity = glm::vec3(color * src.intensity);
  if (!finite(l.intensity))
    gltf.fail(what + ": color times intensity (" + num(src.intensity) +
              ") is beyond float's range");
  if (!(src.range >= 0.0) || !as_float(src.range))
    gltf.fail(what + ": range " + num(src.range) + " is not a number in [0, 3.4e38] (float)");
  // 0 means unlimited: a range too small for float stays the smallest one, not unlimited.
  l.range =
      src.range > 0.0 ? std::max(float(src.range), std::numeric_limits<float>::denorm_min()) : 0.f;
  if (l.type == PunctualLight::Type::spot) {
    const double inner = src.spot.innerConeAngle, outer = src.spot.outerConeAngle;
    if (!(inner >= 0.0 && inner < outer && outer <= 0.5 * M_PI))
      gltf.fail(what +
                ": spot cone angles must satisfy 0 <= innerConeAngle < outerConeAngle <= pi/2");
    l.cos_inner = float(std::cos(inner)), l.cos_outer = float(std::cos(outer));
  }
  l.position = glm::vec3(world[3]);
  if (!finite(l.position))
    gltf.fail(where + " places " + what + " beyond float's range (" + num(world[3].x) + ", " +
              num(world[3].y) + ", " + num(world[3].z) + ")");
  // In double and scaled first: the scale is removed whatever its size.
  const std::optional<glm::vec3> z = direction_of(glm::dvec3(world[2]));
  l.direction = z ? -*z : glm::vec3(0.f);
  if (!z && l.type != PunctualLight::Type::point)
    gltf.fail(where + " gives " + what +
              " a zero scale along its Z axis: the light has no direction");
  return l;
}

}  // namespace dacrt::gltf
