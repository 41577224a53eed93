// The comparison table of several backends' renders (see report.h).
#include "dacrt/util/paths.h"

#include <algorithm>
#include <filesystem>

#include "bench/report.h"
#include "dacrt/film/fixed.h"
#include "dacrt/render/run_report.h"
#include "dacrt/util/text.h"

namespace dacrt {

namespace {

std::string format(const char* fmt, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, v);
  return buf;
}
std::string count(uint64_t v) {
  return std::to_string(v);
}

}  // namespace

std::vector<std::vector<std::string>> comparison_rows(const std::vector<BackendRun>& runs) {
  std::vector<std::vector<std::string>> rows;
  auto row = [&](std::string label, auto cell) {
    std::vector<std::string> r{std::move(label)};
    for (const BackendRun& run : runs) r.push_back(cell(run));
    rows.push_back(std::move(r));
  };
  auto rule = [&] { rows.push_back({}); };
  row("", [](const BackendRun& run) { return run.backend; });
  rule();
  auto ray_rows = [&](const std::string& name, auto stats_of) {
    row(name + " rays", [&](const BackendRun& run) { return count(stats_of(run).rays); });
    row(name + " s", [&](const BackendRun& run) { return format("%.3f", stats_of(run).seconds); });
    row(name + " Mrays/s", [&](const BackendRun& run) {
      return format("%.2f", stats_of(run).rays_per_second() * 1e-6);
    });
  };
  for (int t = 0; t < ray_type_count; ++t)
    if (runs[0].stats.by_type[t].rays)
      ray_rows(std::string(to_string(RayType(t))),
               [t](const BackendRun& run) { return run.stats.by_type[t]; });
  rule();
  size_t bounces = 0;
  for (const BackendRun& run : runs) bounces = std::max(bounces, run.stats.by_bounce.size());
  for (size_t k = 0; k < bounces; ++k)
    row("bounce " + std::to_string(k + 1) + " rays, s, Mrays/s", [k](const BackendRun& run) {
      if (k >= run.stats.by_bounce.size()) return std::string("-");
      const RayTypeStats& b = run.stats.by_bounce[k];
      return count(b.rays) + format(" %.3f", b.seconds) +
             format(" %.2f", b.rays_per_second() * 1e-6);
    });
  rule();
  row("bounce calls", [](const BackendRun& run) { return count(run.stats.bounce_calls); });
  row("bounce batch min/median/max", [](const BackendRun& run) {
    const BatchSizes b = batch_sizes(run.stats.bounce_batches);
    return count(b.min) + "/" + count(b.median) + "/" + count(b.max);
  });
  row("nodes (kept)", [](const BackendRun& run) {
    return count(run.backend_stats.nodes) + " (" + count(run.backend_stats.kept_nodes) + ")";
  });
  row("leaves", [](const BackendRun& run) { return count(run.backend_stats.leaves); });
  row("rays into leaves", [](const BackendRun& run) { return count(run.backend_stats.leaf_rays); });
  row("box tests", [](const BackendRun& run) { return count(run.backend_stats.box_tests); });
  row("triangle tests",
      [](const BackendRun& run) { return count(run.backend_stats.triangle_tests); });
  row("triangles binned", [](const BackendRun& run) { return count(run.backend_stats.binned); });
  row("filter skips", [](const BackendRun& run) { return count(run.backend_stats.filter_skips); });
  row("peak MB per call",
      [](const BackendRun& run) { return format("%.1f", run.backend_stats.peak_bytes * 1e-6); });
  rule();
  row("backend s", [](const BackendRun& run) {
    double s = 0.0;
    for (const auto& t : run.stats.by_type) s += t.seconds;
    return format("%.3f", s);
  });
  row("build s",
      [](const BackendRun& run) { return format("%.3f", run.backend_stats.build_seconds); });
  row("render s, build included",
      [](const BackendRun& run) { return format("%.3f", run.seconds); });
  // The one convention of dacrt's ratios, named as dacrt bench names it.
  row(bench::speedup_title(runs[0].backend), [&](const BackendRun& run) {
    return format("%.2f", run.seconds > 0.0 ? runs[0].seconds / run.seconds : 0.0);
  });
  return rows;
}

void print_comparison(std::FILE* out, const std::vector<BackendRun>& runs) {
  const std::vector<std::vector<std::string>> rows = comparison_rows(runs);
  std::vector<size_t> width;
  for (const auto& r : rows)
    for (size_t c = 0; c < r.size(); ++c) {
      if (width.size() <= c) width.push_back(0);
      width[c] = std::max(width[c], r[c].size());
    }
  for (const auto& r : rows) {
    if (r.empty()) {
      size_t total = 0;
      for (size_t w : width) total += w + 2;
      std::fprintf(out, "%s\n", std::string(total, '-').c_str());
      continue;
    }
    std::fprintf(out, "%-*s", int(width[0] + 2), r[0].c_str());
    for (size_t c = 1; c < r.size(); ++c) std::fprintf(out, "%*s  ", int(width[c]), r[c].c_str());
    std::fprintf(out, "\n");
  }
}

}  // namespace dacrt
