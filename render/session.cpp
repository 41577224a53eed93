// A render request run to its outputs (see session.h).
#include "dacrt/render/session.h"

#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>

#include "dacrt/io/color.h"
#include "dacrt/io/film_exr.h"
#include "dacrt/io/gltf.h"
#include "dacrt/io/image_file.h"
#include "dacrt/render/header.h"
#include "dacrt/tracer/backend.h"
#include "dacrt/tracer/stats_json.h"
#include "dacrt/util/atomic_file.h"
#include "dacrt/util/error.h"
#include "dacrt/util/file_hash.h"
#include "dacrt/util/interrupt.h"
#include "dacrt/util/memory.h"
#include "dacrt/util/progress.h"
#include "dacrt/util/progress_format.h"
#include "dacrt/util/text.h"

namespace fs = std::filesystem;

namespace dacrt {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}
std::string seconds_text(double seconds) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f s", seconds);
  return text;
}

// The render's largest allocations, estimated before any is made: the film, the resolved image
// (and its preview), the path state. Throws Error naming the file and what is too big when they
// exceed the memory this process may still take.
void check_memory(const RenderRequest& r, const Shot& shot) {
  const std::optional<ImageFormat> output = image_format(r.output);
  const bool resolved = !r.preview.empty() || (output && *output != ImageFormat::exr);
  const RenderMemory need = render_memory(shot, r.settings, resolved);
  const uint64_t film = need.image, paths = need.paths;
  const uint64_t available = available_memory();
  if (film + paths <= available) return;
  throw Error(r.scene + ": a " + std::to_string(shot.width) + " x " + std::to_string(shot.height) +
              " render needs about " + format_bytes(film + paths) + " (" + format_bytes(film) +
              " for the image, " + format_bytes(paths) + " of path state), more than the " +
              format_bytes(available) + " of memory available");
}

nlohmann::json to_json(const RayTypeStats& s) {
  return {{"rays", s.rays}, {"seconds", s.seconds}, {"rays_per_second", s.rays_per_second()}};
}

nlohmann::json to_json(const BackendRun& run) {
  const RenderStats& stats = run.stats;
  const Stats& b = run.backend_stats;
  const BatchSizes batches = batch_sizes(stats.bounce_batches);
  nlohmann::json j = {
      {"backend", run.backend},
      {"render_seconds", stats.seconds},
      {"seconds_with_build", run.seconds},
      {"build_seconds", run.build_seconds},
      {"update", run.update},
      {"update_seconds", run.update_seconds},
      {"paths", stats.paths},
      {"wavefront", stats.wavefront},
      {"dropped_samples", stats.dropped_samples},
      {"clamped_samples", stats.clamped_samples},
      {"skipped", stats.skipped},
      {"light_sampler", stats.light_sampler},
      {"light_entries", stats.light_entries},
      {"bounce_calls", stats.bounce_calls},
      {"bounce_batch", {{"min", batches.min}, {"median", batches.median}, {"max", batches.max}}},
      {"backend_stats", to_json(b)}};
  for (int t = 0; t < ray_type_count; ++t)
    j["rays"][std::string(to_string(RayType(t)))] = to_json(stats.by_type[t]);
  j["bounces"] = nlohmann::json::array();
  for (const auto& bounce : stats.by_bounce) j["bounces"].push_back(to_json(bounce));
  return j;
}

