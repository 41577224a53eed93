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
  // Live paths at most (stream regeneration keeps this many while samples remain). 0: as many
  // as wavefront_budget bytes of path state hold (path_state_bytes each), up to the frame's.
  size_t wavefront = 0;
  uint64_t wavefront_budget = uint64_t(96) << 20;
};

// The bytes one live path takes in the path integrator: its state (throughput, radiance, pixel,
// sample, pdf, depth: 40), its rays in the camera, bounce, next-bounce and shadow queues (4 × 36),
// hits (16), the stages' scratch (two ray records of 40, a contribution of 12, flags and indices:
// 109), and the dacrt backend's ray record (36).
inline constexpr uint64_t path_state_bytes = 40 + 4 * 36 + 16 + 109 + 36;

// The largest image side, whether given (--width, --height) or derived from a camera's aspect.
inline constexpr int max_image_side = 1 << 15;

// The image size for a camera of this aspect ratio (width / height; <= 0: none) and the sides
// given (0: not given). Both given are kept; one given keeps the camera's aspect (or makes a
// square); none gives `longer` pixels on the longer side. Throws Error("<camera>'s aspectRatio
// 1e-07 with --width 8 gives a height of 79999999 pixels, more than 32768 …") when the derived side
// is over max_image_side.
glm::ivec2 image_size(float aspect, int width, int height, int longer, const std::string& camera);

// The live paths a render of `paths` samples keeps with these settings.
size_t resolve_wavefront(const RenderSettings& settings, uint64_t paths);

struct RayTypeStats {
  uint64_t rays = 0;
  double seconds = 0.0;  // inside the backend
  double rays_per_second() const { return seconds > 0 ? rays / seconds : 0.0; }
};

struct RenderStats {
  std::array<RayTypeStats, ray_type_count> by_type;
  std::vector<RayTypeStats> by_bounce;  // bounce rays per depth (index 0: the first bounce)
  uint64_t paths = 0;
  uint64_t wavefront = 0;                // live paths at most
  uint64_t bounce_calls = 0;             // backend calls with bounce rays
  std::vector<uint32_t> bounce_batches;  // the bounce rays of each of those calls, in order
  uint64_t dropped_samples = 0;          // NaN or inf radiance, never averaged in
  double seconds = 0.0;                  // whole render
  std::vector<std::string> skipped;      // work the scene did not need, in words

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
