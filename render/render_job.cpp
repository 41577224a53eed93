#include "dacrt/render/render_job.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "dacrt/io/exr.h"
#include "dacrt/tracer/ray.h"
#include "dacrt/tracer/triangle.h"
#include "dacrt/util/error.h"

#ifndef DACRT_VERSION
#define DACRT_VERSION "unknown"
#endif

namespace dacrt {

namespace {
using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}
}  // namespace

const char* version() {
  return DACRT_VERSION;
}

namespace {
// What of the scene emits: emissive triangles, and the brightest emitter's radiance.
struct Emitters {
  size_t triangles = 0, bright = 0;  // bright: radiance above 1 in some channel
  float most = 0.f;                  // the largest channel of any emitter's radiance
};
Emitters count_emitters(const Scene& scene) {
  Emitters e;
  for (uint32_t m : scene.geometry.material) {
    const Material& material = scene.materials[m];
    if (!material.emitter()) continue;
    const float top = std::max({material.emission.x, material.emission.y, material.emission.z});
    ++e.triangles;
    if (top > 1.f) ++e.bright;
    e.most = std::max(e.most, top);
  }
  return e;
}

std::string count_text(size_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

// The depth of the plane in focus when a lens is asked for without a focus: the point looked at
// (--look-at), else the first surface at the image's centre (every triangle, alpha masks taken
// as opaque), else the scene's centre (the framing target). `notes` says which, and the value.
float default_focus(const Scene& scene, const RenderSettings& s, const Camera& cam, int width,
                    int height, std::vector<std::string>& notes) {
  const glm::vec3 forward = -glm::vec3(cam.to_world[2]);
  auto depth_of = [&](const glm::vec3& p) {
    return float(glm::dot(glm::dvec3(p) - glm::dvec3(cam.position()), glm::dvec3(forward)));
  };
  float depth = 0.f;
  std::string why;
  if (s.camera_override.at) {
    depth = depth_of(*s.camera_override.at);
    why = "the --look-at point";
  }
  if (!(depth > 0.f)) {
    glm::vec3 o, d;
    const float tmin =
        CameraProjection(cam, width, height).ray(0.5f * width, 0.5f * height, o, d);
    const Ray ray = Ray::shear(o, d);
    float t = INFINITY;
    for (size_t tri = 0; tri < scene.geometry.size(); ++tri) {
      TriangleHit h;
      if (intersect_triangle(ray, scene.geometry.vertex(tri, 0), scene.geometry.vertex(tri, 1),
                             scene.geometry.vertex(tri, 2), tmin, t, h))
        t = h.t;
    }
    if (t < INFINITY) {
      depth = t * glm::dot(d, forward);
      why = "the first surface at the image's centre";
    }
  }
  if (!(depth > 0.f && std::isfinite(depth))) {
    const Box b = scene.framing_bounds();
    const glm::vec3 centre = b.empty() ? glm::vec3(0.f) : b.center();
    depth = depth_of(centre);
    why = "the scene's centre";
    if (!(depth > 0.f && std::isfinite(depth))) depth = 1.f, why = "a default: nothing is ahead";
  }
  char number[32];
  std::snprintf(number, sizeof number, "%g", double(depth));
  notes.push_back(scene.path + ": focus at depth " + number + ", " + why +
                  " (--focus-distance or --focus-on to choose)");
  return depth;
}
}  // namespace

DefaultLighting default_lighting(const Scene& scene, size_t added_lights) {
  const Emitters e = count_emitters(scene);
  char most[32];
  std::snprintf(most, sizeof most, "%g", double(e.most));
  const std::string punctual =
      scene.lights.empty() ? ""
                           : count_text(scene.lights.size(), "punctual light", "punctual lights");
  DefaultLighting d;
  if (added_lights > 0 || e.bright > 0) {
    std::vector<std::string> parts;
    if (added_lights > 0) parts.push_back(count_text(added_lights, "--point-light", "--point-lights"));
    if (e.triangles > 0)
      parts.push_back(count_text(e.triangles, "emissive triangle", "emissive triangles") +
                      " (radiance up to " + most + ")");
    if (!punctual.empty()) parts.push_back(punctual);
    d.what = "its own: ";
    for (size_t i = 0; i < parts.size(); ++i)
      d.what += (i == 0 ? "" : i + 1 == parts.size() ? " and " : ", ") + parts[i];
    d.what += "; --environment 1,1,1 adds a sky";
    return d;
  }
  d.sky = true;
  d.what = "a uniform sky of 1";
  if (!punctual.empty()) d.what += ", beside " + punctual;
  if (e.triangles > 0)
    d.what += std::string(punctual.empty() ? ", beside " : " and ") +
              count_text(e.triangles, "emissive triangle", "emissive triangles") +
              " no brighter than it (radiance up to " + most +
              ": they glow, they do not light the scene)";
  d.what += punctual.empty() && e.triangles == 0 ? " (the scene has no emitters and no lights)"
                                                 : "; --environment 0,0,0 takes the sky away";
  return d;
}

std::string dark_image_note(const Image& image, const Shot& shot, double exposure,
                            const std::string& output) {
  const size_t pixels = size_t(image.width) * size_t(image.height);
  if (pixels == 0) return {};
  const double scale = std::exp2(exposure);
  size_t dark = 0;
  double sum = 0.0;
  for (size_t p = 0; p < pixels; ++p) {
    const float* c = &image.rgb[3 * p];
    const double y = scale * (0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]);
    if (!(y >= 0.002)) ++dark;  // NaN counts as dark
    if (std::isfinite(y)) sum += y;
  }
  if (double(dark) < 0.97 * double(pixels)) return {};
  const bool lit_by_sky = shot.environment_map || shot.environment != glm::vec3(0.f);
  char line[96];
  std::snprintf(line, sizeof line, ": the image is nearly black (%.1f %% of its pixels, mean %.2g)",
                100.0 * double(dark) / double(pixels), sum / double(pixels));
  return output + line +
         (lit_by_sky ? ": --exposure STOPS brightens its preview"
                     : ": no sky lights it; --environment 1,1,1 adds one, "
                       "--exposure STOPS brightens its preview");
}

