// `dacrt converge`: the command line and the renders at doubling sample counts; the outputs (CSV,
// gnuplot script and plot, the comparison table) are apps/converge_report.cpp's. The metrics, fits
// and interpolations are the library's (render/convergence.h); the render options are `dacrt
// render`'s own parser (apps/render_options.h), so a configuration's `max-depth=8` means what
// `--max-depth 8` means.
#include "studies/converge.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "studies/converge_report.h"
#include "dacrt/render/header.h"
#include "dacrt/render/request.h"
#include "dacrt/render/session.h"
#include "dacrt/util/help_text.h"
#include "dacrt/util/text.h"
#include "dacrt/util/paths.h"
#include "bench/html_page.h"
#include "dacrt/io/exr.h"
#include "dacrt/io/gltf.h"
#include "dacrt/render/convergence.h"
#include "dacrt/render/render_job.h"
#include "dacrt/tracer/backend.h"
#include "dacrt/util/atomic_file.h"
#include "dacrt/util/error.h"
#include "dacrt/util/interrupt.h"
#include "dacrt/util/memory.h"
#include "dacrt/util/paths.h"
#include "dacrt/util/progress.h"
#include "dacrt/util/progress_format.h"

namespace dacrt {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr const char* converge_help = R"help(Usage: dacrt converge SCENE [options] [render options]

Renders each configuration at 1, 2, 4, … samples per pixel until its time budget is spent, and
measures each point's error: run time against error.

Configurations
  --config "KEY=VALUE ..."   one configuration: render options that override the shared ones,
                             KEY a render option's name without its dashes (backend=embree,
                             sampler=independent, integrator=direct, max-depth=8, seed=3,
                             adaptive=0.02, backend-option=dacrt.bins=8, threads=1,
                             wavefront=65536, ...);
                             its label is the text itself ("" is "default"; no line breaks or
                             other control characters). Every configuration is checked (its
                             backend built on no geometry) before anything is rendered, and the
                             CSV and the script are rewritten after each one. Repeatable. Default:
                             "" (dacrt, sobol), "sampler=independent", "backend=embree"
  --time-budget SECONDS      per configuration (default 10): doubling stops when the next point
                             would end past it (its cost predicted from the points so far); the
                             first two points (1 and 2 spp) are always rendered
  --max-spp N                stop at N samples per pixel at most (default 65536)
  --repeats N                render each configuration N times (default 1), repeat i with seed
                             S + 2i (and S + 2i + 1 for --noise): every point is the mean of the
                             N measures, with a 95 % confidence interval (Student t with N - 1
                             degrees of freedom) in the CSV, the plot (shaded) and the tables.
                             The first repeat's doubling sets the points; the others render the
                             same ones. The repeats take turns: each configuration's first, then
                             each one's second, ...
Error
  --reference REF.exr        the converged image (same size as the renders)
  --reference-spp N          without --reference: render one of N >= 2 spp (default 1024) with
                             the shared options (no configuration's) as two halves, seeds
                             S + 2^32 and S + 2^32 + 1, averaged, and keep it as
                             OUTDIR/reference.exr (reuse it with --reference). The halves give
                             the reference's own MSE, mean (a - b)^2 / 4, which is subtracted
                             from every configuration's MSE against it (RMSE and relMSE; clamped
                             at 0) and kept in the EXR (referenceMse, referenceRelmse) for reuse.
                             A --reference without these attributes is used as it is
  --no-reference             no reference: the error is the noise between two seeds
  --noise                    also the noise: every point rendered again with seed S + 1;
                             noise = RMSE(seed S, seed S + 1) / sqrt 2 (the second render's time
                             is not counted). On with --no-reference
  --metric NAME              what the fits, the plot and the table use: rmse (default), relmse,
                             mae, smape, noise (the default with --no-reference)
  --target-error E           the equal-error comparison's level (repeatable; default: the lowest
                             error every configuration reached)
Output
  -o, --output OUTDIR        the directory (default converge-SCENE): convergence.csv (one row per
                             configuration and spp), convergence.gp (the gnuplot script, data
                             inline), convergence.svg and convergence.png (drawn by gnuplot; when
                             gnuplot is missing a warning says so, the rest is written, and the
                             exit code is still 0: `gnuplot convergence.gp` in OUTDIR draws it)
  --no-plot                  write the script, do not run gnuplot
  --quiet                    no progress on stderr
RENDER_OPTIONS

