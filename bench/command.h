// bench_command: `dacrt bench` from its arguments to its table (on `out`) and its JSON file. The
// CLI's bench_main calls it with std::cout; the tests call it directly with a string stream.
#pragma once

#include <tbb/global_control.h>
#include <tbb/task_arena.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include "bench/args.h"
#include "bench/report.h"
#include "bench/run.h"
#include "io/gltf.h"
#include "util/atomic_file.h"
#include "util/error.h"
#include "util/paths.h"

namespace dacrt::bench {

// Bad --backend-option keys or values are usage errors: found by building each backend that takes
// them on empty geometry, before the scene is loaded.
inline void check_backend_options(const BenchArgs& a) {
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

inline int bench_command(const std::vector<std::string>& argv, std::ostream& out) {
  const BenchArgs a = parse_bench_args(argv);
  if (a.help) {
    out << bench_help();
    return 0;
  }
  check_backend_options(a);
  check_writable(a.json);
  check_outputs({{"--json", a.json}}, {{"the scene", a.scene}});

  std::unique_ptr<tbb::global_control> threads;
  if (a.threads > 0)
    threads = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                    size_t(a.threads));

  const Scene scene = load_gltf(a.scene);
  if (scene.geometry.size() == 0) throw Error(a.scene + ": no triangles to benchmark");

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

  print_table(out, report);
  out.flush();
  if (!a.json.empty())
    write_atomically(a.json, "benchmark results",
                     [&](std::ofstream& f) { f << to_json(report).dump(2) << "\n"; });
  return 0;
}

}  // namespace dacrt::bench
