// The record of one backend's render in a session (render/session.h): what it wrote, its
// statistics and times, how many samples its pixels got, and why it stopped early; and its summary
// on stderr.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "dacrt/integrators/integrator.h"
#include "dacrt/scene/shot.h"
#include "dacrt/tracer/stats.h"

namespace dacrt {

struct BackendRun {
  std::string backend, output, preview;
  RenderStats stats;
  Stats backend_stats;
  double seconds = 0.0;        // whole render, the backend's build included
  double build_seconds = 0.0;  // the backend's build (Backend::create) alone; 0 when updated
  // How the backend was made ready for this frame of --frames: "new" (created: the first frame,
  // or option frames=new), else what Backend::update did ("refit", "rebuild", or "build": the
  // triangle count changed), which took update_seconds.
  std::string update = "new";
  double update_seconds = 0.0;
  uint32_t spp = 0;            // samples every pixel has (fewer than asked when stopped early)
  // The samples the pixels got: fewest, most, mean (they differ with adaptive sampling).
  uint32_t least_spp = 0, most_spp = 0;
  double mean_spp = 0.0;
  std::string stopped;  // why the render stopped early ("SIGINT", "the time limit"), or empty
  uint32_t passes = 0;      // the whole passes rendered
  double time_limit = 0.0;  // --time-limit (seconds; 0: none)
};

// The smallest, median and largest of a render's bounce batches.
struct BatchSizes {
  uint32_t min = 0, median = 0, max = 0;
};
BatchSizes batch_sizes(std::vector<uint32_t> sizes);

// The summary on stderr: the output, size, samples, backend, integrator, seconds, the rays of
// each type and the warnings (samples dropped or clamped).
void print_summary(const BackendRun& run, const Shot& shot, const RenderSettings& s);

}  // namespace dacrt
