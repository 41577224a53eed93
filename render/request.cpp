// A render request from the command line: the arguments through the option table
// (render_option_table.cpp), the checks between options, and the checks of the choices.
#include "dacrt/render/request.h"

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <optional>

#include "dacrt/io/image_file.h"
#include "dacrt/util/error.h"
#include "dacrt/util/text.h"

namespace fs = std::filesystem;

namespace dacrt {

namespace {

std::string same_name(std::string_view flag) { return std::string(flag); }

}  // namespace

std::optional<double> parse_real(const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0') return std::nullopt;
  return v;
}

long parse_int(const std::string& flag, const std::string& text, long lo, long hi) {
  char* end = nullptr;
  errno = 0;
  long v = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || errno != 0 || v < lo || v > hi)
    throw UsageError(flag + " wants an integer in [" + std::to_string(lo) + ", " +
                     std::to_string(hi) + "], got '" + text + "'");
  return v;
}

bool valid_time(double t) {
  return t >= 0.0 && t < 1e9;
}

double parse_seconds(const std::string& flag, const std::string& text) {
  const std::optional<double> v = parse_real(text);
  if (!v || !(*v > 0.0 && *v < 1e30))
    throw UsageError(flag + " wants a positive number, got '" + text + "'");
  return *v;
}

RenderRequest parse_render(const std::vector<std::string>& given) {
  RenderRequest r;
  std::vector<std::string> args = given;
  const std::vector<std::string> flags = render_flag_names();
  for (size_t i = 0; i < args.size(); ++i) {
    split_option_value(args, i, flags);
    const std::string& a = args[i];
    if (a == "-h" || a == "--help") {
      r.help = true;
      return r;
    } else if (parse_render_option(args, i, r))
      continue;
    else if (!a.empty() && a[0] == '-')
      throw UsageError("unknown option " + a + option_suggestion(a));
    else if (r.scene.empty())
      r.scene = a;
    else
      throw UsageError("unexpected argument '" + a + "' (one scene at a time)");
  }
  if (r.scene.empty()) throw UsageError("render needs a SCENE");
  check_request(r);
  if (r.output.empty()) r.output = fs::path(r.scene).stem().string() + ".exr";
  return r;
}

namespace {

// The outputs' formats by their names (io/image_file.h), and what an image file other than EXR
// cannot hold: the AOV layers and exact sums (refused here, before any work); --view and
// --exposure change only display values (PNG, JPEG).
void check_output_formats(const RenderRequest& r, OptionNamer name) {
  std::optional<ImageFormat> output, preview;
  if (!r.output.empty()) output = output_format(name("-o"), r.output);
  if (!r.preview.empty()) preview = output_format(name("--preview"), r.preview);
  if (output && *output != ImageFormat::exr) {
    const std::string holds = name("-o") + " " + r.output + " is " + format_name(*output) +
                              ", which holds only the image: ";
    if (!r.settings.aovs.empty())
      throw UsageError(holds + name("--aov") +
                       " needs an EXR output (its layers are channels of the EXR)");
    if (r.samples)
      throw UsageError(holds + name("--samples") +
                       " writes a part for dacrt merge, which needs an EXR output (its exact sums)");
    if (r.keep_sums)
      throw UsageError(holds + name("--keep-sums") + " needs an EXR output");
    if (r.resume)
      throw UsageError(holds + name("--resume") +
                       " continues from the exact sums of an EXR output");
  }
  const bool display = (output && holds_display_values(*output)) ||
                       (preview && holds_display_values(*preview)) || !r.report.empty();
  if (!r.display_flag.empty() && !display)
    throw UsageError(name(r.display_flag) + " needs a PNG or JPEG output (" + name("--preview") +
                     " OUT.png, or " + name("-o") +
                     " OUT.png or OUT.jpg): it changes only display values");
}

}  // namespace

void check_request(RenderRequest& r, OptionNamer name) {
  if (!name) name = same_name;
  check_output_formats(r, name);
  if (r.fps_given && !r.frames) throw UsageError(name("--fps") + " needs " + name("--frames"));
  if (r.samples && r.samples->second > uint32_t(r.settings.spp))
    throw UsageError(name("--samples") + " " + std::to_string(r.samples->first) + ":" +
                     std::to_string(r.samples->second) + " goes past " + name("--spp") + " " +
                     std::to_string(r.settings.spp) + " (the render the samples belong to)");
  if (r.samples && r.settings.adaptive > 0)
    throw UsageError(name("--samples") + " and " + name("--adaptive") +
                     ": an adaptive pixel's samples depend on all those before them; render it "
                     "whole");
  if (!r.report.empty() && r.frames)
    throw UsageError(name("--report") + " is for one frame, not " + name("--frames"));
  if (r.resume && r.frames)
    throw UsageError(name("--resume") + " is for one frame, not " + name("--frames"));
  if (r.resume && r.settings.adaptive > 0)
    throw UsageError(name("--resume") + " and " + name("--adaptive") +
                     ": where an adaptive render stopped sampling a pixel depends on its passes; "
                     "render it whole");
  if (r.settings.adaptive_min > 0 && r.settings.adaptive == 0.0)
    throw UsageError(name("--adaptive-min") + " needs " + name("--adaptive"));
  if (r.frames && r.gltf.time)
    throw UsageError(name("--time") + " and " + name("--frames") +
                     " both give the time: use one (a frame's is frame / fps)");
}

void check_adaptive(const RenderSettings& s) {
  if (s.adaptive_min > 0 && s.adaptive == 0.0) throw UsageError("--adaptive-min needs --adaptive");
}

void check_render_choices(const RenderRequest& r, const std::vector<std::string>& backends) {
  check_integrator(r.settings.integrator);
  for (const std::string& name : backends) check_backend(name);
  try {
    r.backend_options.check_prefixes(backends);
    for (const std::string& name : backends)
      Backend::create(name, Geometry{}, r.backend_options.for_plugin(name));
  } catch (const Error& e) {
    throw UsageError(std::string("--backend-option: ") + e.what());
  }
}

void check_backend(const std::string& name) {
  const std::vector<std::string> known = Backend::names();
  if (std::find(known.begin(), known.end(), name) != known.end()) return;
  try {
    Backend::create(name, Geometry{});  // throws the registry's error naming the backends
  } catch (const Error& e) {
    throw UsageError(e.what() + did_you_mean(name, known));
  }
}

void check_integrator(const std::string& name) {
  const std::vector<std::string> integrators = Integrator::names();
  if (std::find(integrators.begin(), integrators.end(), name) != integrators.end()) return;
  std::string names;
  for (const std::string& n : integrators) names += (names.empty() ? "" : ", ") + n;
  throw UsageError("unknown integrator '" + name + "'" + did_you_mean(name, integrators) +
                   " (known: " + names + ")");
}

}  // namespace dacrt
