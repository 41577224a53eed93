// The measurement loop of `dacrt bench`: for each case (the scene, or one size of a sweep) it makes
// each ray type's batch once, then runs every backend on it once untimed (the warm-up: the first
// run pays for cold caches, page faults and thread start-up, 3.2 against 41.5 Mrays/s warm on
// CornellBox-Original), then times them repeat after repeat, alternating between backends so that
// a noisy neighbour slows them all alike. A run is Backend::create (build seconds) then one
// intersect or occluded call on the whole batch (trace seconds).
#pragma once

#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>
#include <optional>
#include <string>
#include <vector>

#include "bench/args.h"
#include "bench/rays.h"
#include "dacrt/scene/scene.h"
#include "dacrt/tracer/options.h"
#include "dacrt/tracer/ray_batch.h"
#include "dacrt/tracer/stats.h"
#include "dacrt/util/median_interval.h"
#include "dacrt/util/progress.h"

namespace dacrt::bench {

// Runs of each backend on each batch before the timed ones, their figures discarded.
inline constexpr int warmup_runs = 1;

// One backend on one batch: every timed run's numbers, and their medians with 95 % intervals
// (util/median_interval.h).
struct Result {
  std::string backend;
  BenchRay rays = BenchRay::primary;
  size_t count = 0;                            // rays in the batch
  size_t triangles = 0;                        // in the (possibly decimated) scene traced
  size_t decimation = 1;                       // every k-th triangle of the scene was kept
  int width = 0, height = 0;                   // the primary resolution the batch comes from
  std::vector<double> build_runs, trace_runs;  // seconds, one per repeat
  int warmups = 0;                             // untimed runs made before them
  uint64_t peak_bytes = 0;                     // largest over the runs
  uint64_t hits = 0;  // rays that hit something (intersect) or are occluded, in the last run
  Stats stats;        // the backend's counters in the last run (triangle tests, nodes, ...)

  // Per run: build + trace seconds; Mrays/s without and with the build. Figures of whole runs, so
  // that one slow build and one slow trace in different runs do not add.
  std::vector<double> total_runs() const;
  std::vector<double> rate_runs() const;
  std::vector<double> rate_with_build_runs() const;

  MedianInterval build_s() const { return median_interval(build_runs); }
  MedianInterval trace_s() const { return median_interval(trace_runs); }
  MedianInterval total_s() const { return median_interval(total_runs()); }
  MedianInterval mrays_per_s() const { return median_interval(rate_runs()); }
  MedianInterval mrays_per_s_with_build() const { return median_interval(rate_with_build_runs()); }
  double peak_mb() const { return double(peak_bytes) * 1e-6; }
};

// Every k-th triangle of the scene (k = 1 keeps all), with its materials and cameras.
Scene decimate(const Scene& scene, size_t k);

// The primary resolution: --width/--height as given (one alone keeps the camera's aspect), else
// about `count` pixels in the camera's aspect (1024² by default).
glm::ivec2 primary_resolution(const BenchArgs& a, std::optional<size_t> count, float aspect,
                              const std::string& camera);

// The backend whose primary hits seed the secondary rays: dacrt when it is registered.
std::string reference_backend(const BenchArgs& a);

// One configuration to measure: a scene (the loaded one or a decimated copy) and a batch size.
struct BenchCase {
  const Scene* scene = nullptr;
  size_t decimation = 1;
  std::optional<size_t> count;  // rays per batch; none = one per pixel or per primary hit
};

class BenchRunner {
 public:
  BenchRunner(const BenchArgs& args, size_t cases);

  const std::vector<Result>& results() const { return results_; }
  void finish() { progress_.finish(); }

  void run(const BenchCase& c);

 private:
  Options base_options() const;
  Options options_for(const std::string& backend) const;
  void warn(const std::string& message) const;
  void measure(const RayBatch& batch, BenchRay kind, const BenchCase& c, glm::ivec2 res);

  const BenchArgs& args_;
  Progress progress_;
  uint64_t done_ = 0, rays_ = 0;
  std::vector<Result> results_;
};

}  // namespace dacrt::bench