Metrics (on linear radiance, every channel of every pixel, against the reference r):
  RMSE sqrt(mean (x-r)^2), relMSE mean (x-r)^2/(r^2 + 0.01), MAE mean |x-r|,
  SMAPE mean 2|x-r|/(|x|+|r|) (0 where both are 0).
Seconds are cumulative, as a user waits for them: the backend's build and the render of every
sample so far. A configuration whose last point took under 0.1 s gets a warning: times that
short are noisy.
)help";

// The help, with the render options that do not apply and those every configuration shares
// named from the option table.
std::string help_text() {
  std::vector<std::string> not_here, shared_only;
  for (const RenderOption& o : render_options()) {
    if (o.name == "--help") continue;
    const std::string name(o.short_name.empty() ? o.name : o.short_name);
    if (!(o.uses & use_converge))
      not_here.push_back(name);
    else if (!(o.uses & use_config) && o.value != OptionValue::none)
      shared_only.push_back(name);
  }
  auto listed = [](const std::vector<std::string>& names, const char* last) {
    std::string text;
    for (size_t k = 0; k < names.size(); ++k)
      text += (k == 0 ? "" : k + 1 == names.size() ? last : ", ") + names[k];
    return text;
  };
  const std::string paragraph =
      "Render options that apply to every configuration: those of `dacrt render --help` "
      "(--width, --height, --camera, --max-depth, --integrator, --threads, ...) but for " +
      listed(not_here, " and ") + ". Those that change the image itself (" +
      listed(shared_only, ", ") + ") cannot be set per configuration.";
  // The paragraph in lines of at most 100 characters, as the rest of the help.
  std::string lines, line;
  for (size_t at = 0; at < paragraph.size();) {
    const size_t end = std::min(paragraph.find(' ', at), paragraph.size());
    const std::string word = paragraph.substr(at, end - at);
    if (!line.empty() && line.size() + 1 + word.size() > 100) lines += line + "\n", line.clear();
    line += (line.empty() ? "" : " ") + word;
    at = end + 1;
  }
  std::string text = converge_help;
  text.replace(text.find("RENDER_OPTIONS\n"), 15, lines + line + "\n");
  return text;
}


struct Config {
  std::string label;
  RenderRequest args;
};

struct ConvergeArgs {
  RenderRequest shared;
  std::vector<std::string> configs;
  std::string reference, outdir;
  int reference_spp = 1024;
  bool no_reference = false, noise = false, plot = true, help = false;
  std::optional<Metric> metric;
  double budget = 10.0;
  uint32_t max_spp = 1u << 16;
  int repeats = 1;
  std::vector<double> targets;
};

// A --backend-option's key "NAME.key" must name a backend: every backend drops the keys meant for
// another, so a misspelt prefix ("dacr.bins=4", ".bins=4") would be ignored without a word.
void check_backend_option(const std::string& where, const std::string& assignment) {
  const std::string key = assignment.substr(0, assignment.find('='));
  const size_t dot = key.find('.');
  if (dot == std::string::npos) return;
  const std::string prefix = key.substr(0, dot);
  const std::vector<std::string> known = Backend::names();
  if (std::find(known.begin(), known.end(), prefix) != known.end()) return;
  std::string names;
  for (const std::string& n : known) names += (names.empty() ? "" : ", ") + n;
  throw UsageError(where + "--backend-option " + assignment + ": '" + prefix +
                   "' is not a backend (known: " + names + ")");
}

// converge's own options, as its help lists them (the render options of the table come beside
// them).
const std::vector<std::string> converge_options = help_option_names(converge_help);

