#include "bench/report.h"

#include <algorithm>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <string_view>

#include "tracer/stats_json.h"

namespace dacrt::bench {

namespace {

std::string_view to_string(Sweep s) {
  return s == Sweep::rays ? "rays" : s == Sweep::triangles ? "triangles" : "none";
}

// The baseline's trace seconds over this result's, on the same batch; none without a baseline.
std::optional<double> speedup(const BenchReport& report, const Result& r) {
  if (report.baseline.empty()) return std::nullopt;
  for (const Result& b : report.results)
    if (b.backend == report.baseline && b.rays == r.rays && b.count == r.count &&
        b.decimation == r.decimation && b.width == r.width && b.height == r.height)
      return r.trace_s() > 0.0 ? b.trace_s() / r.trace_s() : 0.0;
  return std::nullopt;
}

std::string format_number(const char* format, double v) {
  char text[64];
  std::snprintf(text, sizeof text, format, v);
  return text;
}

// Two decimals, or two significant digits below 0.1 so that a slow row never reads 0.00.
std::string format_rate(double v) {
  return format_number(v > 0.0 && v < 0.1 ? "%.2g" : "%.2f", v);
}

}  // namespace

std::string choose_baseline(const std::vector<std::string>& backends) {
  for (const char* b : {"embree", "dacrt-naive"})
    for (const auto& name : backends)
      if (name == b) return name;
  return "";
}

void print_table(std::ostream& out, const BenchReport& report) {
  const char* title[] = {"rays",    "count",   "triangles",          "backend", "build s",
                         "trace s", "Mrays/s", "Mrays/s with build", "peak MB", nullptr};
  std::string vs = report.baseline.empty() ? "" : "vs " + report.baseline;
  std::vector<std::vector<std::string>> rows;
  rows.emplace_back();
  for (int k = 0; title[k]; ++k) rows.back().push_back(title[k]);
  if (!vs.empty()) rows.back().push_back(vs);
  for (const Result& r : report.results) {
    std::vector<std::string> row = {
        std::string(to_string(r.rays)),     std::to_string(r.count),
        std::to_string(r.triangles),        r.backend,
        format_number("%.3f", r.build_s()), format_number("%.4f", r.trace_s()),
        format_rate(r.mrays_per_s()),       format_rate(r.mrays_per_s_with_build()),
        format_number("%.1f", r.peak_mb())};
    if (!vs.empty()) {
      auto s = speedup(report, r);
      row.push_back(s ? format_rate(*s) : "");
    }
    rows.push_back(std::move(row));
  }
  std::vector<size_t> width(rows[0].size(), 3);
  for (const auto& row : rows)
    for (size_t k = 0; k < row.size(); ++k) width[k] = std::max(width[k], row[k].size());
  // Names left-aligned, numbers right-aligned (columns 0 and 3 are names).
  auto is_text = [](size_t k) { return k == 0 || k == 3; };
  auto print_row = [&](const std::vector<std::string>& row) {
    out << "|";
    for (size_t k = 0; k < row.size(); ++k) {
      std::string pad(width[k] - row[k].size(), ' ');
      out << " " << (is_text(k) ? row[k] + pad : pad + row[k]) << " |";
    }
    out << "\n";
  };

  out << "Scene " << report.scene << ": " << report.triangles << " triangles, " << report.threads
      << " threads, median of " << report.repeat << (report.repeat == 1 ? " run" : " runs")
      << "; secondary rays from " << report.reference << "'s primary hits";
  if (report.tmax_at_hit) out << "; intersect rays end at their closest hit (--tmax-at-hit)";
  if (!vs.empty()) out << "; " << vs << " = " << report.baseline << "'s trace s / the row's";
  out << ".\n\n";
  print_row(rows[0]);
  out << "|";
  for (size_t k = 0; k < width.size(); ++k)
    out << (is_text(k) ? ":" : "-") << std::string(width[k], '-') << (is_text(k) ? "-" : ":")
        << "|";
  out << "\n";
  for (size_t i = 1; i < rows.size(); ++i) print_row(rows[i]);
}

nlohmann::ordered_json to_json(const BenchReport& report) {
  using json = nlohmann::ordered_json;
  json results = json::array();
  for (const Result& r : report.results) {
    auto s = speedup(report, r);
    results.push_back({{"backend", r.backend},
                       {"rays", std::string(to_string(r.rays))},
                       {"count", r.count},
                       {"build_s", r.build_s()},
                       {"trace_s", r.trace_s()},
                       {"mrays_per_s", r.mrays_per_s()},
                       {"mrays_per_s_with_build", r.mrays_per_s_with_build()},
                       {"peak_mb", r.peak_mb()},
                       {"triangles", r.triangles},
                       {"decimation", r.decimation},
                       {"width", r.width},
                       {"height", r.height},
                       {"peak_bytes", r.peak_bytes},
                       {"hits", r.hits},
                       {"speedup", s ? json(*s) : json(nullptr)},
                       {"build_s_runs", r.build_runs},
                       {"backend_stats", to_json(r.stats)},
                       {"trace_s_runs", r.trace_runs}});
  }
  return {{"scene", report.scene},
          {"triangles", report.triangles},
          {"threads", report.threads},
          {"repeat", report.repeat},
          {"seed", report.seed},
          {"tmax_at_hit", report.tmax_at_hit},
          {"sweep", std::string(to_string(report.sweep))},
          {"reference", report.reference},
          {"baseline", report.baseline.empty() ? json(nullptr) : json(report.baseline)},
          {"results", results}};
}

}  // namespace dacrt::bench
