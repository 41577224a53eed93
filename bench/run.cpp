#include "bench/run.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <utility>

#include "dacrt/scene/camera.h"
#include "dacrt/tracer/backend.h"

namespace dacrt::bench {

namespace {

// Millions of rays per second in each run; 0 for a run too short to time.
std::vector<double> mrays_per_second(size_t rays, std::vector<double> seconds) {
  for (double& s : seconds) s = s > 0.0 ? double(rays) / s * 1e-6 : 0.0;
  return seconds;
}

}  // namespace

std::vector<double> Result::total_runs() const {
  std::vector<double> t(build_runs.size());
  for (size_t i = 0; i < t.size(); ++i) t[i] = build_runs[i] + trace_runs[i];
  return t;
}

std::vector<double> Result::rate_runs() const {
  return mrays_per_second(count, trace_runs);
}

std::vector<double> Result::rate_with_build_runs() const {
  return mrays_per_second(count, total_runs());
}

Scene decimate(const Scene& scene, size_t k) {
  Scene d;
  d.path = scene.path;
  d.materials = scene.materials;
  d.cameras = scene.cameras;
  d.cameras_from_file = scene.cameras_from_file;
  const Geometry& g = scene.geometry;
  d.geometry.reserve((g.size() + k - 1) / k);
  for (size_t i = 0; i < g.size(); i += k)
    d.geometry.add(g.vertex(i, 0), g.vertex(i, 1), g.vertex(i, 2), g.material[i]);
  return d;
}

glm::ivec2 primary_resolution(const BenchArgs& a, std::optional<size_t> count, float aspect,
                              const std::string& camera) {
  if (a.width || a.height)
    return image_size(aspect, a.width.value_or(0), a.height.value_or(0), 0, camera);
  return resolution_for_count(count.value_or(size_t(1024) * 1024), aspect);
}

std::string reference_backend(const BenchArgs& a) {
  for (const auto& name : Backend::names())
    if (name == "dacrt") return name;
  return a.backends.front();
}

BenchRunner::BenchRunner(const BenchArgs& args, size_t cases)
    : args_(args),
      progress_("bench",
                uint64_t(cases) * args.rays.size() * args.backends.size() *
                    uint64_t(args.repeat + warmup_runs),
                !args.quiet) {}

void BenchRunner::run(const BenchCase& c) {
  const Scene& scene = *c.scene;
  const Camera& camera = scene.cameras.at(0);
  const glm::ivec2 res =
      primary_resolution(args_, c.count, camera.aspect, scene.path + ": camera 0");
  RayBatch primary = primary_rays(camera, res.x, res.y);

  SurfacePoints points;
  bool secondary = false;
  for (BenchRay r : args_.rays)
    secondary |= r == BenchRay::shadow || r == BenchRay::ao || r == BenchRay::bounce;
  if (secondary) {
    auto reference = Backend::create(reference_backend(args_), scene.geometry, base_options());
    HitBatch hits;
    reference->intersect(primary, hits);
    points = surface_points(scene.geometry, primary, hits);
  }
  const size_t secondary_count = c.count.value_or(points.size());

  for (BenchRay kind : args_.rays) {
    RayBatch batch;  // the primary batch is measured in place, not copied
    switch (kind) {
      case BenchRay::primary:
        break;
      case BenchRay::shadow:
        batch = shadow_rays(scene, ShadowTargets(scene), points, secondary_count, args_.seed);
        break;
      case BenchRay::ao:
        batch = ao_rays(scene, points, secondary_count, args_.seed);
        break;
      case BenchRay::bounce:
        batch = bounce_rays(points, secondary_count, args_.seed);
        break;
      case BenchRay::random:
        batch = random_rays(scene.bounds(), c.count.value_or(primary.size()), args_.seed);
        break;
    }
    if (args_.tmax_at_hit && !uses_occluded(kind)) {
      if (kind == BenchRay::primary) batch = primary;
      HitBatch closest;
      Backend::create(reference_backend(args_), scene.geometry, base_options())
          ->intersect(batch, closest);
      for (size_t i = 0; i < batch.size(); ++i) batch.tmax[i] = closest.t[i];
    }
    const bool in_place = kind == BenchRay::primary && !args_.tmax_at_hit;
    const RayBatch& rays = in_place ? primary : batch;
    if (rays.size() == 0) {
      warn(std::string(to_string(kind)) + ": no rays (no primary ray hit the scene): skipped");
      done_ += args_.backends.size() * size_t(args_.repeat + warmup_runs);
      progress_.update(done_, rays_);
      continue;
    }
    measure(rays, kind, c, res);
  }
}

Options BenchRunner::base_options() const {
  Options o;
  o.threads = args_.threads;
  return o;
}

Options BenchRunner::options_for(const std::string& backend) const {
  Options o = takes_backend_options(backend) ? args_.backend_options : Options();
  o.threads = args_.threads;
  return o;
}

void BenchRunner::warn(const std::string& message) const {
  if (args_.warnings) return args_.warnings->push_back(message);
  // A progress bar on a terminal is a line without its newline yet: end it first.
  bool bar = !args_.quiet && isatty(STDERR_FILENO);
  std::fprintf(stderr, "%sdacrt bench: %s\n", bar ? "\n" : "", message.c_str());
}

void BenchRunner::measure(const RayBatch& batch, BenchRay kind, const BenchCase& c,
                          glm::ivec2 res) {
  using clock = std::chrono::steady_clock;
  const size_t n = batch.size();
  const size_t nb = args_.backends.size();
  const size_t first = results_.size();
  for (const auto& name : args_.backends) {
    Result r;
    r.backend = name;
    r.rays = kind;
    r.count = n;
    r.triangles = c.scene->geometry.size();
    r.decimation = c.decimation;
    r.width = res.x, r.height = res.y;
    results_.push_back(std::move(r));
  }
  // Outputs are allocated and touched once, outside the timing, and reused by every run.
  const bool occlusion = uses_occluded(kind);
  HitBatch hits;
  std::vector<uint8_t> occluded;
  if (occlusion)
    occluded.assign(n, 0);
  else
    hits.resize(n);

  // One run of backend b: timed, and kept unless it is a warm-up.
  auto run = [&](size_t b, bool warmup) {
    Result& r = results_[first + b];
    auto t0 = clock::now();
    auto backend = Backend::create(r.backend, c.scene->geometry, options_for(r.backend));
    auto t1 = clock::now();
    if (occlusion)
      backend->occluded(batch, occluded);
    else
      backend->intersect(batch, hits);
    auto t2 = clock::now();
    r.stats = backend->stats();
    backend.reset();
    if (warmup) {
      ++r.warmups;
    } else {
      r.peak_bytes = std::max(r.peak_bytes, r.stats.peak_bytes);
      r.build_runs.push_back(std::chrono::duration<double>(t1 - t0).count());
      r.trace_runs.push_back(std::chrono::duration<double>(t2 - t1).count());
    }
    r.hits = occlusion
                 ? uint64_t(std::count(occluded.begin(), occluded.end(), uint8_t(1)))
                 : uint64_t(n - std::count(hits.prim.begin(), hits.prim.end(), HitBatch::miss));
    rays_ += n;
    progress_.update(++done_, rays_);
  };
  for (int w = 0; w < warmup_runs; ++w)
    for (size_t b = 0; b < nb; ++b) run(b, true);
  // Rotate which backend goes first, so none always runs right after ray generation.
  for (int rep = 0; rep < args_.repeat; ++rep)
    for (size_t k = 0; k < nb; ++k) run((k + size_t(rep)) % nb, false);
  // Our backends agree bit for bit, and any backend should agree to a few grazing rays: a
  // larger difference means a broken backend, whose speed is then meaningless.
  for (size_t b = 1; b < nb; ++b) {
    const Result &a = results_[first], &r = results_[first + b];
    double diff = std::abs(double(r.hits) - double(a.hits));
    if (diff > 1e-3 * double(n))
      warn(std::string(to_string(kind)) + ": " + r.backend + " answers " + std::to_string(r.hits) +
           " of " + std::to_string(n) + " rays " + (occlusion ? "occluded" : "hit") + ", " +
           a.backend + " " + std::to_string(a.hits));
  }
}

}  // namespace dacrt::bench
