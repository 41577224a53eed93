#include "dacrt/scene/camera.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/gtc/matrix_transform.hpp>
#include <string>

#include "dacrt/util/error.h"

namespace dacrt {

Camera frame_bounds(const Box& bounds, float aspect, float yfov) {
  Camera cam;
  cam.name = "framed";
  cam.yfov = yfov;
  cam.aspect = aspect;
  // In double: in float the extent's length (a sum of squares) overflows for scenes beyond ~1e19
  // and underflows below ~1e-19, and so does lookAt's normalisation (glTF node scales of 1e30 and
  // 1e-30, tests/stress_test.cpp).
  const glm::dvec3 lo(bounds.lo), hi(bounds.hi);
  const glm::dvec3 center = bounds.empty() ? glm::dvec3(0.0) : 0.5 * lo + 0.5 * hi;
  double radius = bounds.empty() ? 1.0 : 0.5 * glm::length(hi - lo);
  if (!(radius > 0.0) || !std::isfinite(radius)) radius = 1.0;
  // Fit the bounding sphere in the narrower of the two fields of view.
  double half = 0.5 * yfov;
  if (aspect > 0.f && aspect < 1.f) half = std::atan(std::tan(half) * aspect);
  const double distance = radius / std::sin(half);
  const glm::dvec3 dir = glm::normalize(glm::dvec3(0.0, 0.25, 1.0));
  const glm::dvec3 eye = center + distance * dir;
  cam.aimed_up = glm::vec3(0.f, 1.f, 0.f);
  cam.to_world = glm::mat4(glm::inverse(glm::lookAt(eye, center, glm::dvec3(0.0, 1.0, 0.0))));
  cam.znear = 0.f;
  return cam;
}

Camera override_camera(const Camera& base, const CameraOverride& o, const glm::vec3& target) {
  const glm::vec3 position = base.position(), forward = -glm::vec3(base.to_world[2]);
  const glm::vec3 from = o.from.value_or(position);
  const glm::vec3 at = o.at ? *o.at : o.from ? target : position + forward;
  const glm::vec3 up = o.up.value_or(base.up());
  // In double: a view between points 1e20 apart has a length whose square overflows a float.
  const glm::dvec3 view = glm::dvec3(at) - glm::dvec3(from);
  if (!(glm::length(view) > 0.0))
    throw SettingError("--look-at must differ from --look-from (the camera's position)");
  if (!(glm::length(glm::dvec3(up)) > 0.0)) throw SettingError("--up must not be zero");
  if (!(glm::length(glm::cross(glm::normalize(view), glm::normalize(glm::dvec3(up)))) > 1e-6))
    throw SettingError("--up must not be parallel to the view direction");
  Camera cam = base;
  if (o.any()) cam.name = "command line";
  cam.to_world =
      glm::mat4(glm::inverse(glm::lookAt(glm::dvec3(from), glm::dvec3(at), glm::dvec3(up))));
  if (o.any()) cam.aimed_up = up;
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

CameraProjection::CameraProjection(const Camera& camera, int w, int h)
    : to_world(camera.to_world),
      width(float(w)),
      height(float(h)),
      aspect(float(w) / float(h)),
      tan_half(std::tan(0.5f * camera.yfov)),
      ymag(camera.ymag),
      znear(camera.znear),
      orthographic(camera.orthographic) {}

float camera_ray(const Camera& camera, int width, int height, float x, float y, glm::vec3& origin,
                 glm::vec3& direction) {
  return CameraProjection(camera, width, height).ray(x, y, origin, direction);
}

std::string camera_flags(const Camera& cam, const glm::vec3& target) {
  const glm::vec3 p = cam.position() + 0.f;  // + 0: no "-0" printed
  const glm::vec3 at = look_at_point(cam, target) + 0.f;
  const glm::vec3 up = cam.up() + 0.f;
  char text[320];
  std::snprintf(text, sizeof text,
                "--look-from %.7g,%.7g,%.7g --look-at %.7g,%.7g,%.7g --up %.7g,%.7g,%.7g", p.x, p.y,
                p.z, at.x, at.y, at.z, up.x, up.y, up.z);
  std::string out = text;
  if (!cam.orthographic) {
    std::snprintf(text, sizeof text, " --fov %.7g", cam.yfov * 180.0 / M_PI);
    out += text;
  }
  return out;
}

glm::ivec2 image_size(float aspect, int width, int height, int longer, const std::string& camera) {
  if (width > 0 && height > 0) return {width, height};
  if (!(aspect > 0.f)) {
    const int side = width > 0 ? width : height > 0 ? height : longer;
    return {side, side};
  }
  auto derived = [&](double size, const char* side, const char* flag, int given) {
    if (!(size <= double(max_image_side))) {
      char ratio[32];
      std::snprintf(ratio, sizeof ratio, "%g", double(aspect));
      throw Error(camera + "'s aspectRatio " + ratio + " with " + flag + " " +
                  std::to_string(given) + " gives a " + side + " of " +
                  (size < 1e15 ? std::to_string(std::llround(size)) : std::to_string(size)) +
                  " pixels, more than " + std::to_string(max_image_side) +
                  " (give --width and --height)");
    }
    return std::max(1, int(std::lround(size)));
  };
  if (width > 0) return {width, derived(width / double(aspect), "height", "--width", width)};
  if (height > 0) return {derived(height * double(aspect), "width", "--height", height), height};
  // The longer side is `longer`: the other cannot exceed it.
  if (aspect >= 1.f) return {longer, std::max(1, int(std::lround(longer / double(aspect))))};
  return {std::max(1, int(std::lround(longer * double(aspect)))), longer};
}

}  // namespace dacrt
