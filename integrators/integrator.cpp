#include "integrators/integrator.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "util/error.h"
#include "util/registry.h"

namespace dacrt {

namespace {
Registry<Integrator::Factory>& registry() {
  static Registry<Integrator::Factory> r("integrator");
  return r;
}
}  // namespace

Integrator::Registration::Registration(std::string name, Factory factory) {
  registry().add(std::move(name), std::move(factory));
}

std::vector<std::string> Integrator::names() {
  return registry().names();
}

std::unique_ptr<Integrator> Integrator::create(std::string_view name, const Scene& scene,
                                               Backend& backend, const RenderSettings& settings) {
  return registry().find(name)(scene, backend, settings);
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

size_t resolve_wavefront(const RenderSettings& s, uint64_t paths) {
  const uint64_t n = s.wavefront > 0 ? s.wavefront : s.wavefront_budget / path_state_bytes;
  return size_t(std::clamp<uint64_t>(std::min(n, paths), 1, uint64_t(1) << 31));
}

float camera_ray(const Camera& camera, int width, int height, float x, float y, glm::vec3& origin,
                 glm::vec3& direction) {
  const float aspect = float(width) / float(height);
  if (camera.orthographic) {
    const glm::vec3 local((2.f * x / width - 1.f) * camera.ymag * aspect,
                          (1.f - 2.f * y / height) * camera.ymag, 0.f);
    origin = glm::vec3(camera.to_world * glm::vec4(local, 1.f));
    direction = -glm::vec3(camera.to_world[2]);
    return camera.znear;
  }
  const float tan_half = std::tan(0.5f * camera.yfov);
  glm::vec3 local((2.f * x / width - 1.f) * tan_half * aspect, (1.f - 2.f * y / height) * tan_half,
                  -1.f);
  origin = camera.position();
  direction = glm::normalize(glm::vec3(camera.to_world * glm::vec4(local, 0.f)));
  // The near plane is at depth znear: `local` (depth 1) scaled by znear, |local| · znear away.
  return camera.znear * glm::length(local);
}

}  // namespace dacrt