ConvergeArgs parse_converge(const std::vector<std::string>& given) {
  ConvergeArgs c;
  std::vector<std::string> args = given;
  std::vector<std::string> flags = render_flag_names();
  const std::vector<std::string> own_flags = help_flag_names(converge_help);
  flags.insert(flags.end(), own_flags.begin(), own_flags.end());
  for (size_t i = 0; i < args.size(); ++i) {
    split_option_value(args, i, flags);
    const std::string& a = args[i];
    if (a == "--backend-option" && i + 1 < args.size()) check_backend_option("", args[i + 1]);
    auto value = [&]() -> const std::string& {
      if (i + 1 >= args.size()) throw UsageError(a + " needs a value");
      return args[++i];
    };
    if (a == "-h" || a == "--help") {
      c.help = true;
      return c;
    } else if (a == "--config")
      c.configs.push_back(value());
    else if (a == "--reference")
      c.reference = value();
    else if (a == "--reference-spp")
      c.reference_spp = int(parse_int(a, value(), 2, 1 << 20));  // two halves
    else if (a == "--no-reference")
      c.no_reference = true;
    else if (a == "--noise")
      c.noise = true;
    else if (a == "--metric") {
      const std::string v = value();
      for (int m = 0; m < 5; ++m)
        if (v == metric_keys[m]) c.metric = Metric(m);
      if (!c.metric)
        throw UsageError("--metric wants rmse, relmse, mae, smape or noise, got '" + v + "'");
    } else if (a == "--time-budget")
      c.budget = parse_seconds(a, value());
    else if (a == "--max-spp")
      c.max_spp = uint32_t(parse_int(a, value(), 1, 1 << 20));
    else if (a == "--repeats")
      c.repeats = int(parse_int(a, value(), 1, 1000));
    else if (a == "--target-error")
      c.targets.push_back(parse_seconds(a, value()));
    else if (a == "-o" || a == "--output")
      c.outdir = value();
    else if (a == "--no-plot")
      c.plot = false;
    else if (const RenderOption* o = find_render_option(a); o && !(o->uses & use_converge))
      throw UsageError(a + " does not apply to dacrt converge");
    else if (parse_render_option(args, i, c.shared, use_converge))
      continue;
    else if (!a.empty() && a[0] == '-') {
      std::string hint = did_you_mean(a, converge_options);
      if (hint.empty()) hint = option_suggestion(a, use_converge);
      throw UsageError("unknown option " + a + hint);
    } else if (c.shared.scene.empty())
      c.shared.scene = a;
    else
      throw UsageError("unexpected argument '" + a + "' (one scene at a time)");
  }
  if (c.shared.scene.empty()) throw UsageError("converge needs a SCENE");
  if (!c.reference.empty() && c.no_reference)
    throw UsageError("--reference and --no-reference exclude each other");
  if (c.no_reference) {
    c.noise = true;
    if (c.metric && *c.metric != Metric::noise)
      throw UsageError(std::string("--metric ") + metric_keys[int(*c.metric)] +
                       " needs a reference (drop --no-reference)");
    c.metric = Metric::noise;
  }
  if (c.metric == Metric::noise) c.noise = true;
  if (!c.metric) c.metric = Metric::rmse;
  if (c.outdir.empty()) c.outdir = "converge-" + fs::path(c.shared.scene).stem().string();
  while (c.outdir.size() > 1 && c.outdir.back() == '/') c.outdir.pop_back();
  return c;
}

// A message quotes at most 200 characters of an argument: it stays one readable line.
std::string shortened(const std::string& text) {
  return text.size() <= 200 ? text : text.substr(0, 200) + "...";
}

// Creates the backend on no geometry with the options the render will give it: an unknown name, an
// unknown key or a bad value is a usage error now rather than after the renders before it.
void check_runs(const std::string& where, Options options, int threads, const std::string& name) {
  options.threads = threads;
  try {
    Backend::create(name, Geometry{}, options.for_plugin(name));
  } catch (const Error& e) {
    throw UsageError(where + e.what());
  }
}

// A configuration: the shared options, then "KEY=VALUE ..." through the render option parser.
Config parse_config(const std::string& text, const RenderRequest& shared) {
  Config c{text, shared};
  std::istringstream words(text);
  std::string word;
  const std::string where = "--config \"" + shortened(text) + "\": ";
  // The label goes into the CSV, the gnuplot script and the plot: a line break or another control
  // character in it would end a gnuplot string or a CSV row.
  for (unsigned char ch : text)
    if ((ch < 0x20 && ch != '\t') || ch == 0x7f)
      throw UsageError("--config holds a control character (" + std::to_string(int(ch)) +
                       "): a configuration is one line of printable KEY=VALUE words");
  while (words >> word) {
    const size_t eq = word.find('=');
    if (eq == std::string::npos || eq == 0)
      throw UsageError(where + "'" + shortened(word) + "' is not KEY=VALUE");
    std::string key = word.substr(0, eq);
    if (key.rfind("--", 0) == 0) key = key.substr(2);
    const std::string flag = "--" + key;
    const RenderOption* o = find_render_option(flag);
    if (o && (o->uses & use_converge) && !(o->uses & use_config) && o->value != OptionValue::none)
      throw UsageError(where + key + " changes the image, which every configuration shares: give " +
                       flag + " before the configurations");
    if (o && !(o->uses & use_converge))
      throw UsageError(where + key + " does not apply to dacrt converge");
    if (key == "backend-option") check_backend_option(where, word.substr(eq + 1));
    const std::vector<std::string> option = {flag, word.substr(eq + 1)};
    size_t i = 0;
    bool known = false;
    try {
      known = parse_render_option(option, i, c.args, use_config) && i == 1;
    } catch (const UsageError& e) {
      throw UsageError(where + e.what());
    }
    if (!known)
      throw UsageError(where + "unknown key '" + shortened(key) + "' (see dacrt render --help)");
  }
  words.clear();
  c.label = text;
  c.label.erase(0, c.label.find_first_not_of(" \t"));
  c.label.erase(c.label.find_last_not_of(" \t") + 1);
  if (c.label.empty()) c.label = "default";
  const std::vector<std::string> backends = split_list(c.args.backend);
  if (backends.size() != 1)
    throw UsageError(where + "a configuration renders with one backend (give one --config each)");
  check_integrator(c.args.settings.integrator);
  try {
    check_adaptive(c.args.settings);
  } catch (const UsageError& e) {
    throw UsageError(where + e.what());
  }
  check_runs(where, c.args.backend_options, c.args.threads, backends[0]);
  return c;
}

