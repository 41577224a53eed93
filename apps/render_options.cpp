// The render options: one parser for `dacrt render` and `dacrt converge`.
#include "apps/render_options.h"

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <optional>

#include "dacrt/util/error.h"

namespace fs = std::filesystem;

namespace dacrt {

namespace {
// Three comma-separated finite numbers ("1,2.5,-3"), or nothing.
std::optional<glm::vec3> parse_three(const std::string& text) {
  glm::vec3 p;
  std::string rest = text;
  for (int k = 0; k < 3; ++k) {
    const size_t comma = rest.find(',');
    const std::string part = rest.substr(0, comma);
    char* end = nullptr;
    const float v = std::strtof(part.c_str(), &end);
    if (part.empty() || *end != '\0' || !std::isfinite(v) ||
        (k < 2) != (comma != std::string::npos))
      return std::nullopt;
    p[k] = v;
    rest = comma == std::string::npos ? "" : rest.substr(comma + 1);
  }
  return p;
}

glm::vec3 parse_point(const std::string& flag, const std::string& text) {
  if (const auto p = parse_three(text)) return *p;
  throw UsageError(flag + " wants X,Y,Z with three finite numbers, got '" + text + "'");
}

glm::vec3 parse_rgb(const std::string& flag, const std::string& text) {
  const auto c = parse_three(text);
  if (c && c->x >= 0.f && c->y >= 0.f && c->z >= 0.f) return *c;
  throw UsageError(flag + " wants R,G,B with three finite non-negative numbers, got '" + text +
                   "'");
}

}  // namespace

long parse_int(const std::string& flag, const std::string& text, long lo, long hi) {
  char* end = nullptr;
  errno = 0;
  long v = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || errno != 0 || v < lo || v > hi)
    throw UsageError(flag + " wants an integer in [" + std::to_string(lo) + ", " +
                     std::to_string(hi) + "], got '" + text + "'");
  return v;
}