Shot make_shot(const Scene& scene, const RenderSettings& s) {
  if (s.camera < 0 || size_t(s.camera) >= scene.cameras.size())
    throw Error(scene.path + ": camera " + std::to_string(s.camera) +
                " does not exist (the scene has " + std::to_string(scene.cameras_from_file) + ")");
  Shot shot;
  shot.camera_index = s.camera;
  shot.camera = scene.cameras[size_t(s.camera)];
  if (s.camera_override.any()) {
    const Box b = scene.framing_bounds();
    shot.camera = override_camera(shot.camera, s.camera_override,
                                  b.empty() ? glm::vec3(0.f) : b.center());
  }
  const glm::ivec2 size = image_size(shot.camera.aspect, s.width, s.height, s.longer_side,
                                     scene.path + ": camera " + std::to_string(s.camera));
  shot.width = size.x, shot.height = size.y;
  if (s.lens.any()) {
    const LensRequest& lens = s.lens;
    const bool focus_needed = (lens.fstop || lens.aperture.value_or(0.f) > 0.f) &&
                              !lens.focus_distance && !lens.focus_on;
    const float focus = focus_needed ? default_focus(scene, s, shot.camera, shot.width,
                                                     shot.height, shot.notes)
                                     : 1.f;
    shot.camera = lens_camera(shot.camera, lens, float(shot.width) / float(shot.height), focus,
                              shot.notes);
  }
  shot.lights = scene.lights;
  shot.lights.insert(shot.lights.end(), s.lights.begin(), s.lights.end());
  if (s.environment_map) {
    shot.environment_map = s.environment_map;
  } else if (!s.environment_file.empty()) {
    shot.environment_map =
        std::make_shared<const EnvironmentMap>(read_exr(s.environment_file), s.environment_file);
  } else if (s.environment) {
    shot.environment = *s.environment;
  } else if (const DefaultLighting lighting = default_lighting(scene, s.lights.size()); lighting.sky) {
    shot.environment = glm::vec3(1.f);
    shot.notes.push_back(scene.path + ": lighting it with " + lighting.what);
  }
  if (scene.cameras_from_file == 0)
    shot.notes.push_back(scene.path + ": no camera in the file: framing the scene's bounds");
  return shot;
}

RenderMemory render_memory(const Shot& shot, const RenderSettings& s, bool preview) {
  const uint64_t pixels = shot.pixels();
  // The resolved channels (4 bytes each, the samples channel always counted), and the preview's
  // 8-bit RGB with its float copy.
  const AovSet a = s.aovs;
  const uint64_t channels = uint64_t(Film::channel_count(a));
  RenderMemory m;
  m.image = Film::bytes(shot.width, shot.height, a) + pixels * (4 * channels + (preview ? 15 : 0));
  m.paths = resolve_wavefront(s, pixels * uint64_t(s.spp)) * path_bytes(a);
  return m;
}

RenderJob::RenderJob(const Scene& scene, Backend& backend, RenderSettings settings)
    : RenderJob(scene, backend, settings, make_shot(scene, settings)) {}

RenderJob::RenderJob(const Scene& scene, Backend& backend, RenderSettings settings, Shot shot)
    : settings_(std::move(settings)),
      shot_(std::move(shot)),
      integrator_(Integrator::create(scene, shot_, backend, settings_)) {
  if (settings_.adaptive > 0) adaptive_.emplace(settings_, shot_.width, shot_.height);
}

RenderJob::~RenderJob() = default;

const RenderStats& RenderJob::stats() const {
  return released_stats_ ? *released_stats_ : integrator_->stats();
}

void RenderJob::release() {
  if (!integrator_) return;
  released_stats_ = integrator_->stats();
  integrator_.reset();
}