// The match keys of every rank must be rank 0's, or the reduction would add the films of
// different renders (a stale scene copy on one machine, other options on one rank) into one image
// that says it is one render. A rank that failed before this point (its load) takes part from the
// front end's error handling. Throws RanksFailed on every rank, rank 0 printing the lowest
// disagreeing rank and its first differing key.
void check_ranks_agree(RankGroup& ranks, const MatchKeys& keys) {
  auto fail_all = [&](const std::string& message) {
    ranks.collectives_over = true;
    throw RanksFailed{1, message};
  };
  if (const std::string failed = ranks.first_error(""); !failed.empty()) fail_all(failed);
  // Each string as its length (8 bytes) and its bytes: names and values may hold any byte.
  auto put = [](std::string& out, const std::string& text) {
    const uint64_t n = text.size();
    out.append(reinterpret_cast<const char*>(&n), sizeof n).append(text);
  };
  std::string mine;
  for (const auto& [name, value] : keys) put(mine, name), put(mine, value);
  const std::string root = ranks.broadcast(mine);
  MatchKeys theirs;
  for (size_t at = 0; at < root.size();) {
    std::string pair[2];
    for (std::string& text : pair) {
      uint64_t n = 0;
      std::memcpy(&n, root.data() + at, sizeof n);
      text = root.substr(at + sizeof n, size_t(n));
      at += sizeof n + size_t(n);
    }
    theirs.push_back({pair[0], pair[1]});
  }
  std::string differs;
  for (size_t k = 0; k < std::max(keys.size(), theirs.size()) && differs.empty(); ++k) {
    const std::string name = k < keys.size() ? keys[k].first : theirs[k].first;
    const std::string here = k < keys.size() ? keys[k].second : "(none)",
                      there = k < theirs.size() && theirs[k].first == name ? theirs[k].second
                                                                           : "(none)";
    if (here != there)
      differs = "dacrt: error: this rank renders another image than rank 0: " + name + " is " +
                one_line(here.substr(0, 200)) + " here, " + one_line(there.substr(0, 200)) +
                " on rank 0 (every rank needs the same scene files and options)";
  }
  if (const std::string failed = ranks.first_error(differs); !failed.empty()) fail_all(failed);
}

// After each rank rendered its share of samples [first, last) into `film`: every rank waits for
// the others (a rank that failed before this point takes part in the same collective from the
// front end, so the whole job fails with its message), the job stops without an output when any
// rank was stopped, and the films add up on rank 0, which then holds every sample and the
// outcome of one process: true there, false on the others (which are done).
bool gather_film(RankGroup& ranks, Film& film, RenderOutcome& outcome, uint32_t first,
                 uint32_t last) {
  const std::string failed = ranks.first_error("");
  if (!failed.empty()) {
    ranks.collectives_over = true;
    throw RanksFailed{1, failed};  // "rank N: dacrt: error: …"
  }
  if (ranks.any(outcome.stopped)) {
    ranks.collectives_over = true;
    throw RanksFailed{130, "dacrt: stopped: a render under mpirun that is stopped writes nothing "
                           "(render parts with --samples to keep what is done)"};
  }
  ranks.reduce(film);
  ranks.collectives_over = true;
  outcome.first = first, outcome.complete = outcome.most = last;
  return ranks.root();
}

// With --resume, the film in the output `file` if there is one: its exact sums, checked to be an
// earlier run of the render that `keys` and samples [first, last) describe. Empty (a render from
// the start) when the file does not exist.
std::optional<Film> film_to_resume(const std::string& file, const RenderJob& job,
                                   const MatchKeys& keys, uint32_t first, uint32_t last,
                                   bool quiet) {
  if (!fs::exists(file)) {
    if (!quiet) print_message(file + ": nothing to resume yet: rendering from the start");
    return std::nullopt;
  }
  const ExrHeader header = read_sums_header(file, "to resume from");
  const PartHeader part = part_from_attributes(file, header.attributes);
  check_same_render(part, std::map<std::string, std::string>(keys.begin(), keys.end()));
  if (part.first != first)
    throw Error(file + " holds samples from " + std::to_string(part.first) +
                ", this render's start at " + std::to_string(first));
  Film film = job.film();
  read_film_state(file, header, film, 0, last - first);
  return film;
}

