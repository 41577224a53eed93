// dacrt: the command-line front end. `dacrt render` path-traces a glTF scene to OpenEXR (plus a
// PNG preview), `dacrt info` describes a scene, `dacrt views` lists the preview's display views,
// `dacrt diff` compares two images.
// Exit codes: 0 success, 1 error (one line on stderr naming the file and what is wrong), 2 usage
// error.
#include <tbb/global_control.h>
#include <tbb/task_arena.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include "apps/converge.h"
#include "apps/diff.h"
#include "apps/merge.h"
#include "apps/ranks.h"
#include "apps/render_options.h"
#include "apps/render_report.h"
#include "apps/report.h"
#include "bench/bench.h"
#include "bench/html_page.h"
#include "dacrt/integrators/integrator.h"
#include "dacrt/io/color.h"
#include "dacrt/io/exr.h"
#include "dacrt/io/film_exr.h"
#include "dacrt/io/gltf.h"
#include "dacrt/render/part_plan.h"
#include "dacrt/render/render_job.h"
#include "dacrt/tracer/backend.h"
#include "dacrt/util/atomic_file.h"
#include "dacrt/util/error.h"
#include "dacrt/util/file_hash.h"
#include "dacrt/util/interrupt.h"
#include "dacrt/util/memory.h"
#include "dacrt/util/paths.h"
#include "dacrt/util/progress.h"
#include "dacrt/util/text.h"

namespace fs = std::filesystem;
using namespace dacrt;

namespace {

// The processes of this run: one, or the ranks of `mpirun -np R dacrt render …` (apps/ranks.h).
const Ranks* ranks = nullptr;
// Set once a rank has passed the last collective call of the run: a failure after it (rank 0
// writing the outputs) is its own and ends the run without waiting for the others.
bool collectives_over = false;

// The whole job fails: another rank's failure (its message, from Ranks::first_error), or a stop.
struct RanksFailed {
  int code;
  std::string message;  // printed by rank 0
};

// Under mpirun, after each rank rendered its share of samples [first, last) into `film`: every
// rank waits for the others (a rank that failed before this point takes part in the same
// collective from main(), so the whole job fails with its message), the job stops without an
// output when any rank was stopped, and the films add up on rank 0, which then holds every
// sample and the outcome of one process: true there, false on the others (which are done).
bool gather_film(Film& film, RenderOutcome& outcome, uint32_t first, uint32_t last) {
  const std::string failed = ranks->first_error("");
  if (!failed.empty()) {
    collectives_over = true;
    throw RanksFailed{1, failed};  // "rank N: dacrt: error: …"
  }
  if (ranks->any(outcome.stopped)) {
    collectives_over = true;
    throw RanksFailed{130, "dacrt: stopped: a render under mpirun that is stopped writes nothing "
                           "(render parts with --samples to keep what is done)"};
  }
  ranks->reduce(film);
  collectives_over = true;
  outcome.first = first, outcome.complete = outcome.most = last;
  return ranks->root();
}

// The match.* keys of a render (match_keys), as name and value.
using MatchKeys = std::vector<std::pair<std::string, std::string>>;

// Under mpirun, before any rank renders: every rank's match keys must be rank 0's, or the
// reduction would add the films of different renders (a stale scene copy on one machine, other
// options on one rank) into one image that says it is one render. A rank that failed before this
// point (its load) takes part from main(), as in gather_film. Throws RanksFailed on every rank,
// rank 0 printing the lowest disagreeing rank and its first differing key.
void check_ranks_agree(const MatchKeys& keys) {
  auto fail_all = [](const std::string& message) {
    collectives_over = true;
    throw RanksFailed{1, message};
  };
  if (const std::string failed = ranks->first_error(""); !failed.empty()) fail_all(failed);
  // Each string as its length (8 bytes) and its bytes: names and values may hold any byte.
  auto put = [](std::string& out, const std::string& text) {
    const uint64_t n = text.size();
    out.append(reinterpret_cast<const char*>(&n), sizeof n).append(text);
  };
  std::string mine;
  for (const auto& [name, value] : keys) put(mine, name), put(mine, value);
  const std::string root = ranks->broadcast(mine);
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
  if (const std::string failed = ranks->first_error(differs); !failed.empty()) fail_all(failed);
}

constexpr const char* main_help = R"(dacrt: a path tracer on divide-and-conquer ray tracing

Usage:
  dacrt render SCENE [options]   render a glTF 2.0 scene (.gltf or .glb) to OpenEXR
  dacrt info SCENE [--scene N] [--animation NAME|INDEX|all]
                                 triangles, meshes, materials, variants, lights, animations,
                                 cameras, bounds
  dacrt views                    the display views a preview can use (`render --view`), from
                                 $OCIO when it is set
  dacrt bench SCENE [options]    every backend on the same rays of each type: build and trace
                                 time, Mrays/s, peak memory (`dacrt bench --help`)
  dacrt converge SCENE [options] run time against error: each configuration (--config
                                 "backend=embree") at 1, 2, 4, ... spp against a reference; a
                                 CSV, a plot, equal-error and equal-time tables
                                 (`dacrt converge --help`)
  dacrt diff A.exr B.exr         how far image A is from B (the reference): RMSE, relMSE,
                                 MAE, SMAPE, max |A-B| per channel; error maps as EXR and
                                 false-colour PNG (`dacrt diff --help`)
  dacrt merge PART.exr... -o OUT  add the parts of one render (`render --samples FIRST:LAST`)
                                 into its image, exactly (`dacrt merge --help`)
  dacrt --help                   this text; `dacrt render --help` lists the render options
)";

