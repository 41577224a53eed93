// The render option table (see request.h): each option's setter and help lines, and the
// parser, --help and lookups made from it.
#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <optional>

#include "dacrt/render/request.h"
#include "dacrt/tracer/backend.h"
#include "dacrt/util/error.h"
#include "dacrt/util/text.h"

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

// FIRST:LAST of `flag` as two integers in [lo, hi] (not yet ordered), or UsageError saying
// `what` the numbers are.
std::pair<long, long> parse_range(const std::string& flag, const std::string& v, long lo,
                                  long first_hi, long last_lo, long hi, const char* what) {
  const size_t colon = v.find(':');
  if (colon == std::string::npos)
    throw UsageError(flag + " wants FIRST:LAST (" + what + "), got '" + v + "'");
  return {parse_int(flag + " FIRST", v.substr(0, colon), lo, first_hi),
          parse_int(flag + " LAST", v.substr(colon + 1), last_lo, hi)};
}

using V = OptionValue;
using R = RenderRequest;
using S = const std::string;

// Each option's setter: the request, the value, the option as the caller spelt it.
void set_output(R& r, S& v, S&) { r.output = v; }
void set_preview(R& r, S& v, S&) { r.preview = v; }
void set_view(R& r, S& v, S& flag) {
  r.display.view = v;
  if (r.display.view.empty()) throw UsageError(flag + " needs a name (see dacrt views)");
  r.display_flag = flag;
}
void set_exposure(R& r, S& v, S& flag) {
  const std::optional<double> stops = parse_real(v);
  if (!stops || !std::isfinite(*stops))
    throw UsageError(flag + " wants a finite number of stops, got '" + v + "'");
  r.display.exposure = *stops;
  r.display_flag = flag;
}
void set_stats(R& r, S& v, S&) { r.stats = v; }
void set_report(R& r, S& v, S&) { r.report = v; }
void set_aovs(R& r, S& v, S& flag) {
  try {
    r.settings.aovs = AovSet::parse(v);
  } catch (const Error& e) {
    throw UsageError(flag + ": " + e.what());
  }
}
void set_pass_spp(R& r, S& v, S& flag) {
  r.passes.spp_per_pass = uint32_t(parse_int(flag, v, 1, 1 << 20));
}
void set_time_limit(R& r, S& v, S& flag) { r.passes.time_limit = parse_seconds(flag, v); }
void set_checkpoint(R& r, S& v, S& flag) { r.passes.checkpoint = parse_seconds(flag, v); }
void set_width(R& r, S& v, S& flag) { r.settings.width = int(parse_int(flag, v, 1, max_image_side)); }
void set_height(R& r, S& v, S& flag) {
  r.settings.height = int(parse_int(flag, v, 1, max_image_side));
}
void set_spp(R& r, S& v, S& flag) { r.settings.spp = int(parse_int(flag, v, 1, 1 << 20)); }
void set_samples(R& r, S& v, S& flag) {
  const auto [first, last] =
      parse_range(flag, v, 0, 1 << 20, 1, 1 << 20, "sample indices, LAST excluded");
  if (last <= first) throw UsageError(flag + " " + v + ": LAST must be after FIRST");
  r.samples = std::pair{uint32_t(first), uint32_t(last)};
}
void set_keep_sums(R& r, S&, S&) { r.keep_sums = true; }
void set_resume(R& r, S&, S&) { r.resume = true; }
void set_adaptive(R& r, S& v, S& flag) {
  const std::optional<double> rel = parse_real(v);
  if (!rel || !(*rel > 0.0 && *rel < 1.0))
    throw UsageError(flag + " wants a relative error in (0, 1), e.g. 0.01, got '" + v + "'");
  r.settings.adaptive = *rel;
}
void set_adaptive_min(R& r, S& v, S& flag) {
  r.settings.adaptive_min = int(parse_int(flag, v, 2, 1 << 20));
}
void set_camera(R& r, S& v, S& flag) { r.settings.camera = int(parse_int(flag, v, 0, 1 << 20)); }
void set_look_from(R& r, S& v, S& flag) { r.settings.camera_override.from = parse_point(flag, v); }
void set_look_at(R& r, S& v, S& flag) { r.settings.camera_override.at = parse_point(flag, v); }
void set_up(R& r, S& v, S& flag) { r.settings.camera_override.up = parse_point(flag, v); }
void set_fov(R& r, S& v, S& flag) {
  char* end = nullptr;
  const float degrees = std::strtof(v.c_str(), &end);
  if (v.empty() || *end != '\0' || !(degrees > 0.f && degrees < 180.f))
    throw UsageError(flag + " wants degrees in (0, 180), got '" + v + "'");
  r.settings.camera_override.fov_degrees = degrees;
}
// `other` ("--fstop") as `flag` spells options: "--fstop" on the command line, "fstop=" for
// Python's keywords and converge's configurations.
std::string spelt_like(S& flag, const std::string& other) {
  if (flag.compare(0, 2, "--") == 0) return other;
  std::string key = other.substr(2);
  std::replace(key.begin(), key.end(), '-', '_');
  return key + "=";
}
// A length for a lens option: a finite number (as a float) in [0, inf), > 0 unless zero_ok.
float parse_length(S& flag, S& v, bool zero_ok, const char* what) {
  const std::optional<double> x = parse_real(v);
  if (!x || !std::isfinite(float(*x)) || !(zero_ok ? *x >= 0.0 : *x > 0.0))
    throw UsageError(flag + " wants " + what + ", got '" + v + "'");
  return float(*x);
}
// Two options that give one thing (the aperture, the focus): the second one given is refused.
void one_of(bool other_given, S& flag, const char* other, const char* what) {
  if (other_given)
    throw UsageError(flag + " and " + spelt_like(flag, other) + " both give the " + what +
                     ": use one");
}
void set_aperture(R& r, S& v, S& flag) {
  one_of(bool(r.settings.lens.fstop), flag, "--fstop", "aperture");
  r.settings.lens.aperture =
      parse_length(flag, v, true, "the lens's diameter, a finite number >= 0 (0: a pinhole)");
}
void set_fstop(R& r, S& v, S& flag) {
  one_of(bool(r.settings.lens.aperture), flag, "--aperture", "aperture");
  r.settings.lens.fstop = parse_length(flag, v, false, "an f-number, a finite number > 0");
}
void set_focus_distance(R& r, S& v, S& flag) {
  one_of(bool(r.settings.lens.focus_on), flag, "--focus-on", "focus");
  r.settings.lens.focus_distance =
      parse_length(flag, v, false, "a distance, a finite number > 0");
}
void set_focus_on(R& r, S& v, S& flag) {
  one_of(bool(r.settings.lens.focus_distance), flag, "--focus-distance", "focus");
  r.settings.lens.focus_on = parse_point(flag, v);
}
void set_scene(R& r, S& v, S& flag) { r.gltf.scene = int(parse_int(flag, v, 0, 1 << 20)); }
void set_variant(R& r, S& v, S& flag) {
  r.gltf.variant = v;
  if (v.empty()) throw UsageError(flag + " needs a name (see dacrt info SCENE)");
}
void set_time(R& r, S& v, S& flag) {
  char* end = nullptr;
  const double t = std::strtod(v.c_str(), &end);
  if (v.empty() || *end != '\0' || !valid_time(t))
    throw UsageError(flag + " wants seconds, a number >= 0, got '" + v + "'");
  r.gltf.time = t;
}
void set_animation(R& r, S& v, S& flag) {
  r.gltf.animation = v;
  if (v.empty())
    throw UsageError(flag + " needs a name, an index or all (see dacrt info SCENE)");
}
void set_frames(R& r, S& v, S& flag) {
  const auto [first, last] = parse_range(flag, v, 0, 999999, 0, 999999, "frame numbers");
  if (last < first) throw UsageError(flag + " " + v + ": LAST is before FIRST");
  if (last - first >= 100000) throw UsageError(flag + " " + v + ": more than 100000 frames");
  r.frames = std::pair{int(first), int(last)};
}
void set_fps(R& r, S& v, S& flag) {
  r.fps = parse_seconds(flag, v);
  r.fps_given = true;
}
void set_integrator(R& r, S& v, S&) { r.settings.integrator = v; }
void set_ao_distance(R& r, S& v, S& flag) { r.settings.ao_distance = float(parse_seconds(flag, v)); }
void set_max_depth(R& r, S& v, S& flag) {
  r.settings.max_depth = int(parse_int(flag, v, 0, 1 << 16));
}
void add_point_light(R& r, S& v, S& flag) {
  const size_t eq = v.find('=');
  PunctualLight light;
  light.name = "--point-light " + v;
  light.position = parse_point(flag, v.substr(0, eq));
  if (eq == std::string::npos)
    throw UsageError(flag + " wants X,Y,Z=R,G,B (a position and an intensity), got '" + v + "'");
  light.intensity = parse_rgb(flag, v.substr(eq + 1));
  r.settings.lights.push_back(light);
}
void set_environment(R& r, S& v, S& flag) {
  const bool exr = v.size() > 4 && (v.compare(v.size() - 4, 4, ".exr") == 0 ||
                                    v.compare(v.size() - 4, 4, ".EXR") == 0);
  if (exr)
    r.settings.environment_file = v, r.settings.environment.reset();
  else
    r.settings.environment = parse_rgb(flag, v), r.settings.environment_file.clear();
}
// --sample-environment's modes.
const std::vector<std::string> environment_modes = {"auto", "on", "off"};