// The output and the preview of a film, each in the format its name says. An EXR output holds
// every channel asked, and the per-pixel counts when they differ (a pass cut short, or samples
// dropped as NaN), with the header saying what it holds; any other file holds the image alone
// (check_request refused what only an EXR can hold), and a render cut short, whose EXR would
// keep the exact sums to resume or merge it, says once (`warned`) that this one does not.
// Returns the resolved image when one was made (a non-EXR output or a preview).
std::optional<Image> write_outputs(const RenderRequest& r, const Scene& scene, const Shot& shot,
                   const BackendRun& run, const Film& film, const RenderOutcome& outcome,
                   const MatchKeys& keys, bool& warned) {
  const ExrMetadata header = render_header(r, scene, shot, run, film, outcome, keys);
  const ImageFormat format = output_format("-o", run.output);
  std::optional<Image> image;
  if (format == ImageFormat::exr) {
    write_film_exr(run.output, film, header, keeps_exact_sums(r, outcome));
  } else {
    image = film.resolve();
    write_image(run.output, *image, r.display, header, {}, "-o");
    if (keeps_exact_sums(r, outcome) && !warned) {
      print_message("warning: " + run.output + " holds only the image of a render cut short: " +
                    "its exact sums and sample counts, to --resume or merge it, need an EXR -o");
      warned = true;
    }
  }
  if (run.preview.empty()) return image;
  if (!image) image = film.resolve();
  write_image(run.preview, *image, r.display, header, {}, "--preview");
  return image;
}

}  // namespace

std::unique_ptr<tbb::global_control> thread_limit(int threads) {
  if (threads <= 0) return nullptr;
  return std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                               size_t(threads));
}

struct RenderSession::State {
  RenderRequest r;
  SessionHooks hooks;
  bool spread = false;  // the ranks of an MPI job split each pixel's samples
  std::vector<std::string> backends;
  std::vector<BackendRun> runs;  // one per backend: its name and outputs (frame -1)
  // The frames rendered: one (-1: no number in the names), or FIRST..LAST of --frames, each at
  // time frame / fps with its number in its outputs' names.
  std::vector<int> frames = {-1};
  std::vector<NamedFile> inputs, outputs;

  // Set by the load.
  std::optional<GltfAnimation> file;
  Scene scene;
  std::string animation;    // which play (match.animation)
  std::string inputs_hash;  // match.inputs
  double load_seconds = 0.0;

  // When the first frame began (ProgressOutput's clock): the total ETA of frames × backends.
  double whole_start = -1.0;

  nlohmann::json frame_stats = nlohmann::json::array();
  // One per backend, kept from frame to frame of --frames and updated (Backend::update) with
  // each frame's geometry; a single frame keeps none.
  std::vector<std::unique_ptr<Backend>> backends_kept;
  std::vector<BackendRun> last_runs;
  std::string title;

  double frame_time(int frame) const { return double(frame) / r.fps; }
  std::vector<BackendRun> frame_runs(int frame) const {
    std::vector<BackendRun> out = runs;
    if (frame >= 0)
      for (BackendRun& run : out)
        run.output = with_frame(run.output, frame), run.preview = with_frame(run.preview, frame);
    return out;
  }

  void check_choices();
  void check_files();
  void load();
  // Renders one frame with every backend; false when a stop ended it.
  bool render_frame(int frame, StopOnSignals& signals);
  // Renders with one backend (the index-th); false when a stop ended it before its first sample.
  bool render_backend(BackendRun& run, size_t index, const Shot& shot, int frame,
                      StopOnSignals& signals);
  // The part of the whole one render is (frame × backend), for its progress lines.
  ProgressPart progress_part(size_t backend, int frame) const;
  void write_stats(int frame, const Shot& shot, const std::vector<BackendRun>& done,
                   double geometry_seconds);
};

void RenderSession::State::check_choices() {
  backends = split_list(r.backend);
  if (backends.empty()) throw UsageError("--backend needs at least one backend name");
  if (r.resume && backends.size() > 1)
    throw UsageError("--resume continues one output: one --backend at a time");
  // Under mpirun the ranks split the samples of one image: one frame, one backend, every rank
  // to the end of its share (a pass cut by the clock would leave the shares uneven).
  spread = hooks.ranks && hooks.ranks->size() > 1;
  if (spread) {
    auto refuse = [](const std::string& what) {
      throw UsageError(what + " is for one process: under mpirun the ranks split one image's "
                              "samples (run separate jobs, or parts with --samples)");
    };
    if (backends.size() > 1) refuse("several backends");
    if (r.frames) refuse("--frames");
    if (r.resume) refuse("--resume");
    if (r.passes.time_limit > 0) refuse("--time-limit");
    if (r.passes.checkpoint > 0) refuse("--checkpoint");
    if (r.settings.adaptive > 0) refuse("--adaptive");
    if (!hooks.ranks->root()) r.quiet = true;  // progress, notes and the summary from rank 0
  }
  check_render_choices(r, backends);
  for (const std::string& name : backends) {
    if (std::count(backends.begin(), backends.end(), name) > 1)
      throw UsageError("--backend names " + name + " twice");
    BackendRun run;
    run.backend = name;
    run.output = backends.size() > 1 ? with_backend(r.output, name) : r.output;
    run.preview = backends.size() > 1 ? with_backend(r.preview, name) : r.preview;
    runs.push_back(std::move(run));
  }
  if (r.frames) {
    frames.clear();
    for (int f = r.frames->first; f <= r.frames->second; ++f) frames.push_back(f);
  }
}

