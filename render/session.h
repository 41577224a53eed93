// RenderSession: a RenderRequest run to its outputs, for every front end. It checks what the
// outputs need before loading anything (the backends, the integrator, writable and distinct
// files that are not inputs, the display transform of a preview), loads the scene once, checks
// the memory the render will take, and renders each frame (posed at frame / fps) with each
// backend: the job, resume from the output's exact sums, checkpoints, the stop on SIGINT or
// SIGTERM, the EXR and preview with the header (render/header.h), the summary and the
// statistics. Under mpirun the ranks (a RankGroup) split each pixel's samples and rank 0 writes.
//
// render_to_film is the same render of a loaded scene into a film, without files: the Python
// module's render().
#pragma once

#include <tbb/global_control.h>

#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "dacrt/film/film.h"
#include "dacrt/render/render_job.h"
#include "dacrt/render/request.h"
#include "dacrt/render/run_report.h"
#include "dacrt/scene/scene.h"
#include "dacrt/util/paths.h"

namespace dacrt {

// The processes that render one image together: the ranks of an MPI job (apps/ranks.h). Every
// collective must be called by every rank in the same order.
class RankGroup {
 public:
  virtual ~RankGroup() = default;
  virtual int size() const = 0;
  virtual bool root() const = 0;
  // This rank's share of the samples [first, last).
  virtual std::pair<uint32_t, uint32_t> share(uint32_t first, uint32_t last) const = 0;
  // Collective: every rank's film added into rank 0's.
  virtual void reduce(Film& film) const = 0;
  // Collective: "" when no rank failed, else the lowest failing rank's message.
  virtual std::string first_error(const std::string& mine) const = 0;
  // Collective: whether any rank's flag is true.
  virtual bool any(bool mine) const = 0;
  // Collective: rank 0's `text` on every rank.
  virtual std::string broadcast(const std::string& text) const = 0;

  // Set once this process has passed the last collective call of the run: a failure after it
  // (rank 0 writing the outputs) is its own, and ends the run without waiting for the others.
  bool collectives_over = false;
};

// The whole MPI job fails: another rank's failure (its message), or a stop; every rank throws
// it, rank 0 prints the message.
struct RanksFailed {
  int code;
  std::string message;
};

// What a front end adds to a session.
struct SessionHooks {
  RankGroup* ranks = nullptr;  // under mpirun; nullptr: this process alone
  // Files the front end writes besides the session's outputs (checked as outputs with them).
  std::vector<NamedFile> more_outputs;
  // After a backend's outputs are written: its record and film.
  std::function<void(const BackendRun&, const Film&)> rendered;
};

class RenderSession {
 public:
  // Checks everything the outputs need before anything is loaded: UsageError for options that
  // cannot go together (one process under mpirun, several backends with --resume), Error for a
  // missing scene or an output that cannot be written.
  RenderSession(RenderRequest request, SessionHooks hooks = {});
  ~RenderSession();

  // Loads and renders every frame with every backend. Returns 0, or 128 + the signal that
  // stopped it (the outputs then hold what was rendered). A non-root rank of an MPI job returns
  // 0 once its share is gathered.
  int run();

  // The last frame's backends, as rendered (a stop skips those after it).
  const std::vector<BackendRun>& runs() const;
  // "scene.gltf, 256×256, 16 spp, path integrator": what the render was, for a report's title.
  const std::string& title() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// At most `threads` worker threads for as long as the result lives (none, all cores, for 0).
std::unique_ptr<tbb::global_control> thread_limit(int threads);

// A render of a loaded scene into a film, as one backend of a session makes it, without files:
// the thread limit, the memory check, the backend, the job and the sample range of `r` (whose
// backend names one). Progress on stderr unless r.quiet; r.passes.stop may stop it.
struct FilmRender {
  Film film;
  RenderOutcome outcome;
  std::vector<std::string> notes;  // for the user, not printed: the shot's (make_shot), a time
                                   // limit's stop, a nearly black image (dark_image_note)
};
FilmRender render_to_film(const RenderRequest& r, const Scene& scene);

}  // namespace dacrt
