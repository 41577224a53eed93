#include "bench/report.h"

#include <algorithm>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string_view>

#include "bench/html_page.h"
#include "dacrt/tracer/stats_json.h"

namespace dacrt::bench {

namespace {

std::string_view to_string(Sweep s) {
  return s == Sweep::rays ? "rays" : s == Sweep::triangles ? "triangles" : "none";
}

// The baseline's result on the same batch as r, if it was benchmarked.
const Result* baseline_of(const BenchReport& report, const Result& r) {
  if (report.baseline.empty()) return nullptr;
  for (const Result& b : report.results)
    if (b.backend == report.baseline && b.rays == r.rays && b.count == r.count &&
        b.decimation == r.decimation && b.width == r.width && b.height == r.height)
      return &b;
  return nullptr;
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

// "median [low, high]"; the median alone for one run, which has no interval.
template <typename Format>
std::string format_interval(const MedianInterval& m, size_t runs, Format format) {
  std::string text = format(m.median);
  if (runs > 1) text += " [" + format(m.low) + ", " + format(m.high) + "]";
  return text;
}

// What the speed-up column holds, for the caption and the JSON.
std::string speedup_legend(const std::string& baseline) {
  return "speed-up = " + baseline + "'s trace s / the row's, repeat by repeat, higher is faster";
}

std::string percent(double p) {
  return format_number("%.0f %%", 100.0 * p);
}

}  // namespace

std::vector<double> speedup_runs(const BenchReport& report, const Result& r) {
  std::vector<double> runs;
  const Result* b = baseline_of(report, r);
  if (!b) return runs;
  for (size_t i = 0; i < std::min(b->trace_runs.size(), r.trace_runs.size()); ++i)
    runs.push_back(r.trace_runs[i] > 0.0 ? b->trace_runs[i] / r.trace_runs[i] : 0.0);
  return runs;
}

std::string method_text(int repeat) {
  const std::string warmup = std::to_string(warmup_runs) + " discarded warm-up run" +
                             (warmup_runs == 1 ? "" : "s") + " per backend and ray type";
  if (repeat <= 1) return "each figure one run after " + warmup + ", without an interval";
  const size_t n = size_t(repeat);
  const MedianRanks r = median_ranks(n);
  std::string text =
      "each figure the median of " + std::to_string(n) + " runs after " + warmup + ", in brackets ";
  if (r.coverage < 0.95)
    return text + "their range (n=" + std::to_string(n) + ": range, " + percent(r.coverage) +
           " coverage of the true median; 95 % needs 6 runs)";
  return text + "its " + percent(r.coverage) + " confidence interval (runs " +
         std::to_string(r.low) + " and " + std::to_string(r.high) + " of the " + std::to_string(n) +
         " sorted)";
}

std::string speedup_title(const std::string& baseline) {
  return "speed-up vs " + baseline + ", higher is faster";
}

std::string choose_baseline(const std::vector<std::string>& backends) {
  for (const char* b : {"embree", "dacrt-naive"})
    for (const auto& name : backends)
      if (name == b) return name;
  return "";
}

std::vector<std::vector<std::string>> table_rows(const BenchReport& report) {
  const char* title[] = {"rays",    "count",   "triangles",          "backend", "build s",
                         "trace s", "Mrays/s", "Mrays/s with build", "peak MB", nullptr};
  const bool vs = !report.baseline.empty();
  std::vector<std::vector<std::string>> rows;
  rows.emplace_back();
  for (int k = 0; title[k]; ++k) rows.back().push_back(title[k]);
  if (vs) rows.back().push_back(speedup_title(report.baseline));
  auto seconds = [](const char* format) {
    return [format](double v) { return format_number(format, v); };
  };
  for (const Result& r : report.results) {
    const size_t n = r.trace_runs.size();
    std::vector<std::string> row = {std::string(to_string(r.rays)),
                                    std::to_string(r.count),
                                    std::to_string(r.triangles),
                                    r.backend,
                                    format_interval(r.build_s(), n, seconds("%.3f")),
                                    format_interval(r.trace_s(), n, seconds("%.4f")),
                                    format_interval(r.mrays_per_s(), n, format_rate),
                                    format_interval(r.mrays_per_s_with_build(), n, format_rate),
                                    format_number("%.1f", r.peak_mb())};
    if (vs) {
      const std::vector<double> s = speedup_runs(report, r);
      row.push_back(s.empty() ? "" : format_interval(median_interval(s), s.size(), format_rate));
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

void print_table(std::ostream& out, const BenchReport& report) {
  const bool vs = !report.baseline.empty();
  const std::vector<std::vector<std::string>> rows = table_rows(report);
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
      << " threads; " << method_text(report.repeat) << "; secondary rays from " << report.reference
      << "'s primary hits";
  if (report.tmax_at_hit) out << "; intersect rays end at their closest hit (--tmax-at-hit)";
  if (vs) out << "; " << speedup_legend(report.baseline);
  out << "; peak MB the largest of the runs.\n\n";
  print_row(rows[0]);
  out << "|";
  for (size_t k = 0; k < width.size(); ++k)
    out << (is_text(k) ? ":" : "-") << std::string(width[k], '-') << (is_text(k) ? "-" : ":")
        << "|";
  out << "\n";
  for (size_t i = 1; i < rows.size(); ++i) print_row(rows[i]);
}

namespace {

nlohmann::ordered_json to_json(const std::vector<double>& runs) {
  const MedianInterval m = median_interval(runs);
  return {{"median", m.median},
          {"low", m.low},
          {"high", m.high},
          {"coverage", m.coverage},
          {"runs", runs}};
}

}  // namespace

nlohmann::ordered_json to_json(const BenchReport& report) {
  using json = nlohmann::ordered_json;
  json results = json::array();
  for (const Result& r : report.results) {
    const std::vector<double> s = speedup_runs(report, r);
    json intervals = {{"build_s", to_json(r.build_runs)},
                      {"trace_s", to_json(r.trace_runs)},
                      {"total_s", to_json(r.total_runs())},
                      {"mrays_per_s", to_json(r.rate_runs())},
                      {"mrays_per_s_with_build", to_json(r.rate_with_build_runs())},
                      {"speedup", s.empty() ? json(nullptr) : to_json(s)}};
    results.push_back({{"backend", r.backend},
                       {"rays", std::string(to_string(r.rays))},
                       {"count", r.count},
                       {"build_s", r.build_s().median},
                       {"trace_s", r.trace_s().median},
                       {"mrays_per_s", r.mrays_per_s().median},
                       {"mrays_per_s_with_build", r.mrays_per_s_with_build().median},
                       {"peak_mb", r.peak_mb()},
                       {"triangles", r.triangles},
                       {"decimation", r.decimation},
                       {"width", r.width},
                       {"height", r.height},
                       {"peak_bytes", r.peak_bytes},
                       {"hits", r.hits},
                       {"speedup", s.empty() ? json(nullptr) : json(median_interval(s).median)},
                       {"warmups", r.warmups},
                       {"intervals", intervals},
                       {"backend_stats", to_json(r.stats)}});
  }
  return {
      {"scene", report.scene},
      {"triangles", report.triangles},
      {"threads", report.threads},
      {"repeat", report.repeat},
      {"warmup_runs", warmup_runs},
      {"method", method_text(report.repeat)},
      {"speedup", report.baseline.empty() ? json(nullptr) : json(speedup_legend(report.baseline))},
      {"seed", report.seed},
      {"tmax_at_hit", report.tmax_at_hit},
      {"sweep", std::string(to_string(report.sweep))},
      {"reference", report.reference},
      {"baseline", report.baseline.empty() ? json(nullptr) : json(report.baseline)},
      {"results", results}};
}

void write_report(const std::string& dir, const BenchReport& report) {
  HtmlPage page("dacrt bench: " + report.scene);
  page.paragraph(std::to_string(report.triangles) + " triangles, " +
                 std::to_string(report.threads) + " threads; " + method_text(report.repeat) +
                 "; secondary rays from " + report.reference + "'s primary hits" +
                 (report.baseline.empty() ? "" : "; " + speedup_legend(report.baseline)) + ".");
  // One cluster per batch (a ray type, and its size in a sweep), one bar per backend.
  std::vector<std::string> backends;
  for (const Result& r : report.results)
    if (std::find(backends.begin(), backends.end(), r.backend) == backends.end())
      backends.push_back(r.backend);
  auto label = [&](const Result& r) {
    std::string l(to_string(r.rays));
    if (report.sweep != Sweep::none)
      l.append(1, ' ').append(std::to_string(report.sweep == Sweep::rays ? r.count : r.triangles));
    return l;
  };
  std::vector<BarGroup> rates, speedups;
  auto group_of = [&](std::vector<BarGroup>& groups, const Result& r) -> Bar& {
    const std::string l = label(r);
    auto g = std::find_if(groups.begin(), groups.end(), [&](const BarGroup& x) { return x.label == l; });
    if (g == groups.end()) {
      groups.push_back({l, std::vector<Bar>(backends.size(), Bar{0.0, NAN, NAN, false})});
      g = groups.end() - 1;
    }
    const size_t k = size_t(std::find(backends.begin(), backends.end(), r.backend) - backends.begin());
    return g->bars[k];
  };
  for (const Result& r : report.results) {
    const MedianInterval m = r.mrays_per_s();
    group_of(rates, r) = {m.median, m.low, m.high};
    if (const std::vector<double> s = speedup_runs(report, r); !s.empty()) {
      const MedianInterval v = median_interval(s);
      group_of(speedups, r) = {v.median, v.low, v.high};
    }
  }
  page.heading("Rays per second");
  page.figure(bar_chart_svg("Mrays/s per ray type", "Mrays/s", backends, rates),
              "The median of the timed runs; the whiskers are its 95 % confidence interval "
              "(order statistics; the min-max range with its coverage when the runs are too few).");
  if (!speedups.empty())
    page.figure(bar_chart_svg(speedup_title(report.baseline), "speed-up", backends, speedups),
                "The baseline's trace seconds over each backend's, repeat by repeat, then the "
                "median and its interval: above 1 is faster than " + report.baseline + ".");
  page.heading("Table");
  std::vector<std::vector<std::string>> rows = table_rows(report);
  const std::vector<std::string> header = rows.front();
  rows.erase(rows.begin());
  page.table(header, rows);
  page.write(dir);
}

}  // namespace dacrt::bench
