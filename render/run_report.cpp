// The record of one backend's render (see run_report.h) and its summary.
#include "dacrt/render/run_report.h"

#include <algorithm>
#include <cstdio>

#include "dacrt/film/fixed.h"
#include "dacrt/util/text.h"

namespace dacrt {

BatchSizes batch_sizes(std::vector<uint32_t> sizes) {
  if (sizes.empty()) return {};
  std::sort(sizes.begin(), sizes.end());
  return {sizes.front(), sizes[sizes.size() / 2], sizes.back()};
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
  std::string stopped;
  if (!run.stopped.empty())
    stopped = " of " + std::to_string(s.spp) + ", stopped by " + run.stopped;
  if (run.stopped == "the time limit") {  // what the limit allowed
    char limit[96];
    std::snprintf(limit, sizeof limit, " of %g s after %u pass%s", run.time_limit, run.passes,
                  run.passes == 1 ? "" : "es");
    stopped += limit;
  }
  std::snprintf(figures, sizeof figures, ": %d×%d, %s%s, %s/%s, %.2f s", shot.width, shot.height,
                spp, stopped.c_str(), run.backend.c_str(), s.integrator.c_str(), stats.seconds);
  print_message(run.output + figures);
  for (int t = 0; t < ray_type_count; ++t) {
    const RayTypeStats& rt = stats.by_type[t];
    if (rt.rays)
      std::fprintf(stderr, "  %-8s %12llu rays  %8.2f s  %7.2f Mrays/s\n",
                   std::string(to_string(RayType(t))).c_str(), (unsigned long long)rt.rays,
                   rt.seconds, rt.rays_per_second() * 1e-6);
  }
  for (const auto& skipped : stats.skipped) print_message("  skipped: " + skipped);
  if (stats.light_sampler == "tree")
    print_message("  emitters picked by a light tree (" + std::to_string(stats.light_entries) +
                  " emitters; --light-sampler)");
  if (stats.dropped_samples)
    std::fprintf(stderr, "  warning: %llu samples were NaN or inf and were dropped\n",
                 (unsigned long long)stats.dropped_samples);
  if (stats.clamped_samples)
    std::fprintf(stderr,
                 "  warning: %llu samples had values beyond ±%.3g (albedo and normal: ±%.0f) and "
                 "were clamped to it\n",
                 (unsigned long long)stats.clamped_samples, value_limit, bounded_limit);
}

}  // namespace dacrt