// Everything an output needs, checked before the scene is loaded: writable and distinct output
// files that are not inputs, the display transform of a preview.
void RenderSession::State::check_files() {
  // The scene first: a missing one is said before any output of a long sequence is looked at.
  check_input_file(r.scene, "file");
  inputs = {{"the scene", r.scene}};
  if (!r.settings.environment_file.empty()) {
    check_input_file(r.settings.environment_file, "environment map");
    inputs.push_back({"the environment map", r.settings.environment_file});
  }
  for (int frame : frames)
    for (const BackendRun& run : frame_runs(frame))
      outputs.push_back({"-o", run.output}), outputs.push_back({"--preview", run.preview});
  outputs.push_back({"--stats", r.stats});
  if (!r.preview.empty() || !r.report.empty()) {
    set_color_warnings(!r.quiet);
    check_display_transform(r.display);
    for (const std::string& file : display_input_files())
      inputs.push_back({"the display configuration's file", file});
  }
  std::vector<std::string> output_paths;
  for (const NamedFile& out : outputs) output_paths.push_back(out.path);
  check_writable(output_paths);
  outputs.insert(outputs.end(), hooks.more_outputs.begin(), hooks.more_outputs.end());
  check_outputs(outputs, inputs);
}

void RenderSession::State::load() {
  if (r.frames) r.gltf.time = frame_time(frames.front());
  const auto t_load = Clock::now();
  // A load that takes long says so (in a log, every few seconds), then what took the time.
  std::error_code size_error;
  const uint64_t bytes = fs::file_size(r.scene, size_error);
  const std::string name =
      r.scene + (size_error ? std::string() : " (" + format_bytes(bytes) + ")");
  Activity loading("loading " + name, !r.quiet);
  file.emplace(r.scene, r.gltf, frames.size() > 1);  // one frame is never posed
  const double read_seconds = seconds_since(t_load);
  scene = file->load();
  animation = file->animation_choice();
  // One frame is never posed again: the file's buffers (as large as the scene's) go now.
  if (frames.size() == 1) file.reset();
  load_seconds = seconds_since(t_load);
  char took[256];
  std::snprintf(took, sizeof took,
                " in %.1f s: reading the file %.1f s, making the scene (%zu triangles, %zu "
                "textures) %.1f s",
                load_seconds, read_seconds, scene.geometry.size(), scene.textures.size(),
                load_seconds - read_seconds);
  loading.done("loaded " + name + took);
  for (const FileRead& read : scene.files)
    inputs.push_back({"the scene's external file", read.path});
  check_outputs(outputs, inputs);
  // The fingerprint of what the image is made from, for merging parts (match.inputs).
  std::vector<FileRead> input_files = {{r.scene, std::nullopt}};
  input_files.insert(input_files.end(), scene.files.begin(), scene.files.end());
  if (!r.settings.environment_file.empty())
    input_files.push_back({r.settings.environment_file, std::nullopt});
  inputs_hash = hash_text(hash_files(input_files));
}

ProgressPart RenderSession::State::progress_part(size_t backend, int frame) const {
  ProgressPart part;
  const size_t n = frames.size() * runs.size();
  const size_t k = size_t(std::find(frames.begin(), frames.end(), frame) - frames.begin());
  if (r.frames)
    part.position = "frame " + std::to_string(frame) + " (" + std::to_string(k + 1) + " of " +
                    std::to_string(frames.size()) + ")";
  if (n > 1) {
    part.before = double(k * runs.size() + backend) / double(n);
    part.share = 1.0 / double(n);
    part.whole_start = whole_start;
  }
  return part;
}

