// BenchReport: what `dacrt bench` found, as a Markdown table (stdout) and as JSON (--json).
// Speed-ups are ratios of trace seconds measured in the same run against one baseline backend.
#pragma once

#include <cstddef>
#include <cstdint>
#include <iosfwd>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "bench/args.h"
#include "bench/run.h"

namespace dacrt::bench {

struct BenchReport {
  std::string scene;
  size_t triangles = 0;  // of the scene as loaded
  int threads = 0;
  int repeat = 0;
  uint64_t seed = 0;
  bool tmax_at_hit = false;
  Sweep sweep = Sweep::none;
  std::string reference;  // whose primary hits seeded the secondary rays
  std::string baseline;   // the "vs" column's backend; empty when there is none
  std::vector<Result> results;
};

// embree when benchmarked (our yardstick), else dacrt-naive (what ray sampling is measured
// against), else none.
std::string choose_baseline(const std::vector<std::string>& backends);

void print_table(std::ostream& out, const BenchReport& report);

// The contract: {"scene", "triangles", "threads", "results": [{"backend", "rays", "count",
// "build_s", "trace_s", "mrays_per_s", "mrays_per_s_with_build", "peak_mb"}]}, plus extra fields.
nlohmann::ordered_json to_json(const BenchReport& report);

}  // namespace dacrt::bench
