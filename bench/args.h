// BenchArgs: the options of `dacrt bench`, their parsing and their --help text. Usage errors throw
// std::invalid_argument with a one-line message; the CLI turns them into exit code 2.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "bench/rays.h"
#include "dacrt/tracer/options.h"

namespace dacrt::bench {

// The help with the dacrt backends' option keys filled in, wrapped to the text's width.
std::string bench_help();

enum class Sweep { none, rays, triangles };

struct BenchArgs {
  std::string scene, json;
  std::string report;  // --report DIR: DIR/index.html
  std::vector<BenchRay> rays;
  std::vector<std::string> backends;
  std::optional<int> width, height;
  std::optional<size_t> count;
  int repeat = 5;
  int threads = 0;  // 0 = all cores
  Options backend_options;
  bool has_backend_options = false;
  Sweep sweep = Sweep::none;
  uint64_t seed = 0;
  bool tmax_at_hit = false;
  bool quiet = false;
  bool help = false;
  // A library's call (Python's bench()): its warnings go here rather than on stderr.
  std::vector<std::string>* warnings = nullptr;
};

// Backends that --backend-option applies to.
inline bool takes_backend_options(std::string_view backend) {
  return backend == "dacrt" || backend == "dacrt-naive";
}

// The backends `dacrt bench` runs when --backends is not given: every registered one but the
// brute-force oracle, which would take hours on a real scene.
std::vector<std::string> default_bench_backends();

BenchArgs parse_bench_args(const std::vector<std::string>& args);

}  // namespace dacrt::bench
