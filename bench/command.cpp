#include "bench/command.h"

#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cstdint>
#include <glm/glm.hpp>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <stdexcept>

#include "bench/args.h"
#include "bench/html_page.h"
#include "bench/report.h"
#include "bench/run.h"
#include "dacrt/io/gltf.h"
#include "dacrt/scene/camera.h"
#include "dacrt/scene/scene.h"
#include "dacrt/tracer/backend.h"
#include "dacrt/tracer/dacrt/dacrt.h"
#include "dacrt/util/atomic_file.h"
#include "dacrt/util/error.h"
#include "dacrt/util/memory.h"
#include "dacrt/util/paths.h"
#include "dacrt/util/text.h"

namespace dacrt::bench {

namespace {

// Bad --backend-option keys or values are usage errors: found by building each backend that takes
// them on empty geometry, before the scene is loaded.
void check_backend_options(const BenchArgs& a) {
  if (!a.has_backend_options) return;
  static const Geometry empty;
  for (const auto& name : a.backends) {
    if (!takes_backend_options(name)) continue;
    try {
      Backend::create(name, empty, a.backend_options);
    } catch (const Error& e) {
      throw std::invalid_argument(std::string("--backend-option: ") + e.what());
    }
  }
}

// Whether the rays of every case fit in memory, known before any is made: the primary batch with
// its hits and surface points, one more batch of each ray type with its hits, and what dacrt keeps
// per ray and triangle (dacrt_memory_bound). Throws a usage error naming the options that ask for
// too much.
void check_bench_memory(const BenchArgs& a, const std::vector<BenchCase>& cases) {
  constexpr uint64_t ray = 8 * sizeof(float) + sizeof(uint32_t), hit = 4 * sizeof(float),
                     point = 7 * sizeof(float);
  const uint64_t available = available_memory();
  for (const BenchCase& c : cases) {
    const Camera& camera = c.scene->cameras.at(0);
    const glm::ivec2 res = primary_resolution(a, c.count, camera.aspect, c.scene->path);
    const uint64_t primary = uint64_t(res.x) * uint64_t(res.y);
    const uint64_t batch = std::max<uint64_t>(primary, c.count.value_or(primary));
    const uint64_t need = primary * (ray + hit + point) + batch * (ray + hit) +
                          dacrt_memory_bound(batch, c.scene->geometry.size());
    if (need <= available) continue;
    const std::string asked = a.width || a.height ? "--width/--height (" + std::to_string(res.x) +
                                                        " x " + std::to_string(res.y) + ")"
                                                  : "--count " + std::to_string(batch);
    throw std::invalid_argument(asked + " asks for " + std::to_string(batch) + " rays, about " +
                                format_bytes(need) + " of rays, hits and records, more than the " +
                                format_bytes(available) + " of memory available");
  }
}

}  // namespace

BenchReport bench_report(const BenchArgs& a, const std::vector<NamedFile>& outputs) {
  check_backend_options(a);
  std::unique_ptr<tbb::global_control> threads;
  if (a.threads > 0)
    threads = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                    size_t(a.threads));

  const Scene scene = load_gltf(a.scene);
  if (scene.geometry.size() == 0) throw Error(a.scene + ": no triangles to benchmark");
  std::vector<NamedFile> inputs = {{"the scene", a.scene}};
  for (const FileRead& file : scene.files) inputs.push_back({"the scene's external file", file.path});
  check_outputs(outputs, inputs);

  // The cases: the scene once, or one per size of the sweep.
  std::vector<Scene> decimated;
  std::vector<BenchCase> cases;
  if (a.sweep == Sweep::rays) {
    for (int e = 14; e <= 22; ++e) cases.push_back({&scene, 1, size_t(1) << e});
  } else if (a.sweep == Sweep::triangles) {
    decimated.reserve(6);
    for (size_t k = 1; k <= 32; k *= 2) {
      const Scene* s = &scene;
      if (k > 1) s = &decimated.emplace_back(decimate(scene, k));
      if (s->geometry.size() > 0) cases.push_back({s, k, a.count});
    }
  } else {
    cases.push_back({&scene, 1, a.count});
  }

  check_bench_memory(a, cases);

  BenchReport report;
  report.scene = a.scene;
  report.triangles = scene.geometry.size();
  report.threads = int(std::min<size_t>(
      size_t(tbb::this_task_arena::max_concurrency()),
      tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism)));
  report.repeat = a.repeat;
  report.seed = a.seed;
  report.tmax_at_hit = a.tmax_at_hit;
  report.sweep = a.sweep;
  report.reference = reference_backend(a);
  report.baseline = choose_baseline(a.backends);

  BenchRunner runner(a, cases.size());
  for (const BenchCase& c : cases) runner.run(c);
  runner.finish();
  report.results = runner.results();
  // A sweep reads as one scaling curve per ray type: group the rows by type, sizes in order.
  std::stable_sort(report.results.begin(), report.results.end(),
                   [](const Result& x, const Result& y) { return x.rays < y.rays; });
  return report;
}

int bench_command(const std::vector<std::string>& argv, std::ostream& out) {
  const BenchArgs a = parse_bench_args(argv);
  if (a.help) {
    out << bench_help();
    return 0;
  }
  std::vector<NamedFile> outputs = {{"--json", a.json}};
  check_writable(a.json);
  // The report's directory is made when the report is written, and goes again if that fails;
  // its page can be checked now only when it is there already.
  std::optional<OutputDirectory> report_dir;
  if (!a.report.empty()) {
    report_dir.emplace("--report", a.report);
    if (report_dir->existed()) check_writable(HtmlPage::file_in(a.report));
    outputs.push_back({"--report", HtmlPage::file_in(a.report)});
  }
  check_outputs(outputs, {{"the scene", a.scene}});

  const BenchReport report = bench_report(a, outputs);
  print_table(out, report);
  out.flush();
  if (!a.json.empty())
    write_atomically(a.json, "benchmark results",
                     [&](std::ostream& f) { f << json_text(to_json(report)) << "\n"; });
  if (report_dir) {
    report_dir->make();
    write_report(a.report, report);
    report_dir->keep();
  }
  return 0;
}

}  // namespace dacrt::bench