bool RenderSession::State::render_backend(BackendRun& run, size_t index, const Shot& shot,
                                          int frame, StopOnSignals& signals) {
  const RenderSettings& s = r.settings;
  const uint32_t first = r.first_sample(), last = r.last_sample();
  const auto t0 = Clock::now();
  const std::string which =
      runs.size() > 1 ? " " + run.backend + " (" + std::to_string(index + 1) + " of " +
                            std::to_string(runs.size()) + ")"
                      : std::string();
  // A sequence keeps each backend and hands it the next frame's geometry; it builds anew the
  // first time, and when the backend does not follow frames (option frames=new).
  const bool keeps = frames.size() > 1;
  if (keeps && backends_kept.size() < runs.size()) backends_kept.resize(runs.size());
  std::unique_ptr<Backend> own;
  std::unique_ptr<Backend>& backend = keeps ? backends_kept[index] : own;
  if (backend) {
    Activity updating("updating the " + run.backend + " backend for " +
                          std::to_string(scene.geometry.size()) + " triangles",
                      !r.quiet);
    const Backend::Update how = backend->update(scene.geometry);
    if (how == Backend::Update::none) {
      backend.reset();
    } else {
      run.update = to_string(how);
      run.update_seconds = seconds_since(t0);
      updating.done("updated the " + run.backend + " backend (" + run.update + ") in " +
                    seconds_text(run.update_seconds));
    }
  }
  if (!backend) {
    Activity building("building the " + run.backend + " backend for " +
                          std::to_string(scene.geometry.size()) + " triangles",
                      !r.quiet);
    backend =
        Backend::create(run.backend, scene.geometry, r.backend_options.for_plugin(run.backend));
    run.build_seconds = seconds_since(t0);
    building.done("built the " + run.backend + " backend in " + seconds_text(run.build_seconds));
  }
  // The integrator's set-up (textures, lights) and the film: long for a large scene or image.
  Activity preparing("preparing the render" + which, !r.quiet);
  RenderJob job(scene, *backend, s, shot);
  if (r.frames) r.gltf.time = frame_time(frame);  // each frame's own time (match.time)
  const MatchKeys keys = match_keys(r, shot, animation, inputs_hash, run.backend);
  if (spread) check_ranks_agree(*hooks.ranks, keys);
  std::optional<Film> earlier;
  if (r.resume) earlier = film_to_resume(run.output, job, keys, first, last, r.quiet);
  const bool resuming = earlier.has_value();
  Film film = resuming ? std::move(*earlier) : job.film();
  uint64_t taken = 0;
  for (size_t p = 0; p < film.pixels(); ++p) taken += film.taken(p);
  preparing.done("prepared the render" + which + " in " + seconds_text(preparing.seconds()));
  // This process's samples: all of them, or its rank's share.
  const auto [from, to] = spread ? hooks.ranks->share(first, last) : std::pair(first, last);
  Progress progress("render" + which, shot.pixels() * uint64_t(to - from) - taken, !r.quiet,
                    progress_part(index, frame), shot.pixels());
  progress.limit_time(r.passes.time_limit);
  bool warned = false;
  const auto checkpoint = [&](const Film& so_far, const RenderOutcome& o) {
    write_outputs(r, scene, shot, run, so_far, o, keys, warned);
  };
  RenderOutcome outcome = resuming
                              ? job.resume(film, first, last, progress, r.passes, checkpoint)
                              : job.run(film, from, to, progress, r.passes, checkpoint);
  if (spread && !gather_film(*hooks.ranks, film, outcome, first, last)) return false;
  run.stats = job.stats();
  job.release();  // the path state is not needed to write the outputs
  run.backend_stats = backend->stats();
  run.seconds = seconds_since(t0);
  run.spp = outcome.spp();
  run.passes = outcome.passes;
  run.time_limit = r.passes.time_limit;
  run.least_spp = film.min_count(), run.most_spp = film.max_count();
  run.mean_spp = double(film.total_count()) / double(std::max<size_t>(film.pixels(), 1));
  if (outcome.stopped) run.stopped = signals.signal() == SIGTERM ? "SIGTERM" : "SIGINT";
  if (outcome.timed_out) run.stopped = "the time limit";
  // A render stopped before its first sample leaves the previous outputs as they were.
  if (film.max_count() == 0 && outcome.stopped) return false;
  std::optional<Image> image = write_outputs(r, scene, shot, run, film, outcome, keys, warned);
  if (!r.quiet) {
    if (!image) image = film.resolve();
    const std::string dark = dark_image_note(*image, shot, r.display.exposure, run.output);
    if (!dark.empty()) print_message(dark);
  }
  if (hooks.rendered) hooks.rendered(run, film);
  if (!r.quiet) print_summary(run, shot, s);
  return !outcome.stopped;
}

