// The render reports (see report.h): per-backend summaries, statistics and the comparison table.
#include "apps/report.h"

#include <algorithm>
#include <filesystem>

#include "bench/report.h"
#include "dacrt/film/fixed.h"
#include "dacrt/tracer/stats_json.h"
#include "dacrt/util/text.h"

namespace dacrt {

MaterialCounts count_materials(const Scene& scene) {
  MaterialCounts c;
  for (uint32_t m : scene.geometry.material) c.emissive_triangles += scene.materials[m].emitter();
  for (const Material& m : scene.materials) {
    c.emissive += m.emitter();
    c.textured += m.textured();
    c.masked += m.alpha_mode == Material::AlphaMode::mask;
    c.blended += m.alpha_mode == Material::AlphaMode::blend;
    c.transmissive += m.transmission > 0.f;
  }
  return c;
}
namespace {

nlohmann::json to_json(const RayTypeStats& s) {
  return {{"rays", s.rays}, {"seconds", s.seconds}, {"rays_per_second", s.rays_per_second()}};
}

struct BatchSizes {
  uint32_t min = 0, median = 0, max = 0;
};
BatchSizes batch_sizes(std::vector<uint32_t> sizes) {
  if (sizes.empty()) return {};
  std::sort(sizes.begin(), sizes.end());
  return {sizes.front(), sizes[sizes.size() / 2], sizes.back()};
}

std::string format(const char* fmt, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, v);
  return buf;
}
std::string count(uint64_t v) {
  return std::to_string(v);
}

}  // namespace

std::vector<std::string> split_list(const std::string& list) {
  std::vector<std::string> parts;
  size_t begin = 0;
  while (begin <= list.size()) {
    const size_t comma = std::min(list.find(',', begin), list.size());
    if (comma > begin) parts.push_back(list.substr(begin, comma - begin));
    begin = comma + 1;
  }
  return parts;
}

std::string with_backend(const std::string& path, const std::string& backend) {
  if (path.empty()) return path;
  std::filesystem::path p(path);
  return (p.parent_path() / (p.stem().string() + "." + backend + p.extension().string())).string();
}

std::string with_frame(const std::string& path, int frame) {
  char number[16];
  std::snprintf(number, sizeof number, "%04d", frame);
  return with_backend(path, number);
}

nlohmann::json to_json(const BackendRun& run) {
  const RenderStats& stats = run.stats;
  const Stats& b = run.backend_stats;
  const BatchSizes batches = batch_sizes(stats.bounce_batches);
  nlohmann::json j = {
      {"backend", run.backend},
      {"render_seconds", stats.seconds},
      {"seconds_with_build", run.seconds},
      {"build_seconds", run.build_seconds},
      {"paths", stats.paths},
      {"wavefront", stats.wavefront},
      {"dropped_samples", stats.dropped_samples},
      {"clamped_samples", stats.clamped_samples},
      {"skipped", stats.skipped},
      {"bounce_calls", stats.bounce_calls},
      {"bounce_batch", {{"min", batches.min}, {"median", batches.median}, {"max", batches.max}}},
      {"backend_stats", to_json(b)}};
  for (int t = 0; t < ray_type_count; ++t)
    j["rays"][std::string(to_string(RayType(t)))] = to_json(stats.by_type[t]);
  j["bounces"] = nlohmann::json::array();
  for (const auto& bounce : stats.by_bounce) j["bounces"].push_back(to_json(bounce));
  return j;
}

void print_summary(const BackendRun& run, const Shot& shot, const RenderSettings& s) {
  const RenderStats& stats = run.stats;
  char figures[256];
  char spp[96];
  if (s.adaptive > 0)
    std::snprintf(spp, sizeof spp, "adaptive %g: %u to %u spp, mean %.1f", s.adaptive,
                  run.least_spp, run.most_spp, run.mean_spp);
  else
    std::snprintf(spp, sizeof spp, "%u spp", run.spp);
  std::snprintf(figures, sizeof figures, ": %d×%d, %s%s, %s/%s, %.2f s", shot.width, shot.height,
                spp,
                run.stopped.empty()
                    ? ""
                    : (" of " + std::to_string(s.spp) + ", stopped by " + run.stopped).c_str(),
                run.backend.c_str(), s.integrator.c_str(), stats.seconds);
  print_message(run.output + figures);
  for (int t = 0; t < ray_type_count; ++t) {
    const RayTypeStats& rt = stats.by_type[t];
    if (rt.rays)
      std::fprintf(stderr, "  %-8s %12llu rays  %8.2f s  %7.2f Mrays/s\n",
                   std::string(to_string(RayType(t))).c_str(), (unsigned long long)rt.rays,
                   rt.seconds, rt.rays_per_second() * 1e-6);
  }
  for (const auto& skipped : stats.skipped) print_message("  skipped: " + skipped);
  if (stats.dropped_samples)
    std::fprintf(stderr, "  warning: %llu samples were NaN or inf and were dropped\n",
                 (unsigned long long)stats.dropped_samples);
  if (stats.clamped_samples)
    std::fprintf(stderr, "  warning: %llu samples had values beyond ±%.3g and were clamped to it\n",
                 (unsigned long long)stats.clamped_samples, value_limit);
}

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
