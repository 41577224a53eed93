// RenderJob: a render as the library runs it, for the CLI, `dacrt bench`, the tests and (later)
// bindings and distributed rendering. It holds the scene, the backend, the settings, the shot
// they resolve to (scene/shot.h: the camera, size, lights and environment, made once) and the
// integrator, and adds a range of samples [first, last) of every pixel to a Film, in passes:
// whole passes give every pixel the same count; a stop token ends the render at the next
// wavefront (the samples begun still finish and reach the film, so nothing rendered is lost); a
// time limit ends it after the pass that crosses it (the passes sized from the rate measured and
// the time left, unless spp_per_pass sets them); a checkpoint callback sees the film after
// passes, at most once per checkpoint interval. Films of [0, a) and [a, b) merge into [0, b).
// With adaptive sampling (settings.adaptive, render/adaptive.h) the passes after the minimum give
// samples only to the pixels that have not converged; the job remembers which pixels stopped, so
// a render continued by another call (first = where the last ended) goes on from there, and one
// from sample 0 starts again with every pixel.
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "dacrt/film/film.h"
#include "dacrt/integrators/integrator.h"
#include "dacrt/render/adaptive.h"
#include "dacrt/scene/scene.h"
#include "dacrt/scene/shot.h"
#include "dacrt/tracer/backend.h"
#include "dacrt/util/progress.h"

namespace dacrt {

// What a render of `scene` with `settings` sees: the chosen camera with the settings' override
// applied, the image size, the scene's lights and the settings', the environment (a map given,
// or read from settings.environment_file), and notes for the user (a scene without emitters lit
// by a uniform environment of 1, a framed camera). Throws Error for a camera the scene does not
// have, a size over max_image_side or a bad environment map; SettingError (naming the flags) for
// a degenerate camera override.
Shot make_shot(const Scene& scene, const RenderSettings& settings);

// The lighting of a render that states none (no --environment): a uniform sky of 1 besides the
// scene's punctual lights and emitters, as glTF viewers light every model with an environment
// (a helmet or a car under its few glowing parts, a model beside a sun, come out black without
// one), unless the scene lights itself: it has an emitter brighter than the sky (a radiance above
// 1 in some channel: glTF's emissiveFactor stops at 1, and only KHR_materials_emissive_strength
// goes past it, as emissive meshes meant as lamps do: the Cornell box's), or the command line adds
// lights (`added_lights`, --point-light). Emitters no brighter than the sky glow (a visor, a
// screen, a label) beside it.
struct DefaultLighting {
  bool sky = false;      // a uniform environment of 1 is added
  std::string what;      // the lighting, for notes and `dacrt info` ("a uniform sky of 1: …")
};
DefaultLighting default_lighting(const Scene& scene, size_t added_lights);

// One line when an image is nearly black (at least 97 % of its pixels below 1/500 of white after
// the exposure, which a preview shows as black): naming the output and the option that changes
// it, which depends on how the shot is lit. Empty when the image is not dark.
std::string dark_image_note(const Image& image, const Shot& shot, double exposure,
                            const std::string& output);

// A render's largest allocations, estimated before any is made: the film, its resolved channels
// and the preview (image), the path state (paths).
struct RenderMemory {
  uint64_t image = 0, paths = 0;
};
RenderMemory render_memory(const Shot& shot, const RenderSettings& settings, bool preview);

struct PassOptions {
  uint32_t spp_per_pass = 0;  // 0: enough samples for 8 wavefronts a pass, at least 1 per pixel
  // Seconds; 0: none. The render stops after the pass that crosses it. Without spp_per_pass the
  // passes are then sized by the time left (RenderJob::run), so that it ends within a pass of it.
  double time_limit = 0.0;
  double checkpoint = 0.0;    // seconds between checkpoint calls (at pass ends); 0: none
  const std::atomic<bool>* stop = nullptr;  // true: stop at the next wavefront
};

struct RenderOutcome {
  uint32_t first = 0;
  // Every pixel has the samples [first, complete), adaptive sampling's pixels still sampling.
  uint32_t complete = 0;
  uint32_t most = 0;      // some pixels have up to [first, most) (a pass cut short by a stop)
  uint32_t passes = 0;    // whole passes
  bool stopped = false, timed_out = false;
  double seconds = 0.0;
  uint32_t spp() const { return complete - first; }
  bool uniform() const { return most == complete; }
};

class RenderJob {
 public:
  // The job of settings.integrator on the shot the settings make (make_shot's errors).
  RenderJob(const Scene& scene, Backend& backend, RenderSettings settings);
  // ... on a shot made already (by make_shot, for several jobs of the same shot).
  RenderJob(const Scene& scene, Backend& backend, RenderSettings settings, Shot shot);
  ~RenderJob();

  const RenderSettings& settings() const { return settings_; }
  const Shot& shot() const { return shot_; }
  const RenderStats& stats() const;

  // An empty film of the shot's size and the settings' outputs.
  Film film() const { return Film(shot_.width, shot_.height, settings_.aovs); }

  // The samples per pixel of one pass.
  uint32_t pass_size(const PassOptions& options) const;

  // Adds samples [first, last) of every pixel to `film`. `checkpoint` (may be empty) is called
  // with the film and the outcome so far after passes, every options.checkpoint seconds.
  using Checkpoint = std::function<void(const Film&, const RenderOutcome&)>;
  RenderOutcome run(Film& film, uint32_t first, uint32_t last, Progress& progress,
                    const PassOptions& options = {}, const Checkpoint& checkpoint = {});

  // Continues a film of samples [first, …) of this render, stopped anywhere (each pixel has
  // [first, first + film.taken(pixel))), up to `last`: first the pixels a stop left behind take
  // the samples the others have, level by level, then passes go on as run's. The film ends the
  // same bit for bit as one run(first, last) would have made it. Not with adaptive sampling.
  RenderOutcome resume(Film& film, uint32_t first, uint32_t last, Progress& progress,
                       const PassOptions& options = {}, const Checkpoint& checkpoint = {});

  // Frees the integrator and its working memory (the path state, the queues, the batches) once
  // the samples are taken, so that writing the film's outputs does not hold them too. stats()
  // stays valid; run and resume may not be called after.
  void release();

 private:
  const RenderSettings settings_;
  const Shot shot_;
  std::unique_ptr<Integrator> integrator_;
  std::optional<RenderStats> released_stats_;  // the integrator's, kept by release()
  std::optional<AdaptiveSampling> adaptive_;  // with settings_.adaptive > 0
};

// dacrt's version ("0.1.0"), for headers and statistics.
const char* version();

}  // namespace dacrt