constexpr const char* render_help = R"help(Usage: dacrt render SCENE [options]

Output
  -o, --output OUT.exr       the image: float RGB, scene-linear Rec.709 (default: SCENE's name .exr)
  --preview OUT.png          also an 8-bit display preview through OpenColorIO ($OCIO if set)
  --view NAME                the preview's display view (default sRGB, or $OCIO's default view);
                             `dacrt views` lists them, e.g. "ACES 1.0 SDR-video (sRGB)" (tone
                             mapped), or with $OCIO "DISPLAY/VIEW". Needs --preview
  --exposure STOPS           scales the preview's scene-linear values by 2^STOPS before the view
                             (default 0; the EXR is not changed). Needs --preview
  --stats OUT.json           render statistics: time and rays/s per ray type and bounce
  --report DIR               also DIR/index.html: one self-contained page with the backends'
                             images side by side (DIR/NAME.png), their rays per second per ray
                             type and bounce, the batch sizes and the comparison table
  --aov LIST                 more layers in the EXR, comma-separated: albedo (albedo.R/G/B), normal
                             (N.X/Y/Z), depth (Z, along the view axis; 1e10 where nothing was hit),
                             position (P.X/Y/Z), variance (variance.R/G/B: of each pixel's mean),
                             samples (samples.X: the per-pixel count)
Progress
  --pass-spp N               samples per pixel in each pass (default: 8 wavefronts' worth)
  --time-limit SECONDS       stop after the pass that crosses it (the header says the spp done)
  --checkpoint SECONDS       rewrite the outputs after passes, at most this often
                             SIGINT or SIGTERM: stop at the next wavefront, finish the paths in
                             flight and write the outputs (exit 130 or 143); a second one ends at once
Image
  --width W, --height H      resolution (default 512 × 512, or the camera's aspect ratio)
  --spp N                    samples per pixel (default 64)
  --samples FIRST:LAST       only sample indices [FIRST, LAST) of every pixel of the --spp
                             render (its numbers are the whole render's: the header's sampleRange
                             says which; not with --adaptive). The EXR keeps the exact sums of its
                             samples: `dacrt merge` adds such parts into the whole render, bit
                             for bit
  --keep-sums                keep the exact sums in a complete render's EXR too (a render cut
                             short by a stop or --time-limit, and its checkpoints, always keep them)
  --resume                   continue the render the -o file holds (same scene and settings, its
                             exact sums kept) up to --spp, or its --samples range; the image is
                             the uninterrupted render's bit for bit. Without the file: from the start
  --adaptive REL             adaptive sampling (default off): after the minimum, a pixel stops
                             taking samples once the relative error of its mean, and of its 3×3
                             neighbours' means, is below REL (in (0, 1), e.g. 0.01); the others go
                             on to --spp. The samples channel and the header say what each got
  --adaptive-min N           with --adaptive: the samples every pixel takes first (default
                             max(16, spp / 16))
  --camera INDEX             which of the scene's cameras (default 0; without one, the scene is framed)
  --look-from X,Y,Z          the camera's position (overrides the chosen camera; without --look-at
                             it looks at the scene's centre); `dacrt info` prints each camera so
  --look-at X,Y,Z            a point it looks at (default: along the chosen camera's view)
  --up X,Y,Z                 its up direction (default: the chosen camera's, +Y when framed)
  --fov DEGREES              its vertical field of view (default: the chosen camera's)
  --scene INDEX              which of the file's scenes (default: the file's default scene)
  --variant NAME             the KHR_materials_variants variant to render (dacrt info lists them)
Animation
  --time SECONDS             evaluate the file's animations at this time (default: the rest pose,
                             nodes and morph weights as the file gives them)
  --animation NAME|INDEX|all which of the file's animations play (default: the first, index 0;
                             all: every one at once); `dacrt info` lists them
  --frames FIRST:LAST        render frames FIRST..LAST, frame f at time f / fps, to OUT.%04d.exr
                             (and PREVIEW.%04d.png); each frame's geometry is re-made in place, and
                             the time that takes and each backend's build time are printed (and
                             written to --stats)
  --fps F                    frames per second for --frames (default 24)
Light transport
  --integrator NAME          path (default: path tracing), direct (direct lighting, NEE + MIS,
                             one scattering event), ao (ambient occlusion), albedo, normal, depth
                             (the first hit's values as the image)
  --ao-distance D            ao: how far occluders count (default: the scene's diagonal)
  --max-depth D              scattering events per path (default 64; Russian roulette after 3)
  --point-light X,Y,Z=R,G,B  adds a point light at X,Y,Z of intensity R,G,B (irradiance I / d², the
                             units of KHR_lights_punctual's intensity as dacrt reads it); repeatable:
                             interiors without emitters (McGuire's conference room) can be lit
  --environment R,G,B        uniform environment radiance (default 0, or 1 when the scene has no emitters)
  --environment FILE.exr     an equirectangular environment map (+Y up, image centre towards -Z),
                             importance-sampled
  --sample-environment MODE  next-event estimation of a uniform environment, with MIS: auto
                             (default: with other lights, where a pilot finds a quarter of bounce
                             rays escaping), on, off
  --seed S                   random seed (default 0)
  --sampler NAME             sobol (default: Owen-scrambled Sobol, stratified in each pair of
                             dimensions), independent (a hash per number: white noise)
Ray tracing
  --backend NAME[,NAME...]   dacrt (default), dacrt-naive, embree, brute; several: each renders
                             with the same seed to OUT.NAME.exr, then a table compares them
                             (rays, seconds and Mrays/s per ray type and bounce, kernel counters,
                             batch sizes, whole render times with the build, ratios) on stdout
  --backend-option [NAME.]KEY=VALUE
                             backend setting, repeatable; NAME. for one backend of several (dacrt: bins, leaf_rays, leaf_work, leaf_triangles,
                             max_leaf_triangles, sample_size, sample_threshold, small_nodes, filter_skip,
                             cost_traversal, cost_intersect, simd, task_rays, chunks, seed,
                             max_depth, top_triangles, leaf_lanes, group_rays)
  --wavefront N              live paths at most (default: what 96 MiB of path state holds,
                             about 286 000, or the frame's paths if fewer)
  --threads T                worker threads (default: all cores)
Other
  --quiet                    no progress bar or summary on stderr
  -h, --help                 this text

Under mpirun (`mpirun -np R dacrt render SCENE ...`) the ranks split the samples of every pixel
and rank 0 writes the image, bit for bit one process's; progress and errors come from rank 0, a
rank that fails fails the job. As root OpenMPI wants --allow-run-as-root, more ranks than cores
--oversubscribe; with 2 ranks or fewer it binds each to one core, so give --bind-to none (or
--map-by node:PE=T) when ranks use several threads. Not with --frames, several backends,
--resume, --time-limit, --checkpoint or --adaptive.
)help";

// The render's largest allocations, estimated before any is made: the film, the resolved image
// (and its preview), the path state. Throws Error naming the file and what is too big when they
// exceed the memory this process may still take.
void check_memory(const RenderArgs& r, const Shot& shot) {
  const RenderMemory need = render_memory(shot, r.settings, !r.preview.empty());
  const uint64_t film = need.image, paths = need.paths;
  const uint64_t available = available_memory();
  if (film + paths <= available) return;
  throw Error(r.scene + ": a " + std::to_string(shot.width) + " x " + std::to_string(shot.height) +
              " render needs about " + format_bytes(film + paths) + " (" + format_bytes(film) +
              " for the image, " + format_bytes(paths) + " of path state), more than the " +
              format_bytes(available) + " of memory available");
}

// A float exactly, as C's %a writes it.
std::string format_hex(float v) {
  char text[32];
  std::snprintf(text, sizeof text, "%a", double(v));
  return text;
}

// What parts of one render (--samples ranges) must share to be merged, as EXR attributes
// "match.NAME": the scene's files, the image, the view, the light, how samples are drawn and
// kept. Everything that changes a sample's value is here; the threads, the wavefront and the
// passes are not (they never change a pixel), nor is the backend, but for its intersection test:
// dacrt, dacrt-naive and brute share one and find the same hits bit for bit, Embree's differ in
// the last bits.
std::vector<std::pair<std::string, std::string>> match_keys(const RenderArgs& r, const Shot& shot,
                                                            const std::string& animation,
                                                            const std::string& camera,
                                                            const std::string& inputs_hash,
                                                            const std::string& backend) {
  const RenderSettings& s = r.settings;
  auto real = [](double v) {
    char text[40];
    std::snprintf(text, sizeof text, "%.17g", v);
    return std::string(text);
  };
  std::string environment = "default";
  if (!s.environment_file.empty())
    environment = "map " + s.environment_file;
  else if (s.environment)
    environment = real(s.environment->x) + "," + real(s.environment->y) + "," +
                  real(s.environment->z);
  std::string lights;
  for (const PunctualLight& l : s.lights) lights += (lights.empty() ? "" : "; ") + l.name;
  std::string aovs;
  for (int a = 0; a < aov_count; ++a)
    if (s.aovs.has(Aov(a))) aovs += (aovs.empty() ? "" : ",") + std::string(AovSet::name(Aov(a)));
  const char* sample_environment[] = {"auto", "on", "off"};
  return {{"match.inputs", inputs_hash},
          {"match.gltfScene", std::to_string(r.gltf.scene)},
          {"match.variant", r.gltf.variant},
          {"match.time", r.gltf.time ? real(*r.gltf.time) : "rest pose"},
          {"match.animation", r.gltf.time ? animation : "rest pose"},
          {"match.size", std::to_string(shot.width) + "x" + std::to_string(shot.height)},
          {"match.camera", camera},
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
}

// The view exactly (hexadecimal floats): the camera flags of the header are rounded for reading.
std::string view_text(const Camera& camera) {
  std::string view;
  for (int c = 0; c < 4; ++c)
    for (int k = 0; k < 4; ++k) view += format_hex(camera.to_world[c][k]) + " ";
  return view + format_hex(camera.yfov) + " " + format_hex(camera.ymag) + " " +
         format_hex(camera.znear) + (camera.orthographic ? " orthographic" : " perspective");
}

// The EXR (every channel asked, and the per-pixel counts when they differ: a pass cut short, or
// samples dropped as NaN) and the preview of a film, with the header saying what it holds: `spp`
// is the count every pixel has. The exact sums go with it when it is a part (--samples), is not
// the whole of its range yet (a stop, the time limit, a checkpoint), or --keep-sums asks.
void write_outputs(const RenderArgs& r, const Scene& scene, const Shot& shot, const BackendRun& run,
                   const Film& film, const RenderOutcome& outcome,
                   const std::vector<std::pair<std::string, std::string>>& keys, uint32_t last) {
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
      {"sampleRange", std::to_string(outcome.first) + ":" + std::to_string(outcome.complete)},
      {"samplesPerPixel", samples_per_pixel_text(least, most)},
      {"software", std::string("dacrt ") + version()},
      {"dacrtVersion", version()}};
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
    meta.extra.push_back({"sampleRangeMost", std::to_string(outcome.first) + ":" +
                                                 std::to_string(outcome.most)});
  for (const auto& key : keys) meta.extra.push_back(key);
  const bool exact = r.samples || r.keep_sums || outcome.complete < last;
  write_film_exr(run.output, film, meta, exact);
  if (!run.preview.empty()) write_preview_png(run.preview, film.resolve(), r.display);
}

// With --resume, the film in the output `file` if there is one: its exact sums, checked to be an
// earlier run of the render that `keys` and samples [first, last) describe. Empty (a render from
// the start) when the file does not exist.
std::optional<Film> film_to_resume(const std::string& file, const RenderJob& job,
                                   const std::vector<std::pair<std::string, std::string>>& keys,
                                   uint32_t first, uint32_t last, bool quiet) {
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

int render(const std::vector<std::string>& args) {
  RenderArgs r = parse_render(args);
  if (r.help) return std::fputs(render_help, stdout), 0;
  // Everything an output needs, checked before the scene is loaded: the backends, the integrator,
  // writable and distinct output files that are not inputs, the display transform of a preview.
  const std::vector<std::string> backends = split_list(r.backend);
  if (backends.empty()) throw UsageError("--backend needs at least one backend name");
  if (r.resume && backends.size() > 1)
    throw UsageError("--resume continues one output: one --backend at a time");
  // Under mpirun the ranks split the samples of one image: one frame, one backend, every rank
  // to the end of its share (a pass cut by the clock would leave the shares uneven).
  const bool spread = ranks->size() > 1;
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
    if (!ranks->root()) r.quiet = true;  // progress, notes and the summary from rank 0
  }
  check_render_choices(r, backends);
  std::vector<BackendRun> runs;
  for (const std::string& name : backends) {
    if (std::count(backends.begin(), backends.end(), name) > 1)
      throw UsageError("--backend names " + name + " twice");
    BackendRun run;
    run.backend = name;
    run.output = backends.size() > 1 ? with_backend(r.output, name) : r.output;
    run.preview = backends.size() > 1 ? with_backend(r.preview, name) : r.preview;
    runs.push_back(std::move(run));
  }
  // The frames rendered: one (-1: no number in the names), or FIRST..LAST of --frames, each at
  // time frame / fps with its number in its outputs' names.
  std::vector<int> frames = {-1};
  if (r.frames) {
    frames.clear();
    for (int f = r.frames->first; f <= r.frames->second; ++f) frames.push_back(f);
  }
  auto frame_runs = [&](int frame) {
    std::vector<BackendRun> out = runs;
    if (frame >= 0)
      for (BackendRun& run : out)
        run.output = with_frame(run.output, frame), run.preview = with_frame(run.preview, frame);
    return out;
  };
  // The scene first: a missing one is said before any output of a long sequence is looked at.
  check_input_file(r.scene, "file");
  std::vector<NamedFile> inputs = {{"the scene", r.scene}}, outputs;
  if (!r.settings.environment_file.empty()) {
    check_input_file(r.settings.environment_file, "environment map");
    inputs.push_back({"the environment map", r.settings.environment_file});
  }
  for (int frame : frames)
    for (const BackendRun& run : frame_runs(frame))
      outputs.push_back({"-o", run.output}), outputs.push_back({"--preview", run.preview});
  outputs.push_back({"--stats", r.stats});
  // The report's directory is made when its first file is written, and goes again if the render
  // fails; its files can be checked now only when it is there already.
  std::optional<OutputDirectory> report_dir;
  std::vector<NamedFile> report_files;
  if (!r.report.empty()) {
    report_dir.emplace("--report", r.report);
    report_files.push_back({"--report", HtmlPage::file_in(r.report)});
    for (const BackendRun& run : runs)
      report_files.push_back({"--report", report_preview(r.report, run.backend)});
  }
  if (!r.preview.empty() || !r.report.empty()) {
    set_color_warnings(!r.quiet);
    check_display_transform(r.display);
    for (const std::string& file : display_input_files())
      inputs.push_back({"the display configuration's file", file});
  }
  std::vector<std::string> output_paths;
  for (const NamedFile& out : outputs) output_paths.push_back(out.path);
  check_writable(output_paths);
  for (const NamedFile& out : report_files) {
    if (report_dir->existed()) check_writable(out.path);
    outputs.push_back(out);
  }
  check_outputs(outputs, inputs);

  std::unique_ptr<tbb::global_control> threads;
  if (r.threads > 0)
    threads = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                    size_t(r.threads));

  auto seconds_since = [](std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  auto frame_time = [&](int frame) { return double(frame) / r.fps; };
  if (r.frames) r.gltf.time = frame_time(frames.front());
  auto t_load = std::chrono::steady_clock::now();
  std::optional<GltfAnimation> file(std::in_place, r.scene, r.gltf);
  Scene scene = file->load();
  const std::string animation = file->animation_choice();  // which play (match.animation)
  // One frame is never posed again: the file's buffers (as large as the scene's) go now.
  if (frames.size() == 1) file.reset();
  double load_seconds = seconds_since(t_load);
  for (const FileRead& file : scene.files) inputs.push_back({"the scene's external file", file.path});
  check_outputs(outputs, inputs);
  // The fingerprint of what the image is made from, for merging parts (match.inputs).
  std::vector<FileRead> input_files = {{r.scene, std::nullopt}};
  input_files.insert(input_files.end(), scene.files.begin(), scene.files.end());
  if (!r.settings.environment_file.empty())
    input_files.push_back({r.settings.environment_file, std::nullopt});
  const std::string inputs_hash = hash_text(hash_files(input_files));

  const RenderSettings& s = r.settings;
  // From here on SIGINT and SIGTERM stop the render and write what it has.
  StopOnSignals signals;
  r.passes.stop = &signals.token();
  r.backend_options.threads = r.threads;
  nlohmann::json frame_stats = nlohmann::json::array();
  std::vector<BackendRun> last_runs;
  std::string report_title;
  for (int frame : frames) {
    // A frame's geometry is made in place: the file's scene posed at its time (the first came
    // with the load).
    double geometry_seconds = load_seconds;
    if (frame != frames.front()) {
      const auto t0 = std::chrono::steady_clock::now();
      file->pose(frame_time(frame), scene);
      geometry_seconds = seconds_since(t0);
    }
    const Shot shot = make_shot(scene, s);
    report_title = fs::path(r.scene).filename().string() + ", " + std::to_string(shot.width) +
                   "×" + std::to_string(shot.height) + ", " + std::to_string(s.spp) + " spp, " +
                   s.integrator + " integrator";
    if (frame == frames.front()) {
      check_memory(r, shot);
      if (!r.quiet)
        for (const std::string& note : shot.notes) print_message(note);
    }
    std::vector<BackendRun> runs_now = frame_runs(frame);
    // The samples rendered: every one of the --spp render's, or the --samples range of them.
    const uint32_t first = r.samples ? r.samples->first : 0,
                   last = r.samples ? r.samples->second : uint32_t(s.spp);
    size_t rendered = 0;  // the runs begun: a stop skips the backends after it
    for (BackendRun& run : runs_now) {
      ++rendered;
      const auto t0 = std::chrono::steady_clock::now();
      auto backend =
          Backend::create(run.backend, scene.geometry, r.backend_options.for_plugin(run.backend));
      run.build_seconds = seconds_since(t0);
      RenderJob job(scene, *backend, s, shot);
      if (r.frames) r.gltf.time = frame_time(frame);  // each frame's own time (match.time)
      const auto keys =
          match_keys(r, shot, animation, view_text(shot.camera), inputs_hash, run.backend);
      if (spread) check_ranks_agree(keys);
      std::optional<Film> earlier;
      if (r.resume) earlier = film_to_resume(run.output, job, keys, first, last, r.quiet);
      const bool resuming = earlier.has_value();
      Film film = resuming ? std::move(*earlier) : job.film();
      uint64_t taken = 0;
      for (size_t p = 0; p < film.pixels(); ++p) taken += film.taken(p);
      // This process's samples: all of them, or its rank's share.
      const auto [from, to] = spread ? ranks->share(first, last) : std::pair(first, last);
      Progress progress(backends.size() > 1 ? "render " + run.backend : "render",
                        shot.pixels() * uint64_t(to - from) - taken, !r.quiet);
      const auto checkpoint = [&](const Film& so_far, const RenderOutcome& o) {
        write_outputs(r, scene, shot, run, so_far, o, keys, last);
      };
      RenderOutcome outcome =
          resuming ? job.resume(film, first, last, progress, r.passes, checkpoint)
                   : job.run(film, from, to, progress, r.passes, checkpoint);
      if (spread && !gather_film(film, outcome, first, last)) return 0;
      run.stats = job.stats();
      run.backend_stats = backend->stats();
      run.seconds = seconds_since(t0);
      run.spp = outcome.spp();
      run.least_spp = film.min_count(), run.most_spp = film.max_count();
      run.mean_spp = double(film.total_count()) / double(std::max<size_t>(film.pixels(), 1));
      if (outcome.stopped) run.stopped = signals.signal() == SIGTERM ? "SIGTERM" : "SIGINT";
      if (outcome.timed_out) run.stopped = "the time limit";
      // A render stopped before its first sample leaves the previous outputs as they were.
      if (film.max_count() == 0 && outcome.stopped) break;
      write_outputs(r, scene, shot, run, film, outcome, keys, last);
      if (report_dir) {
        report_dir->make();
        write_preview_png(report_preview(r.report, run.backend), film.resolve(), r.display);
      }
      if (!r.quiet) print_summary(run, shot, s);
      if (outcome.stopped) break;  // the backends after it are not rendered
    }
    runs_now.resize(rendered);
    if (r.frames && !r.quiet) {
      char line[160];
      std::snprintf(line, sizeof line, "frame %d (t = %g s): geometry %.3f ms%s", frame,
                    frame_time(frame), 1e3 * geometry_seconds,
                    frame == frames.front() ? " (the load)" : "");
      std::string text = line;
      for (const BackendRun& run : runs_now) {
        std::snprintf(line, sizeof line, ", %s build %.3f ms", run.backend.c_str(),
                      1e3 * run.build_seconds);
        text += line;
      }
      print_message(text);
    }

    const auto has_samples = [](const BackendRun& run) {
      return run.spp > 0 || run.stopped.empty();
    };
    size_t kept = 0;
    for (const BackendRun& run : runs_now) kept += has_samples(run);
    if (!r.stats.empty() && kept > 0) {
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
        j = describe(runs_now[0]);
      } else {
        j = {{"backends", nlohmann::json::array()}};
        for (const BackendRun& run : runs_now)
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
      write_atomically(r.stats, "statistics",
                       [&](std::ostream& out) { out << json_text(j) << "\n"; });
    }
    last_runs = std::move(runs_now);
    if (signals.signal()) break;
  }
  runs = std::move(last_runs);
  if (signals.signal()) return 128 + signals.signal();
  if (runs.size() > 1) print_comparison(stdout, runs);
  if (report_dir) {
    report_dir->make();
    write_render_report(r.report, report_title, runs);
    report_dir->keep();
  }
  return 0;
}

int info(const std::vector<std::string>& args) {
  if (args.size() == 1 && (args[0] == "-h" || args[0] == "--help")) {
    std::puts("Usage: dacrt info SCENE [--scene INDEX] [--animation NAME|INDEX|all]");
    return 0;
  }
  GltfOptions options;
  const char* usage = "info needs one SCENE, and optionally --scene INDEX and --animation NAME";
  if (args.empty()) throw UsageError(usage);
  if (args[0].size() > 1 && args[0][0] == '-') throw UsageError("info: unknown option " + args[0]);
  for (size_t i = 1; i < args.size(); i += 2) {
    if (args[i] != "--scene" && args[i] != "--animation")
      throw UsageError(args[i].size() > 1 && args[i][0] == '-' ? "info: unknown option " + args[i]
                                                               : std::string(usage));
    if (i + 1 >= args.size()) throw UsageError(args[i] + " needs a value");
    if (args[i] == "--scene")
      options.scene = int(parse_int(args[i], args[i + 1], 0, 1 << 20));
    else if ((options.animation = args[i + 1]).empty())
      throw UsageError("--animation needs a name, an index or all");
  }
  const GltfAnimation file(args[0], options);
  Scene scene = file.load();
  const Geometry& g = scene.geometry;
  const MaterialCounts counts = count_materials(scene);
  Box b = scene.bounds();
  std::printf("scene      %s\n", args[0].c_str());
  std::printf("triangles  %zu", g.size());
  if (scene.degenerate_triangles > 0)
    std::printf(" (%zu more of zero area dropped: no ray can hit them)",
                scene.degenerate_triangles);
  std::printf("\n");
  std::printf("meshes     %zu (%zu triangle primitives, %zu nodes)\n", scene.mesh_count,
              scene.primitive_count, scene.node_count);
  std::printf(
      "materials  %zu (%zu emissive, %zu textured, %zu alpha MASK, %zu alpha BLEND, %zu "
      "transmissive)\n",
      scene.materials.size(), counts.emissive, counts.textured, counts.masked, counts.blended,
      counts.transmissive);
  size_t punctual[3] = {0, 0, 0};
  for (const PunctualLight& l : scene.lights) ++punctual[size_t(l.type)];
  std::printf(
      "lights     %zu emissive triangles, %zu punctual (%zu point, %zu spot, %zu directional)\n",
      counts.emissive_triangles, scene.lights.size(), punctual[0], punctual[1], punctual[2]);
  size_t image_bytes = 0, images = 0;
  for (const TextureImage& i : scene.images) {
    images += i.width > 0;
    image_bytes += i.rgba8.size() + 2 * i.rgba16.size();
  }
  std::printf("images     %zu decoded (%.1f MB), of %zu in the file\n", images,
              double(image_bytes) / 1e6, scene.images.size());
  std::string attributes = "POSITION";
  if (!scene.normals.empty()) attributes += ", NORMAL";
  for (size_t slot = 0; slot < scene.texcoords.size(); ++slot)
    if (!scene.texcoords[slot].empty())
      attributes += ", TEXCOORD_" + std::to_string(scene.texcoord_sets[slot]);
  if (!scene.colors.empty()) attributes += ", COLOR_0";
  if (!scene.tangents.empty()) attributes += ", tangents (from the file or generated)";
  std::printf("attributes %s\n", attributes.c_str());
  const Scene::Ignored& ig = scene.ignored;
  if (ig.ktx2_textures)
    std::printf("ignores    %zu KTX2 textures (rendered from their fallback images)\n",
                ig.ktx2_textures);
  if (ig.sourceless_textures || ig.unknown_lights)
    std::printf("skips      %zu textures without a source image, %zu lights of unknown types\n",
                ig.sourceless_textures, ig.unknown_lights);
  if (ig.untangented_anisotropic)
    std::printf("arbitrary  %zu anisotropic primitives without tangents (no TANGENT, no uvs)\n",
                ig.untangented_anisotropic);
  if (ig.unmorphed_primitives)
    std::printf("unmorphed  %zu primitives' TEXCOORD or COLOR morph targets (base values kept)\n",
                ig.unmorphed_primitives);
  if (!ig.extensions.empty())
    std::printf("not read   %s\n", one_line(ig.unread_extensions()).c_str());
  if (ig.occlusion_textures)
    std::printf(
        "occlusion  %zu materials' occlusion textures left unread (a path tracer computes "
        "occlusion)\n",
        ig.occlusion_textures);
  if (!scene.variants.empty()) {
    std::string names;
    for (const std::string& v : scene.variants) names += (names.empty() ? "" : ", ") + v;
    std::printf("variants   %zu (render --variant NAME): %s\n", scene.variants.size(),
                one_line(names).c_str());
  }
  if (file.animation_count()) {
    std::printf(
        "animation  %zu animations, keyframes to %g s (render --animation NAME|INDEX|all, --time "
        "T, --frames A:B --fps F)\n",
        file.animation_count(), file.end());
    const std::vector<AnimationSummary>& all = file.animations();
    for (size_t a = 0; a < all.size() && a < 1000; ++a) {
      std::string shares;
      for (size_t b : all[a].shares) shares += (shares.empty() ? "" : ", ") + std::to_string(b);
      std::printf(
          "  animation %zu%s: keyframes to %g s%s%s\n", a,
          all[a].name.empty() ? "" : (" \"" + one_line(all[a].name.substr(0, 200)) + "\"").c_str(),
          all[a].end, all[a].plays ? ", plays" : "",
          shares.empty() ? "" : (", animates targets of " + shares + " too").c_str());
    }
    if (all.size() > 1000) std::printf("  ... (%zu in all)\n", all.size());
  }
  std::printf("cameras    %zu%s\n", scene.cameras_from_file,
              scene.cameras_from_file ? "" : " (renders frame the scene's bounds)");
  for (size_t c = 0; c < scene.cameras.size(); ++c) {
    const Camera& cam = scene.cameras[c];
    glm::vec3 p = cam.position();
    const std::string view = cam.orthographic
                                 ? "orthographic, height " + std::to_string(2.f * cam.ymag)
                                 : "yfov " + std::to_string(cam.yfov * 180.0 / M_PI) + "°";
    std::printf("  camera %zu %s: position (%g, %g, %g), %s, aspect %s\n", c,
                cam.name.empty() ? "(unnamed)" : cam.name.c_str(), p.x, p.y, p.z, view.c_str(),
                cam.aspect > 0 ? std::to_string(cam.aspect).c_str() : "from image");
    // The same view as render flags, ready to copy (an orthographic camera's view is perspective
    // with them, as --fov makes it).
    std::printf("    %s", camera_flags(cam, b.empty() ? glm::vec3(0.f) : b.center()).c_str());
    std::printf("\n");
  }
  if (b.empty())
    std::printf("bounds     empty\n");
  else
    std::printf("bounds     (%g, %g, %g) to (%g, %g, %g)\n", b.lo.x, b.lo.y, b.lo.z, b.hi.x, b.hi.y,
                b.hi.z);
  std::string skips;
  auto skip = [&](bool yes, const char* what) {
    if (yes) skips += (skips.empty() ? "" : "; ") + std::string(what);
  };
  skip(!counts.emissive_triangles && scene.lights.empty(),
       "shadow rays (no emitters and no lights; an environment brings them back where it is "
       "sampled: --environment FILE.exr, or a uniform one in an open scene)");
  for (const std::string& what : scene.unused_work()) skip(true, what.c_str());
  std::printf("skips      %s\n", skips.empty() ? "nothing" : skips.c_str());
  return 0;
}

constexpr const char* views_help = R"help(Usage: dacrt views

Lists the display views `dacrt render --preview OUT.png --view NAME` can use, one a line, the
default marked " (default)". With $OCIO set: every DISPLAY/VIEW of that config, from its
scene_linear role (a view of its default display may also be named VIEW alone). Without it: views
built from OpenColorIO's built-in transforms, for an sRGB and a Rec.1886 (gamma 2.4, HD video)
display, each without tone mapping (sRGB, the default, and Rec.1886) and through the ACES 1.0
output transform for SDR video (ACES 1.0 SDR-video (sRGB), ...).
)help";

int views(const std::vector<std::string>& args) {
  if (args.size() == 1 && (args[0] == "-h" || args[0] == "--help"))
    return std::fputs(views_help, stdout), 0;
  if (!args.empty()) throw UsageError("views takes no arguments");
  set_color_warnings(true);  // OpenColorIO's warnings as our one-line messages
  const DisplayViews views = display_views();
  for (const std::string& name : views.names)
    std::printf("%s%s\n", name.c_str(), name == views.default_name ? " (default)" : "");
  return 0;
}

}  // namespace

// A command's exit code, once what it wrote to stdout has reached the file (a full disk, a closed
// pipe, /dev/full: the output is lost, and that is an error).
int flushed(int code) {
  errno = 0;
  std::cout.flush();
  if (std::fflush(stdout) == 0 && !std::ferror(stdout) && std::cout.good()) return code;
  const int err = errno;
  throw Error(std::string("cannot write to standard output") +
              (err ? ": " + std::generic_category().message(err) : std::string()));
}

int run(std::vector<std::string> args) {
  if (args.empty()) {
    std::fputs(main_help, stderr);
    return 2;
  }
  const std::string command = args[0];
  args.erase(args.begin());
  if (command == "-h" || command == "--help" || command == "help") {
    std::fputs(main_help, stdout);
    return 0;
  }
  // Only render's ranks work together; under mpirun any other command runs in every rank alone.
  collectives_over = command != "render";
  if (command == "render") return render(args);
  if (command == "info") return info(args);
  if (command == "views") return views(args);
  if (command == "bench") return bench_main(args);
  if (command == "converge") return converge_main(args);
  if (command == "diff") return diff_main(args);
  if (command == "merge") return merge_main(args);
  throw UsageError("unknown command '" + command + "'");
}

// A message on stderr: one line of at most 1000 characters, whatever it quotes.
int fail(int code, const std::string& prefix, const std::string& what, const std::string& suffix) {
  print_message(prefix + what + suffix);
  return code;
}

int main(int argc, char** argv) {
  // A file-size limit (ulimit -f) makes a write fail with EFBIG, reported as an error, instead of
  // killing the process with SIGXFSZ halfway through a file. Messages and progress on a closed
  // pipe (`dacrt render … 2>&1 | head`) are lost, not fatal: the render goes on and writes its
  // outputs; a lost standard output is reported by flushed().
  std::signal(SIGXFSZ, SIG_IGN);
  std::signal(SIGPIPE, SIG_IGN);
  // Under an MPI launcher: MPI_Init (and MPI_Finalize when main returns); else one process.
  std::optional<Ranks> world;
  try {
    world.emplace(argc, argv);
  } catch (const std::exception& e) {
    return fail(1, "dacrt: error: ", e.what(), "");
  }
  ranks = &*world;
  int code = 0;
  std::string message;
  try {
    return flushed(run(std::vector<std::string>(argv + 1, argv + argc)));
  } catch (const RanksFailed& e) {  // agreed by every rank already
    if (ranks->root()) print_message(e.message);
    return e.code;
  } catch (const UsageError& e) {
    code = 2, message = "dacrt: " + std::string(e.what()) + " (see dacrt --help)";
  } catch (const std::invalid_argument& e) {  // usage errors of `dacrt bench`
    code = 2, message = "dacrt bench: " + std::string(e.what()) + " (see dacrt bench --help)";
  } catch (const SettingError& e) {  // a camera override that cannot make a view
    code = 2, message = "dacrt: " + std::string(e.what()) + " (see dacrt --help)";
  } catch (const Error& e) {
    code = 1, message = "dacrt: error: " + std::string(e.what());
  } catch (const std::bad_alloc&) {
    code = 1, message = "dacrt: error: out of memory";
  } catch (const std::exception& e) {
    code = 1, message = "dacrt: error: " + std::string(e.what());
  }
  // Under mpirun a failure before the films are gathered is the whole job's: every other rank is
  // waiting in gather_film's first collective, which this one joins; rank 0 prints the failure
  // of the lowest failing rank.
  if (ranks->size() > 1 && !collectives_over) {
    const std::string first = ranks->first_error(message);
    if (ranks->root()) print_message(first);
    return code;
  }
  print_message(message);
  return code;
}