void set_sample_environment(R& r, S& v, S& flag) {
  using Mode = RenderSettings::EnvironmentSampling;
  if (v == "auto")
    r.settings.sample_environment = Mode::automatic;
  else if (v == "on")
    r.settings.sample_environment = Mode::on;
  else if (v == "off")
    r.settings.sample_environment = Mode::off;
  else
    throw UsageError(flag + " wants auto, on or off, not '" + v + "'" +
                     did_you_mean(v, environment_modes));
}
// --light-sampler's modes.
const std::vector<std::string> light_sampler_modes = {"auto", "tree", "power"};

void set_light_sampler(R& r, S& v, S& flag) {
  if (v == "auto")
    r.settings.light_sampler = LightPicking::automatic;
  else if (v == "tree")
    r.settings.light_sampler = LightPicking::tree;
  else if (v == "power")
    r.settings.light_sampler = LightPicking::power;
  else
    throw UsageError(flag + " wants auto, tree or power, not '" + v + "'" +
                     did_you_mean(v, light_sampler_modes));
}
void set_seed(R& r, S& v, S& flag) { r.settings.seed = uint64_t(parse_int(flag, v, 0, LONG_MAX)); }
void set_sampler(R& r, S& v, S&) {
  if (parse_sampler(v, r.settings.sampler)) return;
  std::string names;
  for (const std::string& n : sampler_names()) names += (names.empty() ? "" : ", ") + n;
  throw UsageError("unknown sampler '" + v + "'" + did_you_mean(v, sampler_names()) +
                   " (known: " + names + ")");
}
void set_backend(R& r, S& v, S&) { r.backend = v; }
void add_backend_option(R& r, S& v, S& flag) {
  try {
    r.backend_options.parse(v);
  } catch (const Error& e) {
    throw UsageError(flag + ": " + e.what());
  }
}
void set_wavefront(R& r, S& v, S& flag) {
  r.settings.wavefront = size_t(parse_int(flag, v, 1, 1L << 26));
}
void set_threads(R& r, S& v, S& flag) { r.threads = int(parse_int(flag, v, 1, 1024)); }
void set_quiet(R& r, S&, S&) { r.quiet = true; }
void set_help(R& r, S&, S&) { r.help = true; }