// A positive finite number of seconds (or scene units, for --ao-distance).
// The number the whole text spells (strtod's forms), or nothing.
std::optional<double> parse_real(const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0') return std::nullopt;
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

bool parse_display_option(const std::vector<std::string>& args, size_t& i,
                          DisplayOptions& display, std::string& flag) {
  const std::string& a = args[i];
  auto value = [&]() -> const std::string& {
    if (i + 1 >= args.size()) throw UsageError(a + " needs a value");
    return args[++i];
  };
  if (a == "--view") {
    display.view = value();
    if (display.view.empty()) throw UsageError("--view needs a name (see dacrt views)");
  } else if (a == "--exposure") {
    const std::string v = value();
    const std::optional<double> stops = parse_real(v);
    if (!stops || !std::isfinite(*stops))
      throw UsageError("--exposure wants a finite number of stops, got '" + v + "'");
    display.exposure = *stops;
  } else {
    return false;
  }
  flag = a;
  return true;
}

bool parse_render_option(const std::vector<std::string>& args, size_t& i, RenderArgs& r) {
  const std::string& a = args[i];
  auto value = [&]() -> const std::string& {
    if (i + 1 >= args.size()) throw UsageError(a + " needs a value");
    return args[++i];
  };
  if (a == "-o" || a == "--output")
    r.output = value();
  else if (a == "--preview")
    r.preview = value();
  else if (parse_display_option(args, i, r.display, r.display_flag))
    return true;
  else if (a == "--stats")
    r.stats = value();
  else if (a == "--report")
    r.report = value();
  else if (a == "--spp")
    r.settings.spp = int(parse_int(a, value(), 1, 1 << 20));
  else if (a == "--adaptive") {
    const std::string v = value();
    const std::optional<double> rel = parse_real(v);
    if (!rel || !(*rel > 0.0 && *rel < 1.0))
      throw UsageError("--adaptive wants a relative error in (0, 1), e.g. 0.01, got '" + v + "'");
    r.settings.adaptive = *rel;
  } else if (a == "--adaptive-min")
    r.settings.adaptive_min = int(parse_int(a, value(), 2, 1 << 20));
  else if (a == "--width")
    r.settings.width = int(parse_int(a, value(), 1, max_image_side));
  else if (a == "--height")
    r.settings.height = int(parse_int(a, value(), 1, max_image_side));
  else if (a == "--camera")
    r.settings.camera = int(parse_int(a, value(), 0, 1 << 20));
  else if (a == "--look-from")
    r.settings.camera_override.from = parse_point(a, value());
  else if (a == "--look-at")
    r.settings.camera_override.at = parse_point(a, value());
  else if (a == "--up")
    r.settings.camera_override.up = parse_point(a, value());
  else if (a == "--aov") {
    try {
      r.settings.aovs = AovSet::parse(value());
    } catch (const Error& e) {
      throw UsageError(std::string("--aov: ") + e.what());
    }
  } else if (a == "--pass-spp")
    r.passes.spp_per_pass = uint32_t(parse_int(a, value(), 1, 1 << 20));
  else if (a == "--time-limit")
    r.passes.time_limit = parse_seconds(a, value());
  else if (a == "--checkpoint")
    r.passes.checkpoint = parse_seconds(a, value());
  else if (a == "--ao-distance")
    r.settings.ao_distance = float(parse_seconds(a, value()));
  else if (a == "--fov") {
    const std::string v = value();
    char* end = nullptr;
    const float degrees = std::strtof(v.c_str(), &end);
    if (v.empty() || *end != '\0' || !(degrees > 0.f && degrees < 180.f))
      throw UsageError("--fov wants degrees in (0, 180), got '" + v + "'");
    r.settings.camera_override.fov_degrees = degrees;
  } else if (a == "--variant") {
    r.gltf.variant = value();
    if (r.gltf.variant.empty()) throw UsageError("--variant needs a name (see dacrt info SCENE)");
  } else if (a == "--animation") {
    r.gltf.animation = value();
    if (r.gltf.animation.empty())
      throw UsageError("--animation needs a name, an index or all (see dacrt info SCENE)");
  } else if (a == "--time") {
    const std::string v = value();
    char* end = nullptr;
    const double t = std::strtod(v.c_str(), &end);
    if (v.empty() || *end != '\0' || !valid_time(t))
      throw UsageError("--time wants seconds, a number >= 0, got '" + v + "'");
    r.gltf.time = t;
  } else if (a == "--frames") {
    const std::string v = value();
    const size_t colon = v.find(':');
    if (colon == std::string::npos)
      throw UsageError("--frames wants FIRST:LAST (frame numbers), got '" + v + "'");
    const long first = parse_int(a + " FIRST", v.substr(0, colon), 0, 999999);
    const long last = parse_int(a + " LAST", v.substr(colon + 1), 0, 999999);
    if (last < first)
      throw UsageError("--frames " + v + ": LAST is before FIRST");
    if (last - first >= 100000)
      throw UsageError("--frames " + v + ": more than 100000 frames");
    r.frames = std::pair{int(first), int(last)};
  } else if (a == "--samples") {
    const std::string v = value();
    const size_t colon = v.find(':');
    if (colon == std::string::npos)
      throw UsageError("--samples wants FIRST:LAST (sample indices, LAST excluded), got '" + v + "'");
    const long first = parse_int(a + " FIRST", v.substr(0, colon), 0, 1 << 20);
    const long last = parse_int(a + " LAST", v.substr(colon + 1), 1, 1 << 20);
    if (last <= first) throw UsageError("--samples " + v + ": LAST must be after FIRST");
    r.samples = std::pair{uint32_t(first), uint32_t(last)};
  } else if (a == "--fps") {
    r.fps = parse_seconds(a, value());
    r.fps_given = true;
  } else if (a == "--scene")
    r.gltf.scene = int(parse_int(a, value(), 0, 1 << 20));
  else if (a == "--backend")
    r.backend = value();
  else if (a == "--backend-option") {
    try {
      r.backend_options.parse(value());
    } catch (const Error& e) {
      throw UsageError(std::string("--backend-option: ") + e.what());
    }
  } else if (a == "--integrator")
    r.settings.integrator = value();
  else if (a == "--environment") {
    const std::string v = value();
    const bool exr = v.size() > 4 && (v.compare(v.size() - 4, 4, ".exr") == 0 ||
                                      v.compare(v.size() - 4, 4, ".EXR") == 0);
    if (exr)
      r.settings.environment_file = v, r.settings.environment.reset();
    else
      r.settings.environment = parse_rgb(a, v), r.settings.environment_file.clear();
  } else if (a == "--sample-environment") {
    using Mode = RenderSettings::EnvironmentSampling;
    const std::string v = value();
    if (v == "auto")
      r.settings.sample_environment = Mode::automatic;
    else if (v == "on")
      r.settings.sample_environment = Mode::on;
    else if (v == "off")
      r.settings.sample_environment = Mode::off;
    else
      throw UsageError("--sample-environment wants auto, on or off, not '" + v + "'");
  } else if (a == "--point-light") {
    const std::string v = value();
    const size_t eq = v.find('=');
    PunctualLight light;
    light.name = "--point-light " + v;
    light.position = parse_point(a, v.substr(0, eq));
    if (eq == std::string::npos)
      throw UsageError(a + " wants X,Y,Z=R,G,B (a position and an intensity), got '" + v + "'");
    light.intensity = parse_rgb(a, v.substr(eq + 1));
    r.settings.lights.push_back(light);
  } else if (a == "--max-depth")
    r.settings.max_depth = int(parse_int(a, value(), 0, 1 << 16));
  else if (a == "--sampler") {
    const std::string v = value();
    if (!parse_sampler(v, r.settings.sampler)) {
      std::string names;
      for (const std::string& n : sampler_names()) names += (names.empty() ? "" : ", ") + n;
      throw UsageError("unknown sampler '" + v + "' (known: " + names + ")");
    }
  } else if (a == "--seed")
    r.settings.seed = uint64_t(parse_int(a, value(), 0, LONG_MAX));
  else if (a == "--threads")
    r.threads = int(parse_int(a, value(), 1, 1024));
  else if (a == "--wavefront")
    r.settings.wavefront = size_t(parse_int(a, value(), 1, 1L << 26));
  else if (a == "--quiet")
    r.quiet = true;
  else
    return false;
  return true;
}

RenderArgs parse_render(const std::vector<std::string>& args) {
  RenderArgs r;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "-h" || a == "--help") {
      r.help = true;
      return r;
    } else if (parse_render_option(args, i, r))
      continue;
    else if (a == "--keep-sums")  // about the output file: render's own
      r.keep_sums = true;
    else if (a == "--resume")
      r.resume = true;
    else if (!a.empty() && a[0] == '-')
      throw UsageError("unknown option " + a);
    else if (r.scene.empty())
      r.scene = a;
    else
      throw UsageError("unexpected argument '" + a + "' (one scene at a time)");
  }
  if (r.scene.empty()) throw UsageError("render needs a SCENE");
  if (!r.display_flag.empty() && r.preview.empty())
    throw UsageError(r.display_flag + " needs --preview (it changes only the PNG preview)");
  if (r.output.empty()) r.output = fs::path(r.scene).stem().string() + ".exr";
  if (r.fps_given && !r.frames) throw UsageError("--fps needs --frames");
  if (r.samples && r.samples->second > uint32_t(r.settings.spp))
    throw UsageError("--samples " + std::to_string(r.samples->first) + ":" +
                     std::to_string(r.samples->second) + " goes past --spp " +
                     std::to_string(r.settings.spp) + " (the render the samples belong to)");
  if (r.samples && r.settings.adaptive > 0)
    throw UsageError("--samples and --adaptive: an adaptive pixel's samples depend on all those "
                     "before them; render it whole");
  if (!r.report.empty() && r.frames) throw UsageError("--report is for one frame, not --frames");
  if (r.resume && r.frames) throw UsageError("--resume is for one frame, not --frames");
  if (r.resume && r.settings.adaptive > 0)
    throw UsageError("--resume and --adaptive: where an adaptive render stopped sampling a pixel "
                     "depends on its passes; render it whole");
  check_adaptive(r.settings);
  if (r.frames && r.gltf.time)
    throw UsageError("--time and --frames both give the time: use one (a frame's is frame / fps)");
  return r;
}

void check_adaptive(const RenderSettings& s) {
  if (s.adaptive_min > 0 && s.adaptive == 0.0) throw UsageError("--adaptive-min needs --adaptive");
}

void check_render_choices(const RenderArgs& r, const std::vector<std::string>& backends) {
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
    throw UsageError(e.what());
  }
}

void check_integrator(const std::string& name) {
  const std::vector<std::string> integrators = Integrator::names();
  if (std::find(integrators.begin(), integrators.end(), name) != integrators.end()) return;
  std::string names;
  for (const std::string& n : integrators) names += (names.empty() ? "" : ", ") + n;
  throw UsageError("unknown integrator '" + name + "' (known: " + names + ")");
}

}  // namespace dacrt
