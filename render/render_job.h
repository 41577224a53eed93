// RenderJob: a render as the library runs it, for the CLI, `dacrt bench`, the tests and (later)
// bindings and distributed rendering. It holds the scene, the backend, the settings and the
// integrator, and adds a range of samples [first, last) of every pixel to a Film, in passes:
// whole passes give every pixel the same count; a stop token ends the render at the next
// wavefront (the samples begun still finish and reach the film, so nothing rendered is lost); a
// time limit ends it after the pass that crosses it; a checkpoint callback sees the film after
// passes, at most once per checkpoint interval. Films of [0, a) and [a, b) merge into [0, b).
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "integrators/integrator.h"
#include "film/film.h"
#include "scene/scene.h"
#include "tracer/backend.h"
#include "util/progress.h"

namespace dacrt {

// What the user asked of the scene that glTF does not say: which camera and how it is moved,
// the image size, the environment.
struct RenderSetup {
  int camera = 0;
  CameraOverride camera_override;
  std::optional<int> width, height;      // unset: from the camera's aspect ratio
  int longer_side = 512;                 // with neither set
  std::optional<glm::vec3> environment;  // uniform radiance; unset: 0, or 1 without emitters
  std::string environment_file;          // an equirectangular .exr map instead
  std::vector<PunctualLight> lights;     // added to the scene's (--point-light)
};

// Applies the camera override to the chosen camera (Error naming the flags when it is
// degenerate; Error when the camera does not exist).
void override_scene_camera(Scene& scene, const RenderSetup& setup);

// Sets the image size (settings.width, height, camera), adds the setup's lights and sets the
// scene's environment. Returns
// notes for the user (a scene without emitters lit by a uniform environment of 1, a framed
// camera). Throws Error for a size over max_image_side or a bad environment map.
std::vector<std::string> prepare_render(Scene& scene, RenderSettings& settings,
                                        const RenderSetup& setup);

// Whether anything in the scene emits light (emissive triangles, punctual lights).
bool has_emitters(const Scene& scene);

// A render's largest allocations, estimated before any is made: the film, its resolved channels
// and the preview (image), the path state (paths).
struct RenderMemory {
  uint64_t image = 0, paths = 0;
};
RenderMemory render_memory(const RenderSettings& settings, bool preview);

struct PassOptions {
  uint32_t spp_per_pass = 0;  // 0: enough samples for 8 wavefronts a pass, at least 1 per pixel
  double time_limit = 0.0;    // seconds; 0: none. The render stops after the pass that crosses it
  double checkpoint = 0.0;    // seconds between checkpoint calls (at pass ends); 0: none
  const std::atomic<bool>* stop = nullptr;  // true: stop at the next wavefront
};

struct RenderOutcome {
  uint32_t first = 0;
  uint32_t complete = 0;  // every pixel has the samples [first, complete)
  uint32_t most = 0;      // some pixels have up to [first, most) (a pass cut short by a stop)
  uint32_t passes = 0;    // whole passes
  bool stopped = false, timed_out = false;
  double seconds = 0.0;
  uint32_t spp() const { return complete - first; }
  bool uniform() const { return most == complete; }
};

class RenderJob {
 public:
  RenderJob(const Scene& scene, Backend& backend, RenderSettings settings,
            std::string integrator = "path");
  ~RenderJob();

  const RenderSettings& settings() const { return settings_; }
  const std::string& integrator() const { return name_; }
  const RenderStats& stats() const;

  // An empty film of the job's size and outputs.
  Film film() const { return Film(settings_.width, settings_.height, settings_.aovs); }

  // The samples per pixel of one pass.
  uint32_t pass_size(const PassOptions& options) const;

  // Adds samples [first, last) of every pixel to `film`. `checkpoint` (may be empty) is called
  // with the film and the outcome so far after passes, every options.checkpoint seconds.
  using Checkpoint = std::function<void(const Film&, const RenderOutcome&)>;
  RenderOutcome run(Film& film, uint32_t first, uint32_t last, Progress& progress,
                    const PassOptions& options = {}, const Checkpoint& checkpoint = {});

 private:
  const Scene& scene_;
  const RenderSettings settings_;
  const std::string name_;
  std::unique_ptr<Integrator> integrator_;
};

// dacrt's version ("0.1.0"), for headers and statistics.
const char* version();

}  // namespace dacrt