// The table. An option's help lines begin with its column ("  --spp N   ..."), continued lines
// indented to the text's column; sections are printed in the order they first appear.
const RenderOption table[] = {
    {"--output", "Output", V::path, use_render, false,
     R"h(  -o, --output OUT.exr       the image, in the format its extension says (any case): .exr float
                             RGB, scene-linear Rec.709, with the AOVs and exact sums (default:
                             SCENE's name .exr); .hdr Radiance RGBE, scene-linear; .png 8-bit or
                             .jpg/.jpeg through the display view, as --preview. Only an EXR holds
                             --aov, --samples, --keep-sums and --resume
)h",
     set_output, "-o"},
    {"--preview", "Output", V::path, use_render, false,
     R"h(  --preview OUT.png          also the image alone: .png or .jpg/.jpeg, 8-bit through an
                             OpenColorIO display view ($OCIO if set); .hdr or .exr scene-linear
)h",
     set_preview},
    {"--view", "Output", V::text, use_render, false,
     R"h(  --view NAME                the preview's display view (default sRGB, or $OCIO's default view);
                             `dacrt views` lists them, e.g. "ACES 1.0 SDR-video (sRGB)" (tone
                             mapped), or with $OCIO "DISPLAY/VIEW". Needs a PNG or JPEG output
)h",
     set_view},
    {"--exposure", "Output", V::number, use_render, false,
     R"h(  --exposure STOPS           scales the scene-linear values by 2^STOPS before the view (default
                             0; an EXR or HDR is not changed). Needs a PNG or JPEG output
)h",
     set_exposure},
    {"--stats", "Output", V::path, use_render, false,
     R"h(  --stats OUT.json           render statistics: time and rays/s per ray type and bounce
)h",
     set_stats},
    {"--report", "Output", V::path, use_render, false,
     R"h(  --report DIR               also DIR/index.html: one self-contained page with the backends'
                             images side by side (DIR/NAME.png), their rays per second per ray
                             type and bounce, the batch sizes and the comparison table
)h",
     set_report},
    {"--aov", "Output", V::names, use_render | use_python, false,
     R"h(  --aov LIST                 more layers in the EXR, comma-separated: albedo (albedo.R/G/B), normal
                             (N.X/Y/Z), depth (Z, along the view axis; 1e10 where nothing was hit),
                             position (P.X/Y/Z), variance (variance.R/G/B: of each pixel's mean),
                             samples (samples.X: the per-pixel count)
)h",
     set_aovs, "", "aovs"},
    {"--pass-spp", "Progress", V::integer, use_render | use_converge | use_config | use_python, false,
     R"h(  --pass-spp N               samples per pixel in each pass (default: 8 wavefronts' worth)
)h",
     set_pass_spp},
    {"--time-limit", "Progress", V::number, use_render | use_python, false,
     R"h(  --time-limit SECONDS       stop each render (frame, backend) after the pass that crosses it,
                             the passes sized to end near it (the header says the spp done)
)h",
     set_time_limit},
    {"--checkpoint", "Progress", V::number, use_render, false,
     R"h(  --checkpoint SECONDS       rewrite the outputs after passes, at most this often
                             SIGINT or SIGTERM: stop at the next wavefront, finish the paths in
                             flight and write the outputs (exit 130 or 143); a second one ends at once
)h",
     set_checkpoint},
    {"--width", "Image", V::integer, use_render | use_converge | use_python, false,
     R"h(  --width W, --height H      resolution (default 512 × 512, or the camera's aspect ratio)
)h",
     set_width},
    {"--height", "Image", V::integer, use_render | use_converge | use_python, false,
     "",
     set_height},
    {"--spp", "Image", V::integer, use_render | use_python, false,
     R"h(  --spp N                    samples per pixel (default 64)
)h",
     set_spp},
    {"--samples", "Image", V::range, use_render | use_python, false,
     R"h(  --samples FIRST:LAST       only sample indices [FIRST, LAST) of every pixel of the --spp
                             render (its numbers are the whole render's: the header's sampleRange
                             says which; not with --adaptive). The EXR keeps the exact sums of its
                             samples: `dacrt merge` adds such parts into the whole render, bit
                             for bit
)h",
     set_samples},
    {"--keep-sums", "Image", V::none, use_render, false,
     R"h(  --keep-sums                keep the exact sums in a complete render's EXR too (a render cut
                             short by a stop or --time-limit, and its checkpoints, always keep them)
)h",
     set_keep_sums},
    {"--resume", "Image", V::none, use_render, false,
     R"h(  --resume                   continue the render the -o file holds (same scene and settings, its
                             exact sums kept) up to --spp, or its --samples range; the image is
                             the uninterrupted render's bit for bit. Without the file: from the start
)h",
     set_resume},
    {"--adaptive", "Image", V::number, use_render | use_converge | use_config | use_python, false,
     R"h(  --adaptive REL             adaptive sampling (default off): after the minimum, a pixel stops
                             taking samples once the relative error of its mean, and of its 3×3
                             neighbours' means, is below REL (in (0, 1), e.g. 0.01); the others go
                             on to --spp. The samples channel and the header say what each got
)h",
     set_adaptive},
    {"--adaptive-min", "Image", V::integer, use_render | use_converge | use_config | use_python, false,
     R"h(  --adaptive-min N           with --adaptive: the samples every pixel takes first (default
                             max(16, spp / 16))
)h",
     set_adaptive_min},
    {"--camera", "Image", V::integer, use_render | use_converge | use_python, false,
     R"h(  --camera INDEX             which of the scene's cameras (default 0; without one, the scene is framed)
)h",
     set_camera},
    {"--look-from", "Image", V::point, use_render | use_converge | use_python, false,
     R"h(  --look-from X,Y,Z          the camera's position (overrides the chosen camera; without --look-at
                             it looks at the scene's centre); `dacrt info` prints each camera so
)h",
     set_look_from},
    {"--look-at", "Image", V::point, use_render | use_converge | use_python, false,
     R"h(  --look-at X,Y,Z            a point it looks at (default: along the chosen camera's view)
)h",
     set_look_at},
    {"--up", "Image", V::point, use_render | use_converge | use_python, false,
     R"h(  --up X,Y,Z                 its up direction (default: the chosen camera's, +Y when framed)
)h",
     set_up},
    {"--fov", "Image", V::number, use_render | use_converge | use_python, false,
     R"h(  --fov DEGREES              its vertical field of view (default: the chosen camera's)
)h",
     set_fov},
    {"--aperture", "Image", V::number, use_render | use_converge | use_python, false,
     R"h(  --aperture D               depth of field: a thin lens of diameter D in scene units (glTF:
                             metres) in place of the pinhole (default 0: a pinhole, all sharp);
                             orthographic cameras too
)h",
     set_aperture},
    {"--fstop", "Image", V::number, use_render | use_converge | use_python, false,
     R"h(  --fstop N                  or the aperture as an f-number: diameter = focal length / N, the
                             focal length a 36×24 mm sensor (its long side along the image's
                             longer side) needs for the vertical field of view, in metres
)h",
     set_fstop},
    {"--focus-distance", "Image", V::number, use_render | use_converge | use_python, false,
     R"h(  --focus-distance D         the depth in focus, along the view axis (default: the --look-at
                             point, else the first surface at the image's centre, else the
                             scene's centre; the render says which)
)h",
     set_focus_distance},
    {"--focus-on", "Image", V::point, use_render | use_converge | use_python, false,
     R"h(  --focus-on X,Y,Z           or focus on a point: the plane through it across the view is sharp
)h",
     set_focus_on},
    {"--scene", "Image", V::integer, use_render | use_converge, false,
     R"h(  --scene INDEX              which of the file's scenes (default: the file's default scene)
)h",
     set_scene},
    {"--variant", "Image", V::text, use_render | use_converge | use_python, false,
     R"h(  --variant NAME             the KHR_materials_variants variant to render (dacrt info lists them)
)h",
     set_variant},
    {"--time", "Animation", V::number, use_render | use_converge | use_config | use_python, false,
     R"h(  --time SECONDS             evaluate the file's animations at this time (default: the rest pose,
                             nodes and morph weights as the file gives them)
)h",
     set_time},
    {"--animation", "Animation", V::name_or_index, use_render | use_converge | use_config | use_python, false,
     R"h(  --animation NAME|INDEX|all which of the file's animations play (default: the first, index 0;
                             all: every one at once); `dacrt info` lists them
)h",
     set_animation},
    {"--frames", "Animation", V::range, use_render, false,
     R"h(  --frames FIRST:LAST        render frames FIRST..LAST, frame f at time f / fps, to OUT.%04d.exr
                             (and PREVIEW.%04d.png); each frame's geometry is made anew from the
                             file decoded once, and the time that takes and each backend's build
                             time are printed (and written to --stats)
)h",
     set_frames},
    {"--fps", "Animation", V::number, use_render, false,
     R"h(  --fps F                    frames per second for --frames (default 24)
)h",
     set_fps},
    {"--integrator", "Light transport", V::text, use_render | use_converge | use_config | use_python, false,
     R"h(  --integrator NAME          path (default: path tracing), direct (direct lighting, NEE + MIS,
                             one scattering event), ao (ambient occlusion), albedo, normal, depth
                             (the first hit's values as the image)
)h",
     set_integrator},
    {"--ao-distance", "Light transport", V::number, use_render | use_converge | use_config | use_python, false,
     R"h(  --ao-distance D            ao: how far occluders count (default: the scene's diagonal)
)h",
     set_ao_distance},
    {"--max-depth", "Light transport", V::integer, use_render | use_converge | use_config | use_python, false,
     R"h(  --max-depth D              scattering events per path (default 64; Russian roulette after 3)
)h",
     set_max_depth},
    {"--point-light", "Light transport", V::text, use_render | use_converge | use_python, true,
     R"h(  --point-light X,Y,Z=R,G,B  adds a point light at X,Y,Z of intensity R,G,B (irradiance I / d², the
                             units of KHR_lights_punctual's intensity as dacrt reads it); repeatable:
                             interiors without emitters (McGuire's conference room) can be lit
)h",
     add_point_light},
    {"--environment", "Light transport", V::colour_or_file, use_render | use_converge | use_python, false,
     R"h(  --environment R,G,B        uniform environment radiance (default: a sky of 1
                             unless the scene's lamps light it; `dacrt info` says which)
  --environment FILE.exr     an equirectangular environment map (+Y up, image centre towards -Z),
                             importance-sampled
)h",
     set_environment},
    {"--sample-environment", "Light transport", V::text, use_render | use_converge | use_config | use_python, false,
     R"h(  --sample-environment MODE  next-event estimation of a uniform environment, with MIS: auto
                             (default: with other lights, where a pilot finds a quarter of bounce
                             rays escaping), on, off
)h",
     set_sample_environment},
    {"--light-sampler", "Light transport", V::text, use_render | use_converge | use_config | use_python, false,
     R"h(  --light-sampler MODE       how next-event estimation picks an emitter: auto (default: a
                             light tree from 8 emitters on where no environment is sampled,
                             else by power), tree, power
)h",
     set_light_sampler},
    {"--seed", "Light transport", V::integer, use_render | use_converge | use_config | use_python, false,
     R"h(  --seed S                   random seed (default 0)
)h",
     set_seed},
    {"--sampler", "Light transport", V::text, use_render | use_converge | use_config | use_python, false,
     R"h(  --sampler NAME             sobol (default: Owen-scrambled Sobol, stratified in each pair of
                             dimensions), independent (a hash per number: white noise)
)h",
     set_sampler},
    {"--backend", "Ray tracing", V::names, use_render | use_converge | use_config | use_python, false,
     R"h(  --backend NAME[,NAME...]   dacrt (default), dacrt-naive, embree, brute; several: each renders
                             with the same seed to OUT.NAME.exr, then a table compares them
                             (rays, seconds and Mrays/s per ray type and bounce, kernel counters,
                             batch sizes, whole render times with the build, ratios) on stdout
)h",
     set_backend},
    {"--backend-option", "Ray tracing", V::text, use_render | use_converge | use_config | use_python, true,
     R"h(  --backend-option [NAME.]KEY=VALUE
                             backend setting, repeatable; NAME. for one backend of several (dacrt: bins, leaf_rays, leaf_work, leaf_triangles,
                             max_leaf_triangles, sample_size, sample_threshold, small_nodes, filter_skip,
                             cost_traversal, cost_intersect, simd, task_rays, chunks, seed,
                             max_depth, top_triangles, leaf_lanes, group_rays, walk_rays);
                             embree: quality, robust; every backend: frames=refit|rebuild|new,
                             how --frames hands it each frame's geometry
)h",
     add_backend_option},
    {"--wavefront", "Ray tracing", V::integer, use_render | use_converge | use_config | use_python, false,
     R"h(  --wavefront N              live paths at most (default: what 96 MiB of path state holds,
                             about 286 000, or the frame's paths if fewer)
)h",
     set_wavefront},
    {"--threads", "Ray tracing", V::integer, use_render | use_converge | use_config | use_python, false,
     R"h(  --threads T                worker threads (default: all cores)
)h",
     set_threads},
    {"--quiet", "Other", V::none, use_render | use_converge, false,
     R"h(  --quiet                    no progress bar or summary on stderr
)h",
     set_quiet},
    {"--help", "Other", V::none, use_render, false,
     R"h(  -h, --help                 this text
)h",
     set_help, "-h"},
};