uint32_t RenderJob::pass_size(const PassOptions& options) const {
  if (options.spp_per_pass > 0) return options.spp_per_pass;
  const uint64_t pixels = shot_.pixels();
  const uint64_t wavefront = resolve_wavefront(settings_, UINT64_MAX);
  return uint32_t(std::clamp<uint64_t>((8 * wavefront + pixels - 1) / pixels, 1, 1u << 20));
}

RenderOutcome RenderJob::run(Film& film, uint32_t first, uint32_t last, Progress& progress,
                             const PassOptions& options, const Checkpoint& checkpoint) {
  const auto start = Clock::now();
  auto last_checkpoint = start;
  const uint32_t pass = pass_size(options);
  const uint64_t wavefront = resolve_wavefront(settings_, UINT64_MAX);
  // A time limit without --pass-spp sizes the passes so that the render can end near it: the
  // first of one sample per pixel, each next of what the rate so far fits in half the time left
  // (at least one sample, at most `pass`): the passes shrink as the limit nears, so that one
  // slower than the rate measured (a busy machine) still ends close to it. The render ends after
  // the pass that crosses the limit.
  const bool sized_by_time = options.time_limit > 0 && options.spp_per_pass == 0;
  uint64_t samples_taken = 0;  // over every pixel, by this call
  RenderOutcome out;
  out.first = out.complete = out.most = first;
  if (adaptive_ && first == 0) adaptive_->reset();
  while (out.complete < last) {
    // Adaptive sampling lists the pixels still sampling; before the minimum, all of them.
    std::span<const uint32_t> only;
    if (adaptive_ && out.complete >= adaptive_->min_spp()) {
      only = adaptive_->active();
      if (only.empty()) break;  // every pixel converged
    }
    const uint64_t pixels = only.empty() ? shot_.pixels() : only.size();
    uint32_t this_pass = pass;
    if (sized_by_time) {
      const double rate = samples_taken > 0 && out.seconds > 0
                              ? double(samples_taken) / out.seconds
                              : 0.0;  // nothing measured yet: one sample per pixel
      const double fits = rate * (options.time_limit - out.seconds) / 2 / double(pixels);
      this_pass = uint32_t(std::clamp<double>(std::floor(fits), 1.0, double(pass)));
    }
    uint32_t end = adaptive_
                       ? adaptive_->pass_end(out.complete, last, this_pass, wavefront)
                       : uint32_t(std::min<uint64_t>(uint64_t(out.complete) + this_pass, last));
    if (sized_by_time) end = uint32_t(std::min<uint64_t>(end, uint64_t(out.complete) + this_pass));
    const uint64_t taken =
        integrator_->render(film, out.complete, end, only, options.stop, progress);
    samples_taken += taken;
    const auto [fewest, most] = integrator_->sample_order(out.complete, end, pixels).counts(taken);
    out.most = out.complete + most;
    out.complete += fewest;
    out.seconds = seconds_since(start);
    if (out.complete < end) {  // the stop token cut the pass short
      out.stopped = true;
      break;
    }
    ++out.passes;
    if (adaptive_) adaptive_->update(film, end);
    if (options.stop && options.stop->load()) {
      out.stopped = true;
      break;
    }
    if (out.complete < last && options.time_limit > 0 && out.seconds >= options.time_limit) {
      out.timed_out = true;
      break;
    }
    if (checkpoint && out.complete < last && options.checkpoint > 0 &&
        seconds_since(last_checkpoint) >= options.checkpoint) {
      checkpoint(film, out);
      last_checkpoint = Clock::now();
    }
  }
  progress.finish();
  out.seconds = seconds_since(start);
  return out;
}

RenderOutcome RenderJob::resume(Film& film, uint32_t first, uint32_t last, Progress& progress,
                                const PassOptions& options, const Checkpoint& checkpoint) {
  if (adaptive_) throw Error("a render with adaptive sampling cannot be resumed");
  const auto start = Clock::now();
  RenderOutcome out;
  out.first = first;
  std::vector<uint32_t> behind;
  uint32_t least = 0, most = 0;
  auto levels = [&] {
    least = UINT32_MAX, most = 0;
    for (size_t p = 0; p < film.pixels(); ++p)
      least = std::min(least, film.taken(p)), most = std::max(most, film.taken(p));
    out.complete = first + least, out.most = first + most;
  };
  for (levels(); least < most; levels()) {
    // The pixels at the lowest level take the samples up to the next level.
    uint32_t next = most;
    behind.clear();
    for (size_t p = 0; p < film.pixels(); ++p) {
      const uint32_t taken = film.taken(p);
      if (taken == least)
        behind.push_back(uint32_t(p));
      else
        next = std::min(next, taken);
    }
    integrator_->render(film, first + least, first + next, behind, options.stop, progress);
    if (options.stop && options.stop->load()) {
      out.stopped = true;
      levels();
      out.seconds = seconds_since(start);
      progress.finish();
      return out;
    }
  }
  RenderOutcome rest = run(film, std::min(out.complete, last), last, progress, options, checkpoint);
  rest.first = first;
  rest.seconds = seconds_since(start);
  return rest;
}

}  // namespace dacrt