std::vector<Config> parse_configs(const ConvergeArgs& c) {
  std::vector<std::string> texts = c.configs;
  if (texts.empty()) {
    texts = {"", "sampler=independent"};
    const std::vector<std::string> known = Backend::names();
    if (std::find(known.begin(), known.end(), "embree") != known.end())
      texts.push_back("backend=embree");
  }
  if (c.reference.empty() && !c.no_reference) {  // the reference's render: the shared options
    const std::vector<std::string> backends = split_list(c.shared.backend);
    check_integrator(c.shared.settings.integrator);
    check_runs("the reference (the shared options): ", c.shared.backend_options, c.shared.threads,
               backends.empty() ? "dacrt" : backends[0]);
  }
  std::vector<Config> configs;
  std::set<std::string> labels;
  for (const std::string& text : texts) {
    configs.push_back(parse_config(text, c.shared));
    if (!labels.insert(configs.back().label).second)
      throw UsageError("--config \"" + shortened(text) + "\" is given twice");
  }
  return configs;
}

// The largest allocations of the renders, estimated before any is made (as `dacrt render` does):
// a configuration's film and path state, twice with --noise, beside the reference image. Throws
// Error when they exceed the memory this process may still take.
void check_memory(const ConvergeArgs& a, const std::vector<Config>& configs, const Shot& shot) {
  const RenderMemory reference = render_memory(shot, a.shared.settings, false);
  // The reference's render beside its first half's image and, once both are done, their mean.
  const uint64_t rgb = uint64_t(shot.pixels()) * 3 * sizeof(float);
  uint64_t need = reference.image + reference.paths + 2 * rgb;
  for (const Config& c : configs) {
    const RenderMemory m = render_memory(shot, c.args.settings, false);
    need = std::max(need, (a.noise ? 2 : 1) * (m.image + m.paths) + reference.image);
  }
  const uint64_t available = available_memory();
  if (need <= available) return;
  throw Error(a.shared.scene + ": converge's " + std::to_string(shot.width) + " x " +
              std::to_string(shot.height) + " renders need about " + format_bytes(need) +
              ", more than the " + format_bytes(available) + " of memory available");
}

// A reference with a NaN or an infinite value would make every error NaN or infinite.
void check_finite(const std::string& path, const Image& image) {
  if (const std::optional<std::string> where = first_non_finite(image))
    throw Error(path + ": the reference's " + *where + ": a reference must be finite everywhere");
}

// The reference's own error, kept in the EXR that converge renders so that a later
// `--reference` of it subtracts the same; a reference from elsewhere has none.
constexpr const char* reference_mse_key = "referenceMse";
constexpr const char* reference_relmse_key = "referenceRelmse";

std::optional<ReferenceError> stored_reference_error(const std::string& path) {
  const std::map<std::string, std::string> attributes = read_exr_file(path).attributes;
  auto number = [&](const char* key) -> std::optional<double> {
    const auto it = attributes.find(key);
    if (it == attributes.end()) return std::nullopt;
    char* end = nullptr;
    const double v = std::strtod(it->second.c_str(), &end);
    if (it->second.empty() || *end != '\0' || !std::isfinite(v) || v < 0)
      throw Error(path + ": the reference's " + key + " '" + shortened(it->second) +
                  "' is not a non-negative number");
    return v;
  };
  const std::optional<double> mse = number(reference_mse_key),
                              relmse = number(reference_relmse_key);
  if (!mse || !relmse) return std::nullopt;
  return ReferenceError{*mse, *relmse};
}

