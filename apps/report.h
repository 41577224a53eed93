// What `dacrt render` reports about each backend it rendered with: the summary on stderr, the
// statistics as JSON, and, for several backends (--backend a,b,c), one table side by side.
#pragma once

#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "dacrt/integrators/integrator.h"
#include "dacrt/scene/scene.h"
#include "dacrt/tracer/stats.h"

namespace dacrt {

// A scene's materials counted by kind, for `dacrt info` and the Python module's Scene.info.
struct MaterialCounts {
  size_t emissive_triangles = 0, emissive = 0, textured = 0, masked = 0, blended = 0,
         transmissive = 0;
};
MaterialCounts count_materials(const Scene& scene);

struct BackendRun {
  std::string backend, output, preview;
  RenderStats stats;
  Stats backend_stats;
  double seconds = 0.0;        // whole render, the backend's build included
  double build_seconds = 0.0;  // the backend's build (Backend::create) alone
  uint32_t spp = 0;            // samples every pixel has (fewer than asked when stopped early)
  // The samples the pixels got: fewest, most, mean (they differ with adaptive sampling).
  uint32_t least_spp = 0, most_spp = 0;
  double mean_spp = 0.0;
  std::string stopped;  // why the render stopped early ("SIGINT", "the time limit"), or empty
};

// "a,b,c" → {a, b, c}; empty parts are dropped.
std::vector<std::string> split_list(const std::string& list);
// out.exr → out.NAME.exr (empty stays empty).
std::string with_backend(const std::string& path, const std::string& backend);

// out.exr → out.0007.exr for frame 7 (empty stays empty).
std::string with_frame(const std::string& path, int frame);

nlohmann::json to_json(const BackendRun& run);
void print_summary(const BackendRun& run, const Shot& shot, const RenderSettings& s);
// The comparison's rows: a label, then one cell per backend; the first row names the backends, an
// empty row is a rule, and the last row is each one's speed-up against the first (the first's
// render seconds over its own: higher is faster).
std::vector<std::vector<std::string>> comparison_rows(const std::vector<BackendRun>& runs);
// The rows as a text table, one column per backend.
void print_comparison(std::FILE* out, const std::vector<BackendRun>& runs);

}  // namespace dacrt
