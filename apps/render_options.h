// The render options of the command line (`dacrt render --help` lists them), parsed into one
// struct: `dacrt render` reads them all, `dacrt converge` reads the shared ones and each
// configuration's KEY=VALUE overrides through the same parser, so a flag means the same in both.
#pragma once

#include <cstdint>
#include <optional>
#include <utility>
#include <stdexcept>
#include <string>
#include <vector>

#include "dacrt/integrators/integrator.h"
#include "dacrt/io/color.h"
#include "dacrt/io/gltf.h"
#include "dacrt/render/render_job.h"
#include "dacrt/tracer/options.h"

namespace dacrt {

// A mistake on the command line: the CLI prints it with a pointer to --help and exits 2.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct RenderArgs {
  std::string scene, output, preview, stats;
  std::string report;  // --report DIR: DIR/index.html and the backends' previews beside it
  DisplayOptions display;
  std::string display_flag;  // --view or --exposure, when given: they need --preview
  GltfOptions gltf;
  std::string backend = "dacrt";
  Options backend_options;
  int threads = 0;
  // --frames FIRST:LAST: the frames rendered, each at time frame / fps (--fps, default 24).
  std::optional<std::pair<int, int>> frames;
  // --samples FIRST:LAST: sample indices [FIRST, LAST) of every pixel of the --spp render (the
  // numbers of those samples are the whole render's: parts merge into it).
  std::optional<std::pair<uint32_t, uint32_t>> samples;
  // --keep-sums: the output keeps the film's exact sums (io/film_exr.h) even when it is complete;
  // --resume: continue the render its output holds (the exact sums of an earlier run).
  bool keep_sums = false, resume = false;
  double fps = 24.0;
  bool fps_given = false;
  bool quiet = false, help = false;
  RenderSettings settings;  // what is rendered: the image's options
  PassOptions passes;       // how the samples are scheduled: --pass-spp, --time-limit, --checkpoint
};

// Parses the render option args[i] (and its value, args[i + 1], advancing i past it) into `r`.
// Returns false, with nothing changed, when args[i] is not a render option (-h, --help, a
// positional argument, an unknown flag: the caller's business). Throws UsageError for a bad or
// missing value.
bool parse_render_option(const std::vector<std::string>& args, size_t& i, RenderArgs& r);

// --view NAME and --exposure STOPS (args[i] and its value, advancing i) into `display`, the flag
// into `flag`; false, nothing changed, for another argument. UsageError for a bad value.
bool parse_display_option(const std::vector<std::string>& args, size_t& i,
                          DisplayOptions& display, std::string& flag);

// `dacrt render`'s arguments: SCENE and render options.
RenderArgs parse_render(const std::vector<std::string>& args);

// Throws UsageError for --adaptive-min without --adaptive.
void check_adaptive(const RenderSettings& settings);

// Throws UsageError naming the known integrators unless `name` is one.
void check_integrator(const std::string& name);

// What `dacrt render` checks before loading anything: the integrator is known (UsageError), each
// of `backends` is (Error naming those there are), and every --backend-option is for one of them
// and taken by it, each backend built once on no geometry (UsageError).
void check_render_choices(const RenderArgs& r, const std::vector<std::string>& backends);
// A backend name the registry does not know is a usage error naming the known ones.
void check_backend(const std::string& name);

// An integer in [lo, hi] for `flag`, else UsageError.
long parse_int(const std::string& flag, const std::string& text, long lo, long hi);
// A positive finite number (seconds, distances) for `flag`, else UsageError.
double parse_seconds(const std::string& flag, const std::string& text);
// Whether `t` is a time an animation is posed at (`--time`, Python's load(time=)): seconds,
// finite, >= 0 and below 1e9.
bool valid_time(double t);

}  // namespace dacrt
