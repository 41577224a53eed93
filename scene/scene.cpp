#include "scene/scene.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

#include "util/error.h"

namespace dacrt {

Camera frame_bounds(const Box& bounds, float aspect, float yfov) {
  Camera cam;
  cam.name = "framed";
  cam.yfov = yfov;
  cam.aspect = aspect;
  glm::vec3 center = bounds.empty() ? glm::vec3(0.f) : bounds.center();
  float radius = bounds.empty() ? 1.f : 0.5f * glm::length(bounds.extent());
  if (!(radius > 0.f)) radius = 1.f;
  // Fit the bounding sphere in the narrower of the two fields of view.
  float half = 0.5f * yfov;
  if (aspect > 0.f && aspect < 1.f) half = std::atan(std::tan(half) * aspect);
  float distance = radius / std::sin(half);
  glm::vec3 dir = glm::normalize(glm::vec3(0.f, 0.25f, 1.f));
  glm::vec3 eye = center + distance * dir;
  cam.to_world = glm::inverse(glm::lookAt(eye, center, glm::vec3(0.f, 1.f, 0.f)));
  cam.znear = 0.f;
  return cam;
}

Camera override_camera(const Camera& base, const CameraOverride& o, const glm::vec3& target) {
  const glm::vec3 position = base.position(), forward = -glm::vec3(base.to_world[2]);
  const glm::vec3 from = o.from.value_or(position);
  const glm::vec3 at = o.at ? *o.at : o.from ? target : position + forward;
  const glm::vec3 up = o.up.value_or(glm::vec3(base.to_world[1]));
  const glm::vec3 view = at - from;
  if (!(glm::length(view) > 0.f))
    throw Error("--look-at must differ from --look-from (the camera's position)");
  if (!(glm::length(glm::cross(glm::normalize(view), up)) > 1e-6f))
    throw Error("--up must not be parallel to the view direction (or zero)");
  Camera cam = base;
  if (o.any()) cam.name = "command line";
  cam.to_world = glm::inverse(glm::lookAt(from, at, up));
  if (o.fov_degrees) {
    cam.orthographic = false;
    cam.yfov = glm::radians(*o.fov_degrees);
  }
  return cam;
}

glm::vec3 look_at_point(const Camera& camera, const glm::vec3& target) {
  const float d = glm::length(target - camera.position());
  return camera.position() - glm::vec3(camera.to_world[2]) * (d > 0.f ? d : 1.f);
}

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
  const float d2 = glm::dot(to, to);
  if (!(d2 > 0.f)) return glm::vec3(0.f);
  float falloff = 1.f / d2;
  if (range > 0.f) {  // KHR_lights_punctual's recommended window: clamp(1 − (d/range)⁴, 0, 1)
    const float r = d2 / (range * range);
    falloff *= std::clamp(1.f - r * r, 0.f, 1.f);
  }
  if (type == Type::spot) {
    const float cd = glm::dot(direction, to) / std::sqrt(d2);
    const float scale = 1.f / std::max(1e-3f, cos_inner - cos_outer);
    const float t = std::clamp((cd - cos_outer) * scale, 0.f, 1.f);
    falloff *= t * t;
  }
  return intensity * falloff;
}

}  // namespace dacrt