std::optional<std::string> find_in_path(const std::string& program) {
  const char* path = std::getenv("PATH");
  std::istringstream dirs(path ? path : "");
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    const std::string candidate = (dir.empty() ? std::string(".") : dir) + "/" + program;
    if (::access(candidate.c_str(), X_OK) == 0 && fs::is_regular_file(candidate)) return candidate;
  }
  return std::nullopt;
}

// The render settings a configuration's job runs with (seed offset for the second-seed render).
struct Run {
  std::unique_ptr<Backend> backend;
  std::unique_ptr<RenderJob> job;
  std::optional<Film> film;
};

Run start_run(const Scene& scene, const Shot& shot, const Config& c, uint64_t seed) {
  Run run;
  RenderSettings s = c.args.settings;
  s.seed = seed;
  Options options = c.args.backend_options;
  options.threads = c.args.threads;
  const std::string name = split_list(c.args.backend)[0];
  run.backend = Backend::create(name, scene.geometry, options.for_plugin(name));
  run.job = std::make_unique<RenderJob>(scene, *run.backend, s, shot);
  run.film.emplace(run.job->film());
  return run;
}

// Adds samples up to `spp` to the run's film, its progress on stderr unless `quiet` (`part`: of
// what); false when a signal stopped it.
bool render_to(Run& run, uint32_t from, uint32_t spp, const std::string& label, bool quiet,
               const ProgressPart& part, const std::atomic<bool>* stop, double* seconds) {
  const uint64_t pixels = run.job->shot().pixels();
  ProgressTimes times;
  times.tenths = false;  // a log hears of the renders that take a while, and each point's line
  Progress progress(label, pixels * spp, !quiet, part, pixels, ProgressOutput::standard_error(),
                    times);
  PassOptions passes;
  passes.stop = stop;
  const RenderOutcome outcome = run.job->run(*run.film, from, spp, progress, passes);
  if (seconds) *seconds = outcome.seconds;
  return !outcome.stopped;
}

// Where the outputs go: OUTDIR's files, checked before anything is rendered.
struct ConvergeFiles {
  fs::path outdir;
  bool outdir_exists = false, render_reference = false;
  std::string csv, script, svg, png, reference_out, page;
  std::vector<NamedFile> inputs, outputs;
};

ConvergeFiles check_files(const ConvergeArgs& a) {
  check_input_file(a.shared.scene, "scene");
  if (!a.reference.empty()) check_input_file(a.reference, "reference");
  if (!a.shared.settings.environment_file.empty())
    check_input_file(a.shared.settings.environment_file, "environment map");
  ConvergeFiles f;
  f.outdir = a.outdir;
  std::error_code ec;
  f.outdir_exists = fs::exists(f.outdir, ec);
  if (f.outdir_exists && !fs::is_directory(f.outdir, ec))
    throw Error(a.outdir + ": cannot write the outputs there: it is not a directory");
  if (!f.outdir_exists && fs::is_symlink(fs::symlink_status(f.outdir, ec)))
    throw Error(a.outdir + ": cannot write the outputs there: it is a symbolic link to " +
                fs::read_symlink(f.outdir, ec).string() + ", which does not exist");
  f.csv = (f.outdir / "convergence.csv").string();
  f.script = (f.outdir / "convergence.gp").string();
  f.svg = (f.outdir / "convergence.svg").string();
  f.png = (f.outdir / "convergence.png").string();
  f.reference_out = (f.outdir / "reference.exr").string();
  f.page = HtmlPage::file_in(a.outdir);
  f.render_reference = a.reference.empty() && !a.no_reference;
  if (f.outdir_exists) {
    for (const std::string& out : {f.csv, f.script, f.svg, f.png, f.page}) check_writable(out);
    if (f.render_reference) check_writable(f.reference_out);
  } else {
    check_writable(a.outdir);  // its parent is a writable directory
  }
  f.inputs = {{"the scene", a.shared.scene},
              {"--reference", a.reference},
              {"--environment", a.shared.settings.environment_file}};
  f.outputs = {{"-o", f.csv}, {"-o", f.script}, {"-o", f.svg}, {"-o", f.png}, {"-o", f.page}};
  if (f.render_reference) f.outputs.push_back({"-o", f.reference_out});
  check_outputs(f.outputs, f.inputs);
  return f;
}

