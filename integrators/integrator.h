// Integrator: turns a scene, traced through a Backend, into radiance on a Film. Integrators
// register themselves by name (one static Integrator::Registration line) and are created by name:
// path (the default), direct, ao, albedo, normal, depth; each file's first comment is its user
// documentation (`dacrt render --help` lists them).
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <glm/glm.hpp>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "dacrt/film/film.h"
#include "dacrt/integrators/light_tree.h"
#include "dacrt/integrators/sampler.h"
#include "dacrt/integrators/sample_order.h"
#include "dacrt/scene/camera.h"
#include "dacrt/scene/shot.h"
#include "dacrt/scene/scene.h"
#include "dacrt/tracer/backend.h"
#include "dacrt/tracer/ray_batch.h"
#include "dacrt/util/progress.h"

namespace dacrt {

// Everything a render is asked to do, the one description of it that the CLI (its render options
// map onto it one to one), `dacrt converge` and the library's callers fill. The scene is not
// changed by it: RenderJob resolves the view and the lighting into a Shot (scene/shot.h) once.
struct RenderSettings {
  std::string integrator = "path";  // Integrator::names()
  // The view.
  int camera = 0;                  // the scene's camera
  CameraOverride camera_override;  // --look-from, --look-at, --up, --fov
  LensRequest lens;                // --aperture or --fstop, --focus-distance or --focus-on
  int width = 0, height = 0;       // 0: from the camera's aspect ratio (scene/camera.h image_size)
  int longer_side = 512;           // with neither given
  // The lighting.
  std::optional<glm::vec3> environment;  // uniform radiance; unset: 0, or 1 without emitters
  std::string environment_file;          // an equirectangular .exr map instead
  std::shared_ptr<const EnvironmentMap> environment_map;  // or a map made already (the library)
  std::vector<PunctualLight> lights;     // added to the scene's (--point-light)
  // Next-event estimation of a uniform environment (the path tracer): as a constant map, with
  // MIS against BSDF sampling. automatic: where the scene is open to the sky (a deterministic
  // pilot of bounce rays from the camera's first hits, integrators/path.cpp).
  enum class EnvironmentSampling : uint8_t { automatic, on, off };
  EnvironmentSampling sample_environment = EnvironmentSampling::automatic;
  // How next-event estimation picks an emitter (integrators/lights.h): by a light tree where
  // there are many, else by power.
  LightPicking light_sampler = LightPicking::automatic;
  // The samples.
  int spp = 64;
  int max_depth = 64;      // scattering events per path; Russian roulette ends most earlier
  int roulette_depth = 3;  // Russian roulette from this many bounces on
  uint64_t seed = 0;
  // Adaptive sampling (render/adaptive.h): 0 off, else the relative error at which a pixel stops
  // taking samples, in (0, 1); adaptive_min: the samples every pixel takes first (0: max(16,
  // spp / 16)).
  double adaptive = 0.0;
  int adaptive_min = 0;
  SamplerKind sampler = SamplerKind::sobol;  // where the paths' numbers come from
  // The path tracer shades Lambert vertices sixteen at a time, and samples plain
  // metallic-roughness BRDFs in lanes (integrators/lambert_lanes.h); false: one at a time, the
  // general way (for the tests, and to measure what the lanes save).
  bool lambert_lanes = true;
  float ao_distance = 0.f;  // ao: how far occluders count (0: the scene's bounding-box diagonal)
  AovSet aovs;              // the first-hit values and statistics the film keeps
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
// ... and with the first-hit values the AOVs need.
inline uint64_t path_bytes(AovSet aovs) {
  return path_state_bytes + (aovs.first_hit() ? sizeof(FirstHit) : 0);
}

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
  uint64_t clamped_samples = 0;          // with values beyond ±value_limit (film/fixed.h)
  double seconds = 0.0;                  // whole render
  std::vector<std::string> skipped;      // work the scene did not need, in words
  // How next-event estimation picked emitters: "tree" or "power" (empty: it samples none), and
  // how many it picked from.
  std::string light_sampler;
  uint64_t light_entries = 0;

  uint64_t total_rays() const {
    uint64_t n = 0;
    for (const auto& t : by_type) n += t.rays;
    return n;
  }
};

class Integrator {
 public:
  virtual ~Integrator() = default;

  // The integrator settings.integrator names, rendering `shot` of `scene`.
  static std::unique_ptr<Integrator> create(const Scene& scene, const Shot& shot,
                                            Backend& backend, const RenderSettings& settings);
  static std::vector<std::string> names();

  // Adds samples [first, last) of every pixel to the film (sample indices, so that renders of
  // [0, a) and [a, b) merge into the image of [0, b)); of the pixels `only` lists (increasing)
  // when it is not empty. When *stop becomes true no new sample starts; the paths in flight
  // finish, so every sample begun reaches the film. Progress counts the samples finished over all
  // calls.
  // Returns the samples taken: (last − first) × pixels unless stopped, else the first that many
  // in the call's sample_order().
  virtual uint64_t render(Film& film, uint32_t first, uint32_t last,
                          std::span<const uint32_t> only, const std::atomic<bool>* stop,
                          Progress& progress) = 0;
  virtual const RenderStats& stats() const = 0;
  // The order of the samples of render(first, last) over `pixels` pixels (all, or as many as
  // `only` lists): integrators/sample_order.h. RenderJob learns from it what every pixel has
  // after a stop.
  virtual SampleOrder sample_order(uint32_t first, uint32_t last, uint64_t pixels) const = 0;

  using Factory = std::function<std::unique_ptr<Integrator>(const Scene&, const Shot&, Backend&,
                                                             const RenderSettings&)>;
  struct Registration {
    Registration(std::string name, Factory factory);
  };
};

}  // namespace dacrt