constexpr const char* help_head = "Usage: dacrt render SCENE [options]\n";
constexpr const char* help_tail = R"help(
Under mpirun (`mpirun -np R dacrt render SCENE ...`) the ranks split the samples of every pixel
and rank 0 writes the image, bit for bit one process's; progress and errors come from rank 0, a
rank that fails fails the job. As root OpenMPI wants --allow-run-as-root, more ranks than cores
--oversubscribe; with 2 ranks or fewer it binds each to one core, so give --bind-to none (or
--map-by node:PE=T) when ranks use several threads. Not with --frames, several backends,
--resume, --time-limit, --checkpoint or --adaptive.
)help";

}  // namespace

std::string RenderOption::python_keyword() const {
  std::string k(keyword.empty() ? name.substr(2) : keyword);
  std::replace(k.begin(), k.end(), '-', '_');
  return k;
}

std::span<const RenderOption> render_options() { return table; }

const RenderOption* find_render_option(std::string_view name) {
  for (const RenderOption& o : table)
    if (o.name == name || (!o.short_name.empty() && o.short_name == name)) return &o;
  return nullptr;
}

std::string render_help() {
  std::string text = help_head;
  std::string section;
  for (const RenderOption& o : table) {
    if (o.section != section) {
      section = o.section;
      text += (text == help_head ? "\n" : "") + section + "\n";
    }
    text += o.help;
  }
  return text + help_tail;
}