void RenderSession::State::write_stats(int frame, const Shot& shot,
                                       const std::vector<BackendRun>& done,
                                       double geometry_seconds) {
  const RenderSettings& s = r.settings;
  const auto has_samples = [](const BackendRun& run) {
    return run.spp > 0 || run.stopped.empty();
  };
  size_t kept = 0;
  for (const BackendRun& run : done) kept += has_samples(run);
  if (r.stats.empty() || kept == 0) return;
  auto describe = [&](const BackendRun& run) {
    nlohmann::json j = {{"scene", r.scene},
                        {"triangles", scene.geometry.size()},
                        {"degenerate_triangles", scene.degenerate_triangles},
                        {"width", shot.width},
                        {"height", shot.height},
                        {"spp", run.spp},
                        {"spp_requested", s.spp},
                        {"integrator", s.integrator},
                        {"sampler", sampler_name(s.sampler)},
                        {"threads", tbb::this_task_arena::max_concurrency()},
                        {"load_seconds", load_seconds}};
    if (!run.stopped.empty()) j["stopped_by"] = run.stopped;
    j["passes"] = run.passes;
    if (run.time_limit > 0) j["time_limit"] = run.time_limit;
    if (shot.camera.aperture > 0.f)  // a thin lens (a pinhole's statistics say nothing)
      j["lens"] = {{"aperture", shot.camera.aperture},
                   {"focus_distance", shot.camera.focus_distance}};
    if (s.adaptive > 0)
      j["adaptive"] = {{"target", s.adaptive},
                       {"min_spp", adaptive_min_spp(s)},
                       {"least_spp", run.least_spp},
                       {"most_spp", run.most_spp},
                       {"mean_spp", run.mean_spp}};
    j.update(to_json(run));
    return j;
  };
  nlohmann::json j;
  if (runs.size() == 1) {
    j = describe(done[0]);
  } else {
    j = {{"backends", nlohmann::json::array()}};
    for (const BackendRun& run : done)
      if (has_samples(run)) j["backends"].push_back(describe(run));
  }
  if (r.frames) {
    // Each frame: its number, time, the seconds its geometry took to make, and its renders.
    j["frame"] = frame;
    j["time"] = frame_time(frame);
    j["geometry_seconds"] = geometry_seconds;
    frame_stats.push_back(j);
    j = {{"frames", frame_stats}};
  }
  write_atomically(r.stats, "statistics", [&](std::ostream& out) { out << json_text(j) << "\n"; });
}

