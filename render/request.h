// RenderRequest: a render as any front end asks for it (the CLI's `dacrt render`, `dacrt
// converge`'s configurations, the Python module's keywords): the scene file and how to load it,
// the settings of the image, the backends, the sample range, the frames and the outputs. A
// RenderSession (render/session.h) runs it.
//
// The render options are one table (render_options()): each option's name, value, where it is
// taken (the CLI, converge, Python), its lines of `dacrt render --help` and the function that
// applies its value. The CLI's parser, `--help`, converge's --config keys and Python's keywords
// all come from it, so an option cannot be in one and missing from another.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "dacrt/integrators/integrator.h"
#include "dacrt/io/color.h"
#include "dacrt/io/gltf.h"
#include "dacrt/render/render_job.h"
#include "dacrt/tracer/options.h"
#include "dacrt/util/error.h"

namespace dacrt {

struct RenderRequest {
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

  // The samples rendered: every one of the --spp render's, or the --samples range of them.
  uint32_t first_sample() const { return samples ? samples->first : 0; }
  uint32_t last_sample() const { return samples ? samples->second : uint32_t(settings.spp); }
};

// What an option's value is: how the CLI spells it and what Python passes for it.
enum class OptionValue : uint8_t {
  none,     // a flag (Python: a bool)
  integer,  // Python: an int
  number,   // Python: an int or a float
  text,     // a name (Python: a str)
  name_or_index,  // a name or an index (Python: a str or an int)
  path,     // a file (Python: a str, bytes or a path-like object)
  point,    // X,Y,Z (Python: three numbers)
  range,    // FIRST:LAST (Python: two ints)
  names,    // NAME[,NAME...] (Python: a str or a list of str)
  colour_or_file,  // R,G,B or FILE.exr (Python: three numbers, or a path)
};

// Where an option is taken: bits of RenderOption::uses.
enum OptionUse : unsigned {
  use_render = 1,     // `dacrt render`
  use_converge = 2,   // `dacrt converge`'s shared options
  use_config = 4,     // a converge --config KEY=VALUE
  use_python = 8,     // a keyword of Python's render()
};

struct RenderOption {
  std::string_view name;     // "--spp"
  std::string_view section;  // the heading of `dacrt render --help` it is listed under
  OptionValue value;
  unsigned uses;        // OptionUse bits
  bool repeatable;      // each use adds one (Python: a list of them)
  std::string_view help;  // its lines of `dacrt render --help` (empty: on another's lines)
  // Sets the option's value into the request; `flag` is how the caller spelt the option
  // ("--spp", "spp="), for messages. Throws UsageError for a bad value.
  void (*apply)(RenderRequest& r, const std::string& value, const std::string& flag);
  std::string_view short_name = {};  // "-o"
  std::string_view keyword = {};     // Python's keyword when not the name's ("aovs")

  // The Python keyword: `keyword`, else the name without dashes, '-' as '_' ("look_from").
  std::string python_keyword() const;
};

// Every render option, in the order of `dacrt render --help`.
std::span<const RenderOption> render_options();
// The option named `name` ("--spp", "-o"), or nullptr.
const RenderOption* find_render_option(std::string_view name);
// `dacrt render --help`, made from the table.
std::string render_help();

// Parses the render option args[i] (and its value, args[i + 1], advancing i past it) into `r`.
// Returns false, with nothing changed, when args[i] is not an option of `use` (-h, --help, a
// positional argument, an unknown flag: the caller's business). Throws UsageError for a bad or
// missing value.
bool parse_render_option(const std::vector<std::string>& args, size_t& i, RenderRequest& r,
                         unsigned use = use_render);

// An option given as one word, "--name=value" (args[i]), made two, "--name" and "value", as
// the parsers take them; a flag among `flags` given a value is a UsageError ("--quiet takes no
// value"). Only at an option's place: a value that begins with "--" is left as it is.
void split_option_value(std::vector<std::string>& args, size_t i,
                        const std::vector<std::string>& flags = {});

// The render options that take no value (the flags), for split_option_value.
std::vector<std::string> render_flag_names();

// The values an option takes when they are a known set of names, for completion: --backend's
// backends (those built in), --integrator's, --sampler's, --aov's, --sample-environment's
// modes; empty for any other option (its value is a number, a file or a name of the scene).
std::vector<std::string> render_option_choices(std::string_view name);

// " (did you mean --samples?)" for the name of a render option of `use` near `given`, else "".
std::string option_suggestion(std::string_view given, unsigned use = use_render);

// --view NAME and --exposure STOPS (args[i] and its value, advancing i) into `display`, the flag
// into `flag`; false, nothing changed, for another argument. UsageError for a bad value.
bool parse_display_option(const std::vector<std::string>& args, size_t& i,
                          DisplayOptions& display, std::string& flag);

// `dacrt render`'s arguments: SCENE and render options, checked (check_request).
RenderRequest parse_render(const std::vector<std::string>& args);

// The checks between options (--samples within --spp, --fps with --frames, ...) and the
// defaults that depend on others (the output named after the scene). `name` spells an option
// for messages: "--spp" → "--spp" for the CLI, "spp=" for Python. Throws UsageError.
using OptionNamer = std::string (*)(std::string_view flag);
void check_request(RenderRequest& r, OptionNamer name = nullptr);

// Throws UsageError for --adaptive-min without --adaptive.
void check_adaptive(const RenderSettings& settings);

// Throws UsageError naming the known integrators unless `name` is one.
void check_integrator(const std::string& name);

// What a render checks before loading anything: the integrator is known, each of `backends` is,
// and every --backend-option is for one of them and taken by it, each backend built once on no
// geometry (UsageError).
void check_render_choices(const RenderRequest& r, const std::vector<std::string>& backends);
// A backend name the registry does not know is a usage error naming the known ones.
void check_backend(const std::string& name);

// An integer in [lo, hi] for `flag`, else UsageError.
long parse_int(const std::string& flag, const std::string& text, long lo, long hi);
// The number the whole text spells (strtod's forms), or nothing.
std::optional<double> parse_real(const std::string& text);
// A positive finite number (seconds, distances) for `flag`, else UsageError.
double parse_seconds(const std::string& flag, const std::string& text);
// Whether `t` is a time an animation is posed at (`--time`, Python's load(time=)): seconds,
// finite, >= 0 and below 1e9.
bool valid_time(double t);

}  // namespace dacrt