// A warning: into `said` for a library, else a line on stderr.
void warn(ConvergeSaid* said, const std::string& message) {
  if (said)
    said->warnings.push_back(message);
  else
    std::fprintf(stderr, "dacrt converge: warning: %s\n", message.c_str());
}

// The reference and its own error: given (--reference), or rendered as two independent halves,
// averaged (their difference measures the reference's own noise) and written to OUTDIR. False
// when a stop came first.
struct Reference {
  std::optional<Image> image;
  std::optional<ReferenceError> error;
};

bool render_reference(const ConvergeArgs& a, const ConvergeFiles& f, const Scene& scene,
                      const Shot& shot, const std::atomic<bool>* stop, Reference& out) {
  const RenderSettings& base = a.shared.settings;
  const bool verbose = !a.shared.quiet;
  Config shared{"reference", a.shared};
  shared.args.settings.adaptive = 0.0;  // the reference samples every pixel alike
  shared.args.settings.adaptive_min = 0;
  shared.args.backend =
      split_list(a.shared.backend).empty() ? "dacrt" : split_list(a.shared.backend)[0];
  const uint64_t seed = base.seed + (uint64_t(1) << 32);
  const uint32_t halves[2] = {uint32_t(a.reference_spp) / 2,
                              uint32_t(a.reference_spp) - uint32_t(a.reference_spp) / 2};
  if (verbose)
    std::fprintf(stderr,
                 "converge: rendering the reference: %d spp as two halves, %s, sampler %s, "
                 "seeds %llu and %llu (--reference-spp, or --reference REF.exr)\n",
                 a.reference_spp, shared.args.backend.c_str(), sampler_name(base.sampler).c_str(),
                 (unsigned long long)seed, (unsigned long long)seed + 1);
  std::vector<Image> images;
  double seconds = 0;
  ProgressPart part;  // the halves' lines give the whole reference's ETA
  part.whole_start = ProgressOutput::standard_error().now();
  for (int h = 0; h < 2; ++h) {
    Run run = start_run(scene, shot, shared, seed + h);
    double step = 0;
    part.position = "(half " + std::to_string(h + 1) + " of 2)";
    part.before = h ? double(halves[0]) / a.reference_spp : 0.0;
    part.share = double(halves[h]) / a.reference_spp;
    if (!render_to(run, 0, halves[h], "converge: reference", !verbose, part, stop, &step))
      return false;
    seconds += step;
    images.push_back(run.film->resolve());
  }
  SplitReference split = combine_halves(images[0], images[1]);
  out.image = std::move(split.image);
  out.error = split.error;
  if (!f.outdir_exists) fs::create_directories(f.outdir);
  ExrMetadata meta;
  meta.spp = a.reference_spp;
  meta.backend = shared.args.backend;
  meta.integrator = base.integrator;
  meta.render_seconds = seconds;
  meta.extra = {
      {"scene", a.shared.scene},
      {"sampler", sampler_name(base.sampler)},
      {"seed", std::to_string(seed)},
      {"referenceHalves", std::to_string(halves[0]) + " spp with seed " + std::to_string(seed) +
                              " and " + std::to_string(halves[1]) + " spp with seed " +
                              std::to_string(seed + 1) + ", averaged"},
      {reference_mse_key, format("%.9g", split.error.mse)},
      {reference_relmse_key, format("%.9g", split.error.relmse)},
      software_attribute()};
  write_exr(f.reference_out, *out.image, meta);
  if (verbose)
    std::fprintf(stderr, "converge: reference: %d spp in %.3g s, its own MSE %.3g, %s\n",
                 a.reference_spp, seconds, split.error.mse, f.reference_out.c_str());
  return true;
}

