// Integrator: turns a scene, traced through a Backend, into radiance on a Film. Integrators
// register themselves by name (one static Integrator::Registration line) and are created by name.
// Names: path (wavefront path tracer).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <glm/glm.hpp>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "integrators/environment.h"
#include "integrators/film.h"
#include "scene/scene.h"
#include "tracer/backend.h"
#include "tracer/ray_batch.h"
#include "util/progress.h"

namespace dacrt {

// Everything a render is asked to do; the CLI's render options map onto it one to one.
struct RenderSettings {
  int width = 512;
  int height = 512;
  int spp = 64;
  int camera = 0;
  int max_depth = 64;      // scattering events per path; Russian roulette ends most earlier
  int roulette_depth = 3;  // Russian roulette from this many bounces on
  uint64_t seed = 0;
  glm::vec3 environment{0.f};  // uniform radiance of everything the rays escape to
  // An equirectangular map instead (importance-sampled in next-event estimation); null: uniform.
  std::shared_ptr<const EnvironmentMap> environment_map;
  size_t wavefront = size_t(1) << 19;  // live paths at most per wavefront
};

struct RayTypeStats {
  uint64_t rays = 0;
  double seconds = 0.0;  // inside the backend
  double rays_per_second() const { return seconds > 0 ? rays / seconds : 0.0; }
};

struct RenderStats {
  std::array<RayTypeStats, ray_type_count> by_type;
  std::vector<RayTypeStats> by_bounce;  // bounce rays per depth (index 0: the first bounce)
  uint64_t paths = 0;
  uint64_t dropped_samples = 0;      // NaN or inf radiance, never averaged in
  double seconds = 0.0;              // whole render
  std::vector<std::string> skipped;  // work the scene did not need, in words

  uint64_t total_rays() const {
    uint64_t n = 0;
    for (const auto& t : by_type) n += t.rays;
    return n;
  }
};

class Integrator {
 public:
  virtual ~Integrator() = default;

  static std::unique_ptr<Integrator> create(std::string_view name, const Scene& scene,
                                            Backend& backend, const RenderSettings& settings);
  static std::vector<std::string> names();

  virtual void render(Film& film, Progress& progress) = 0;
  virtual const RenderStats& stats() const = 0;

  using Factory =
      std::function<std::unique_ptr<Integrator>(const Scene&, Backend&, const RenderSettings&)>;
  struct Registration {
    Registration(std::string name, Factory factory);
  };
};

// The camera ray through image point (x, y) (pixels, from the top-left corner) of a width ×
// height image, unit direction. Returns where along it the camera's near plane (znear) lies: the
// ray's tmin, so nothing nearer than znear is seen.
float camera_ray(const Camera& camera, int width, int height, float x, float y, glm::vec3& origin,
                 glm::vec3& direction);

}  // namespace dacrt
