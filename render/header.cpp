// The EXR header's attributes (see header.h).
#include "dacrt/render/header.h"

#include <cstdio>
#include <cstdlib>

#include "dacrt/io/film_exr.h"
#include "dacrt/scene/camera.h"
#include "dacrt/util/error.h"

namespace dacrt {

namespace {

// A float exactly, as C's %a writes it.
std::string format_hex(float v) {
  char text[32];
  std::snprintf(text, sizeof text, "%a", double(v));
  return text;
}

// A double that reads back the same.
std::string real(double v) {
  char text[40];
  std::snprintf(text, sizeof text, "%.17g", v);
  return text;
}

// The view exactly (hexadecimal floats): the camera attribute is rounded for reading.
std::string view_text(const Camera& camera) {
  std::string view;
  for (int c = 0; c < 4; ++c)
    for (int k = 0; k < 4; ++k) view += format_hex(camera.to_world[c][k]) + " ";
  return view + format_hex(camera.yfov) + " " + format_hex(camera.ymag) + " " +
         format_hex(camera.znear) + (camera.orthographic ? " orthographic" : " perspective") +
         (camera.aperture > 0.f ? " lens " + format_hex(camera.aperture) + " " +
                                      format_hex(camera.focus_distance)
                                : "");
}

std::string range_text(uint32_t first, uint32_t last) {
  return std::to_string(first) + ":" + std::to_string(last);
}

// The attributes a merged file gets anew rather than from its first part.
const std::set<std::string> recomputed = {
    "spp",        "backend",        "integrator",       "renderSeconds",  "sampleRange",
    "sampleRangeMost", "samplesPerPixel", "stoppedBy", "samplesDropped", "samplesClamped",
    "exactSums",  "software",       "dacrtVersion",     "mergedFrom",     "samplesMissing",
    "sampleRanges"};

// What every header ends with: the software that wrote it.
void add_software(ExrMetadata& meta) {
  meta.extra.push_back(software_attribute());
  meta.extra.push_back({"dacrtVersion", version()});
}

}  // namespace

std::pair<std::string, std::string> software_attribute() {
  return {"software", std::string("dacrt ") + version()};
}

MatchKeys match_keys(const RenderRequest& r, const Shot& shot, const std::string& animation,
                     const std::string& inputs_hash, const std::string& backend) {
  const RenderSettings& s = r.settings;
  std::string environment = "default";
  if (!s.environment_file.empty())
    environment = "map " + s.environment_file;
  else if (s.environment)
    environment = real(s.environment->x) + "," + real(s.environment->y) + "," +
                  real(s.environment->z);
  std::string lights;
  for (const PunctualLight& l : s.lights) lights += (lights.empty() ? "" : "; ") + l.name;
  std::string aovs;
  for (int a = 0; a < aov_count; ++a) {
    if (!s.aovs.has(Aov(a))) continue;
    if (!aovs.empty()) aovs += ',';
    aovs += AovSet::name(Aov(a));
  }
  const char* sample_environment[] = {"auto", "on", "off"};
  MatchKeys keys = {{"match.inputs", inputs_hash},
          {"match.gltfScene", std::to_string(r.gltf.scene)},
          {"match.variant", r.gltf.variant},
          {"match.time", r.gltf.time ? real(*r.gltf.time) : "rest pose"},
          {"match.animation", r.gltf.time ? animation : "rest pose"},
          {"match.size", std::to_string(shot.width) + "x" + std::to_string(shot.height)},
          {"match.camera", view_text(shot.camera)},
          {"match.integrator", s.integrator},
          {"match.sampler", sampler_name(s.sampler)},
          {"match.seed", std::to_string(s.seed)},
          {"match.spp", std::to_string(s.spp)},
          {"match.maxDepth", std::to_string(s.max_depth)},
          {"match.rouletteDepth", std::to_string(s.roulette_depth)},
          {"match.environment", environment},
          {"match.sampleEnvironment", sample_environment[int(s.sample_environment)]},
          {"match.lights", lights},
          {"match.aoDistance", real(s.ao_distance)},
          {"match.lambertLanes", s.lambert_lanes ? "on" : "off"},
          {"match.aovs", aovs},
          {"match.intersection", backend == "embree" ? "embree" : "dacrt"}};
  // (Only when asked: auto decides alike from the same scene and lights.)
  const char* light_sampler[] = {"auto", "tree", "power"};
  if (s.light_sampler != LightPicking::automatic)
    keys.push_back({"match.lightSampler", light_sampler[int(s.light_sampler)]});
  return keys;
}

ExrMetadata render_header(const RenderRequest& r, const Scene& scene, const Shot& shot,
                          const BackendRun& run, const Film& film, const RenderOutcome& outcome,
                          const MatchKeys& keys) {
  const RenderSettings& s = r.settings;
  const uint32_t least = film.min_count(), most = film.max_count();
  ExrMetadata meta;
  meta.spp = int(least);
  meta.backend = run.backend;
  meta.integrator = s.integrator;
  meta.render_seconds = outcome.seconds;
  const Camera& camera = shot.camera;
  const Box b = scene.framing_bounds();
  meta.extra = {
      {"scene", r.scene},
      {"camera", std::to_string(shot.camera_index) +
                     (camera.name.empty() ? "" : " (" + camera.name + ")") + ": " +
                     camera_flags(camera, b.empty() ? glm::vec3(0.f) : b.center())},
      {"sampler", sampler_name(s.sampler)},
      {"seed", std::to_string(s.seed)},
      {"sppRequested", std::to_string(s.spp)},
      // The samples every pixel has (fewer than asked when a stop or the time limit came first).
      {"sampleRange", range_text(outcome.first, outcome.complete)},
      {"samplesPerPixel", samples_per_pixel_text(least, most)}};
  add_software(meta);
  if (s.adaptive > 0) {
    char target[32];
    std::snprintf(target, sizeof target, "%g", s.adaptive);
    const std::string min = std::to_string(adaptive_min_spp(s));
    meta.extra.push_back({"adaptiveSampling", "on: relative error " + std::string(target) +
                                                  ", at least " + min + " spp, at most " +
                                                  std::to_string(s.spp)});
    meta.extra.push_back({"adaptiveTarget", target});
    meta.extra.push_back({"adaptiveMinSpp", min});
  }
  if (!run.stopped.empty()) meta.extra.push_back({"stoppedBy", run.stopped});
  if (!outcome.uniform())  // a pass cut short: some pixels have more
    meta.extra.push_back({"sampleRangeMost", range_text(outcome.first, outcome.most)});
  for (const auto& key : keys) meta.extra.push_back(key);
  return meta;
}

bool keeps_exact_sums(const RenderRequest& r, const RenderOutcome& outcome) {
  return r.samples || r.keep_sums || outcome.complete < r.last_sample();
}

std::string part_cut_short(const std::map<std::string, std::string>& attributes) {
  const auto most = attributes.find("sampleRangeMost");
  return most == attributes.end() ? "" : most->second;
}

double part_render_seconds(const std::string& file,
                           const std::map<std::string, std::string>& attributes) {
  // Render times add up: each must be a number of seconds (a forged inf, NaN or 1e308 would make
  // the sum infinite).
  const auto it = attributes.find("renderSeconds");
  if (it == attributes.end()) return 0.0;
  char* end = nullptr;
  const double s = std::strtod(it->second.c_str(), &end);
  if (it->second.empty() || *end != '\0' || !(s >= 0.0 && s < 1e12))
    throw Error(file + ": its renderSeconds attribute \"" + one_line(it->second.substr(0, 40)) +
                "\" is not a number of seconds");
  return s;
}

std::string part_backend(const std::map<std::string, std::string>& attributes) {
  const auto it = attributes.find("backend");
  return it == attributes.end() ? "" : it->second;
}

MergedHeader merged_header(const std::map<std::string, std::string>& first,
                           const std::vector<PartHeader>& parts, const PartPlan& plan,
                           const Film& film, const std::set<std::string>& backends,
                           double seconds, bool keep_sums) {
  std::vector<std::pair<uint32_t, uint32_t>> held;  // the samples in the parts, as ranges
  uint32_t next = 0;
  for (const auto& [from, to] : plan.missing) {
    if (from > next) held.push_back({next, from});
    next = to;
  }
  if (next < plan.spp) held.push_back({next, plan.spp});
  MergedHeader out;
  ExrMetadata& meta = out.meta;
  const uint32_t least = film.min_count(), most = film.max_count();
  meta.spp = int(least);
  for (const std::string& b : backends) meta.backend += (meta.backend.empty() ? "" : ", ") + b;
  const auto integrator = parts.front().match.find("match.integrator");
  if (integrator != parts.front().match.end()) meta.integrator = integrator->second;
  meta.render_seconds = seconds;
  for (const auto& [key, value] : first)
    if (!recomputed.count(key)) meta.extra.push_back({key, value});
  std::string from;
  for (size_t i : plan.order)
    from += (from.empty() ? "" : ", ") + parts[i].file + " (" + range_text(parts[i].first, parts[i].last) + ")";
  meta.extra.push_back({"mergedFrom", from});
  // One range is a part of the render (or the whole): sampleRange says which. Several are not
  // one range of anything: sampleRanges lists them.
  const bool one_range = held.size() == 1;
  if (one_range)
    meta.extra.push_back({"sampleRange", range_text(held[0].first, held[0].second)});
  else
    meta.extra.push_back({"sampleRanges", ranges_text(held)});
  if (!plan.missing.empty()) meta.extra.push_back({"samplesMissing", ranges_text(plan.missing)});
  meta.extra.push_back({"samplesPerPixel", samples_per_pixel_text(least, most)});
  add_software(meta);
  // One range short of the whole render is a part itself: it keeps its sums.
  out.exact = one_range && (keep_sums || held[0] != std::pair(0u, plan.spp));
  return out;
}

}  // namespace dacrt