// One configuration's run (its `repeat`-th): renders of 1, 2, 4, ... spp until the time budget
// or --max-spp (the first repeat's doubling sets the points, the others render the same ones),
// each measured against the reference and/or the noise between two seeds, into `curve`.
void measure(const ConvergeArgs& a, const Config& c, int repeat, const Scene& scene,
             const Shot& shot, const Reference& reference, const std::string& position,
             const std::atomic<bool>* stop, Curve& curve) {
  const Metric metric = *a.metric;
  const std::string suffix = a.repeats > 1 ? " (repeat " + std::to_string(repeat + 1) + "/" +
                                                 std::to_string(a.repeats) + ")"
                                           : std::string();
  const uint64_t seed = c.args.settings.seed + 2 * uint64_t(repeat);
  const auto own_threads =
      thread_limit(c.args.threads != a.shared.threads ? c.args.threads : 0);
  const auto t0 = Clock::now();
  Run run = start_run(scene, shot, c, seed);
  const double setup_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  std::optional<Run> second;
  if (a.noise) second = start_run(scene, shot, c, seed + 1);
  double rendered = 0;  // the render seconds of the samples so far
  uint32_t spp = 0;
  for (uint32_t next = 1, index = 0;; next *= 2, ++index) {
    if (repeat > 0 && index >= curve.points.size()) break;
    const std::string label = "converge " + c.label + suffix + ": " + std::to_string(next) + " spp";
    ProgressPart part;
    part.position = position;
    double step = 0;
    if (!render_to(run, spp, next, label, a.shared.quiet, part, stop, &step)) break;
    if (second && !render_to(*second, spp, next, label + " (seed S + 1)", a.shared.quiet, part,
                             stop, nullptr))
      break;
    spp = next;
    rendered += step;
    Measure m;
    m.seconds = setup_seconds + rendered;
    const Image image = run.film->resolve();
    if (reference.image) {
      m.raw = image_error(image, *reference.image);
      m.error = reference.error ? without_reference_error(*m.raw, *reference.error) : *m.raw;
    }
    if (second) m.noise = noise_from_seeds(image, second->film->resolve());
    if (repeat == 0)
      curve.points.push_back({spp, {m}});
    else
      curve.points[index].repeats.push_back(m);
    if (!a.shared.quiet)
      std::fprintf(stderr, "converge %s%s: %u spp, %.3g s, %s %.4g\n", c.label.c_str(),
                   suffix.c_str(), spp, m.seconds, metric_names[int(metric)],
                   value_of(m, metric).value_or(NAN));
    // Doubling renders as many samples again: it costs about what the samples so far cost.
    if (repeat == 0 &&
        (spp >= a.max_spp || (curve.points.size() >= 2 && m.seconds + rendered > a.budget)))
      break;
  }
}

// The plot, the summary on stdout and in the page, and the closing lines.
void finish(const ConvergeArgs& a, const ConvergeFiles& f, const std::vector<Curve>& curves,
            const Reference& reference, const std::optional<std::string>& gnuplot,
            const std::string& title, ConvergeSaid* said) {
  if (gnuplot) draw_plot(*gnuplot, fs::absolute(f.script).string(), f.svg, f.png);
  for (const std::string& w : short_run_warnings(curves)) warn(said, w);
  // The summary goes to stdout and into the page.
  char* text = nullptr;
  size_t size = 0;
  std::FILE* summary = open_memstream(&text, &size);
  if (!summary) throw Error(std::string("cannot make the summary: ") + std::strerror(errno));
  if (reference.image)
    print_reference(summary, a.reference.empty() ? f.reference_out : a.reference, reference.error);
  print_table(summary, curves, *a.metric, a.targets);
  std::fclose(summary);
  const std::string summary_text(text, size);
  std::free(text);
  if (!said) std::fputs(summary_text.c_str(), stdout);
  write_page(a.outdir, title, curves, *a.metric, summary_text, gnuplot ? f.svg : std::string());
  if (!a.shared.quiet && !said) {
    std::fprintf(stderr, "converge: wrote %s, %s, %s", f.page.c_str(), f.csv.c_str(),
                 f.script.c_str());
    if (gnuplot) std::fprintf(stderr, ", %s, %s", f.svg.c_str(), f.png.c_str());
    std::fprintf(stderr, "\n");
  }
  if (a.plot && !gnuplot)
    warn(said, "no plot: gnuplot is not on PATH (install gnuplot-nox, then run `gnuplot "
               "convergence.gp` in " + a.outdir + ")");
}

