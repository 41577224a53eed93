// BenchReport: what `dacrt bench` found, as a Markdown table (stdout) and as JSON (--json).
// Every figure is the median of the timed runs with its confidence interval
// (util/median_interval.h). Speed-ups (higher is faster) are the baseline backend's trace seconds
// over the row's, repeat by repeat (the runs of one repeat follow each other, so they share the
// machine's mood), then their median.
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

// The speed-up of each repeat, in the order of the runs; empty without a baseline.
std::vector<double> speedup_runs(const BenchReport& report, const Result& r);

// How the figures were made, one phrase for the table's caption and the JSON's "method": the
// runs, the warm-up, the interval and its coverage.
std::string method_text(int repeat);

// The speed-up column's header, naming its convention: "speed-up vs embree, higher is faster".
std::string speedup_title(const std::string& baseline);

// The table's cells: the header row, then one row per result.
std::vector<std::vector<std::string>> table_rows(const BenchReport& report);
void print_table(std::ostream& out, const BenchReport& report);

// `bench --report DIR`: DIR/index.html, a self-contained page (bench/html_page.h) with the table
// and bar charts of Mrays/s and of the speed-up per ray type, with intervals.
void write_report(const std::string& dir, const BenchReport& report);

// The contract: {"scene", "triangles", "threads", "results": [{"backend", "rays", "count",
// "build_s", "trace_s", "mrays_per_s", "mrays_per_s_with_build", "peak_mb"}]}, those figures
// medians, plus extra fields: "intervals" holds each figure's {"median", "low", "high",
// "coverage", "runs"}, every timed run's value.
nlohmann::ordered_json to_json(const BenchReport& report);

}  // namespace dacrt::bench