bool parse_display_option(const std::vector<std::string>& args, size_t& i,
                          DisplayOptions& display, std::string& flag) {
  const std::string& a = args[i];
  if (a != "--view" && a != "--exposure") return false;
  if (i + 1 >= args.size()) throw UsageError(a + " needs a value");
  RenderRequest r;
  r.display = display;
  (a == "--view" ? set_view : set_exposure)(r, args[i + 1], a);
  ++i;
  display = r.display;
  flag = a;
  return true;
}

void split_option_value(std::vector<std::string>& args, size_t i,
                        const std::vector<std::string>& flags) {
  const std::string a = args[i];
  const size_t eq = a.find('=');
  if (a.size() < 3 || a.compare(0, 2, "--") != 0 || eq == std::string::npos) return;
  const std::string name = a.substr(0, eq);
  if (std::find(flags.begin(), flags.end(), name) != flags.end())
    throw UsageError(name + " takes no value");
  args[i] = name;
  args.insert(args.begin() + std::ptrdiff_t(i) + 1, a.substr(eq + 1));
}

std::vector<std::string> render_flag_names() {
  std::vector<std::string> flags;
  for (const RenderOption& o : table)
    if (o.value == OptionValue::none) flags.emplace_back(o.name);
  return flags;
}

std::vector<std::string> render_option_choices(std::string_view name) {
  if (name == "--backend") return Backend::names();
  if (name == "--integrator") return Integrator::names();
  if (name == "--sampler") return sampler_names();
  if (name == "--sample-environment") return environment_modes;
  if (name == "--light-sampler") return light_sampler_modes;
  std::vector<std::string> names;
  if (name == "--aov")
    for (int a = 0; a < aov_count; ++a) names.emplace_back(AovSet::name(Aov(a)));
  return names;
}

std::string option_suggestion(std::string_view given, unsigned use) {
  std::vector<std::string> names;
  for (const RenderOption& o : table)
    if (o.uses & use) names.emplace_back(o.name);
  return did_you_mean(given, names);
}

bool parse_render_option(const std::vector<std::string>& args, size_t& i, RenderRequest& r,
                         unsigned use) {
  const std::string& a = args[i];
  const RenderOption* o = find_render_option(a);
  if (!o || !(o->uses & use) || o->name == "--help") return false;
  if (o->value == OptionValue::none) {
    o->apply(r, "", a);
    return true;
  }
  if (i + 1 >= args.size()) throw UsageError(a + " needs a value");
  o->apply(r, args[i + 1], a);
  ++i;
  return true;
}

}  // namespace dacrt