// The command; `said` (a library's call) takes its warnings and notes, and stdout stays empty.
int run_converge(const std::vector<std::string>& args, ConvergeSaid* said) {
  ConvergeArgs a = parse_converge(args);
  if (a.help) {
    if (said) throw UsageError("converge: --help is the command line's");
    return std::fputs(help_text().c_str(), stdout), 0;
  }
  std::vector<Config> configs = parse_configs(a);
  const bool verbose = !a.shared.quiet;
  ConvergeFiles f = check_files(a);
  std::optional<std::string> gnuplot;
  if (a.plot) {
    gnuplot = find_in_path("gnuplot");
    if (!gnuplot)
      warn(said, "gnuplot is not on PATH: the CSV and the script are written, the plot is not "
                 "(install gnuplot-nox)");
  }
  Reference reference;
  if (!a.reference.empty()) {
    reference.image = read_exr(a.reference);
    check_finite(a.reference, *reference.image);
    reference.error = stored_reference_error(a.reference);
  }

  const auto threads = thread_limit(a.shared.threads);
  Activity loading("converge: loading " + a.shared.scene, verbose);
  Scene scene = load_gltf(a.shared.scene, a.shared.gltf);
  loading.done("converge: loaded " + a.shared.scene + " in " + format_duration(loading.seconds()));
  for (const FileRead& file : scene.files) f.inputs.push_back({"the scene's external file", file.path});
  check_outputs(f.outputs, f.inputs);
  // Every configuration renders the same shot (the options that change it are the shared ones).
  const Shot shot = make_shot(scene, a.shared.settings);
  if (said)
    said->warnings.insert(said->warnings.end(), shot.notes.begin(), shot.notes.end());
  else if (verbose)
    for (const std::string& note : shot.notes) std::fprintf(stderr, "%s\n", note.c_str());
  const std::optional<Image>& given = reference.image;
  if (given && (given->width != shot.width || given->height != shot.height))
    throw Error(a.reference + ": the reference is " + std::to_string(given->width) + " x " +
                std::to_string(given->height) + ", the renders are " +
                std::to_string(shot.width) + " x " + std::to_string(shot.height) +
                " (give --width " + std::to_string(given->width) + " --height " +
                std::to_string(given->height) + ", or another reference)");
  check_memory(a, configs, shot);

  StopOnSignals signals;
  const std::atomic<bool>* stop = &signals.token();
  if (f.render_reference && !render_reference(a, f, scene, shot, stop, reference))
    return 128 + signals.signal();

  const Metric metric = *a.metric;
  const std::string title = fs::path(a.shared.scene).filename().string() + ", " +
                            std::to_string(shot.width) + " x " + std::to_string(shot.height) +
                            ": " + metric_names[int(metric)] + " against time";
  std::vector<Curve> curves;
  for (const Config& c : configs) curves.push_back({c.label, {}});
  // The CSV and the script hold every point measured so far: written after each configuration's
  // run, and before an error of a later one ends the command, so that it loses none of them.
  auto measured = [&] {
    std::vector<Curve> all;
    for (const Curve& c : curves)
      if (!c.points.empty()) all.push_back(c);
    return all;
  };
  auto write_so_far = [&] {
    const std::vector<Curve> all = measured();
    if (all.empty()) return;
    if (!fs::exists(f.outdir)) fs::create_directories(f.outdir);
    write_csv(f.csv, all, reference.error);
    write_script(f.script, all, metric, title);
  };
  // On an error: the points so far are kept if they can be, the error (one line) is the
  // command's. Out of memory, the write may fail too: the original error is the one to report.
  auto keep_so_far = [&] {
    try {
      write_so_far();
      return !measured().empty();
    } catch (...) {
      return false;
    }
  };
  // Repeat-major order: a configuration's repeats are spread over the run, so that a slow spell
  // of a shared machine falls on every configuration rather than on one.
  for (int repeat = 0; repeat < a.repeats && !signals.signal(); ++repeat)
    for (size_t k = 0; k < configs.size() && !signals.signal(); ++k) {
      try {
        const std::string position = "(configuration " + std::to_string(k + 1) + " of " +
                                     std::to_string(configs.size()) + ")";
        if (verbose)
          std::fprintf(stderr, "converge: configuration %zu of %zu: %s%s\n", k + 1, configs.size(),
                       configs[k].label.c_str(),
                       a.repeats > 1 ? (", repeat " + std::to_string(repeat + 1) + " of " +
                                        std::to_string(a.repeats))
                                           .c_str()
                                     : "");
        measure(a, configs[k], repeat, scene, shot, reference, position, stop, curves[k]);
      } catch (const Error& e) {
        const bool kept = keep_so_far();
        throw Error("--config \"" + shortened(configs[k].label) + "\": " + e.what() +
                    (kept ? " (the points so far are in " + f.csv + ")" : ""));
      } catch (...) {
        keep_so_far();
        throw;
      }
      write_so_far();
    }
  curves = measured();
  if (!curves.empty()) finish(a, f, curves, reference, gnuplot, title, said);
  if (signals.signal()) return 128 + signals.signal();
  return 0;
}

}  // namespace

int converge_main(const std::vector<std::string>& args) { return run_converge(args, nullptr); }

int converge_for_library(const std::vector<std::string>& args, ConvergeSaid& said) {
  return run_converge(args, &said);
}

}  // namespace dacrt