bool RenderSession::State::render_frame(int frame, StopOnSignals& signals) {
  const RenderSettings& s = r.settings;
  // A frame's geometry is made in place: the file's scene posed at its time (the first came
  // with the load).
  double geometry_seconds = load_seconds;
  if (frame != frames.front()) {
    const auto t0 = Clock::now();
    file->pose(frame_time(frame), scene);
    geometry_seconds = seconds_since(t0);
  }
  const Shot shot = make_shot(scene, s);
  title = fs::path(r.scene).filename().string() + ", " + std::to_string(shot.width) + "×" +
          std::to_string(shot.height) + ", " + std::to_string(s.spp) + " spp, " + s.integrator +
          " integrator";
  if (frame == frames.front()) {
    check_memory(r, shot);
    if (!r.quiet)
      for (const std::string& note : shot.notes) print_message(note);
  }
  std::vector<BackendRun> runs_now = frame_runs(frame);
  size_t rendered = 0;  // the runs begun: a stop skips the backends after it
  bool go_on = true;
  for (BackendRun& run : runs_now) {
    const bool finished = render_backend(run, rendered++, shot, frame, signals);
    if (spread && !hooks.ranks->root()) return false;  // rank 0 writes; this rank is done
    if (!finished) {
      go_on = false;
      break;  // the backends after it are not rendered
    }
  }
  runs_now.resize(rendered);
  if (r.frames && !r.quiet) {
    char line[160];
    const size_t k = size_t(std::find(frames.begin(), frames.end(), frame) - frames.begin());
    std::snprintf(line, sizeof line, "frame %d (%zu of %zu, t = %g s): geometry %.3f ms%s", frame,
                  k + 1, frames.size(), frame_time(frame), 1e3 * geometry_seconds,
                  frame == frames.front() ? " (the load)" : "");
    std::string text = line;
    for (const BackendRun& run : runs_now) {
      if (run.update == "new")
        std::snprintf(line, sizeof line, ", %s build %.3f ms", run.backend.c_str(),
                      1e3 * run.build_seconds);
      else
        std::snprintf(line, sizeof line, ", %s %s %.3f ms", run.backend.c_str(),
                      run.update.c_str(), 1e3 * run.update_seconds);
      text += line;
    }
    if (k + 1 < frames.size() && go_on) {  // the frames left, at the pace of those done
      const double so_far = ProgressOutput::standard_error().now() - whole_start;
      text += "; total ETA " +
              format_duration(so_far * double(frames.size() - k - 1) / double(k + 1));
    }
    print_message(text);
  }
  write_stats(frame, shot, runs_now, geometry_seconds);
  last_runs = std::move(runs_now);
  return go_on && !signals.signal();
}

RenderSession::RenderSession(RenderRequest request, SessionHooks hooks)
    : state_(std::make_unique<State>()) {
  state_->r = std::move(request);
  state_->hooks = std::move(hooks);
  state_->check_choices();
  state_->check_files();
}

RenderSession::~RenderSession() = default;

int RenderSession::run() {
  State& st = *state_;
  const auto threads = thread_limit(st.r.threads);
  st.load();
  // From here on SIGINT and SIGTERM stop the render and write what it has.
  StopOnSignals signals;
  st.r.passes.stop = &signals.token();
  st.r.backend_options.threads = st.r.threads;
  st.whole_start = ProgressOutput::standard_error().now();
  for (int frame : st.frames)
    if (!st.render_frame(frame, signals)) break;
  if (signals.signal()) return 128 + signals.signal();
  return 0;
}

const std::vector<BackendRun>& RenderSession::runs() const { return state_->last_runs; }
const std::string& RenderSession::title() const { return state_->title; }

FilmRender render_to_film(const RenderRequest& r, const Scene& scene) {
  const auto threads = thread_limit(r.threads);
  const Shot shot = make_shot(scene, r.settings);
  check_memory(r, shot);
  Options options = r.backend_options;
  options.threads = r.threads;
  Activity building("building the " + r.backend + " backend for " +
                        std::to_string(scene.geometry.size()) + " triangles",
                    !r.quiet);
  auto backend = Backend::create(r.backend, scene.geometry, options.for_plugin(r.backend));
  building.done("built the " + r.backend + " backend in " + seconds_text(building.seconds()));
  RenderJob job(scene, *backend, r.settings, shot);
  Film film = job.film();
  const uint32_t first = r.first_sample(), last = r.last_sample();
  Progress bar("render", shot.pixels() * uint64_t(last - first), !r.quiet, {}, shot.pixels());
  bar.limit_time(r.passes.time_limit);
  const RenderOutcome outcome = job.run(film, first, last, bar, r.passes);
  std::vector<std::string> notes = shot.notes;
  if (outcome.timed_out)
    notes.push_back(r.scene + ": the time limit stopped the render at " +
                    std::to_string(outcome.spp()) + " of " + std::to_string(last - first) +
                    " samples per pixel");
  if (std::string dark = dark_image_note(film.resolve(), shot, 0.0, r.scene); !dark.empty())
    notes.push_back(std::move(dark));
  return {std::move(film), outcome, std::move(notes)};
}

}  // namespace dacrt
