// path (the default integrator): a wavefront path tracer with stream regeneration. Up to
// RenderSettings::wavefront paths are alive at once; whenever paths end, new camera samples take
// their slots, so every iteration hands the backend full batches until the frame drains. Each
// iteration runs the stages of pbrt-v4's wavefront integrator, each over whole queues:
//   camera rays (free slots) → intersect → escaped → emitted → roulette → materials (next-event
//   estimation pushes shadow rays, BSDF sampling bounce rays) → shadow rays → film.
// Surfaces reflect by the glTF metallic-roughness BRDF (materials/gltf_brdf.h) around the shading
// normal. Next-event estimation samples emissive triangles and punctual lights by power, or the
// environment map, and is combined with BSDF sampling by multiple importance sampling
// (integrators/light_sampling.h). Scenes without emitters trace no shadow rays.
//
// The image depends only on (seed, pixel, sample, dimension): it is the same bit for bit for any
// thread count and for every exact backend, and the same up to the order of the film's sums for
// any wavefront size.
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <chrono>

#include "integrators/dimensions.h"
#include "integrators/integrator.h"
#include "integrators/light_sampling.h"
#include "integrators/path/queues.h"
#include "materials/sampling.h"
#include "materials/surface.h"
#include "tracer/ray.h"
#include "util/random.h"

namespace dacrt {
namespace {

using Clock = std::chrono::steady_clock;

// A camera batch smaller than this share of the bounce batch (or the other way round) is traced in
// the same call: DACRT pays per call for the triangles it partitions.
constexpr size_t merge_ratio = 8;

class PathTracer final : public Integrator {
 public:
  PathTracer(const Scene& scene, Backend& backend, const RenderSettings& settings)
      : scene_(scene),
        backend_(backend),
        s_(settings),
        map_(settings.environment_map && !settings.environment_map->black()
                 ? settings.environment_map.get()
                 : nullptr),
        lights_(scene, map_) {
    if (s_.camera < 0 || size_t(s_.camera) >= scene.cameras.size())
      throw Error("camera " + std::to_string(s_.camera) + " does not exist (the scene has " +
                  std::to_string(scene.cameras.size()) + ")");
    if (lights_.empty())
      stats_.skipped.push_back(
          "shadow rays (the scene has no emitters and no lights, and no environment map)");
    std::vector<uint8_t> tested(scene.geometry.size(), 0);
    bool any = false;
    for (size_t t = 0; t < tested.size(); ++t)
      any |= tested[t] =
          scene.materials[scene.geometry.material[t]].alpha_mode != Material::AlphaMode::opaque;
    if (any) alpha_ = std::make_unique<AlphaFilter>(std::move(tested), *this);
    for (const Material& m : scene.materials) emitters_ |= m.emissive();
    for (std::string& what : scene.unused_work()) stats_.skipped.push_back(std::move(what));
  }

  const RenderStats& stats() const override { return stats_; }

  void render(Film& film, Progress& progress) override {
    const auto start_time = Clock::now();
    const uint64_t total = uint64_t(s_.width) * s_.height * uint64_t(s_.spp);
    const size_t slots = resolve_wavefront(s_, total);
    stats_.wavefront = slots;
    paths_.resize(slots);
    ended_.assign(slots, 0);
    free_.resize(slots);
    for (size_t j = 0; j < slots; ++j) free_[j] = uint32_t(slots - 1 - j);  // popped from the back
    bounce_.type = RayType::bounce;
    bounce_.clear();
    uint64_t next_sample = 0, finished = 0;
    while (next_sample < total || bounce_.size() > 0) {
      next_sample += camera_rays(next_sample, total);
      shadow_.type = RayType::shadow;
      shadow_.clear();
      shadow_contribution_.clear();
      next_.type = RayType::bounce;
      next_.clear();
      intersect_and_shade();
      shadow_rays();
      finished += to_film(film);
      std::swap(bounce_, next_);
      // The bounce rays' paths go one vertex deeper.
      tbb::parallel_for(size_t(0), bounce_.size(),
                        [&](size_t i) { ++paths_.depth[bounce_.path[i]]; });
      progress.update(finished, stats_.total_rays());
    }
    progress.finish();
    stats_.paths += finished;
    stats_.dropped_samples = film.dropped();
    stats_.seconds = std::chrono::duration<double>(Clock::now() - start_time).count();
  }

 private:
  // The live paths, by slot (RayBatch::path).
  struct Paths {
    Array<glm::vec3> throughput, radiance;
    Array<uint32_t> pixel, sample;
    Array<float> bsdf_pdf;  // solid-angle pdf of the direction the path's last ray took
    Array<uint32_t> depth;  // scattering events so far: the depth of the vertex it is at
    void resize(size_t n) {
      throughput.resize(n), radiance.resize(n), pixel.resize(n), sample.resize(n);
      bsdf_pdf.resize(n), depth.resize(n);
    }
  };

  // Alpha-masked and alpha-blended materials, seen through by the backend's hit filter. A blended
  // surface stops a ray with probability alpha, drawn from the path's random stream (so renders
  // stay deterministic and the same for every backend). The number is keyed by the ray's own
  // type, which a merged batch does not tell: a path at depth 0 is on its camera ray.
  class AlphaFilter final : public HitFilter {
   public:
    AlphaFilter(std::vector<uint8_t> tested, const PathTracer& tracer)
        : HitFilter(std::move(tested)), t_(tracer) {}
    bool accept(const RayBatch& rays, uint32_t ray, uint32_t tri, float u, float v) const override {
      const uint32_t path = rays.path[ray];
      const uint32_t depth = t_.paths_.depth[path];
      const RayType type = rays.type == RayType::shadow ? RayType::shadow
                           : depth == 0                 ? RayType::primary
                                                        : RayType::bounce;
      const float xi =
          uniform_float(t_.s_.seed, t_.paths_.pixel[path], t_.paths_.sample[path], uint64_t(depth),
                        uint64_t(alpha) + uint64_t(type) + (uint64_t(tri) << 8));
      return xi < coverage_at(t_.scene_, tri, u, v);
    }

   private:
    const PathTracer& t_;
  };

  float random(uint32_t path, Dimension dim) const {
    return uniform_float(s_.seed, paths_.pixel[path], paths_.sample[path],
                         uint64_t(paths_.depth[path]), uint64_t(dim));
  }

  // Stage 1: new camera samples, in sample order, take the free slots. Returns how many.
  size_t camera_rays(uint64_t first, uint64_t total) {
    const size_t n = size_t(std::min<uint64_t>(free_.size(), total - first));
    const uint64_t pixels = uint64_t(s_.width) * s_.height;
    const Camera& camera = scene_.cameras[s_.camera];
    camera_.type = RayType::primary;
    camera_.resize(n);
    const size_t base = free_.size() - n;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](auto range) {
      for (size_t j = range.begin(); j != range.end(); ++j) {
        const uint32_t slot = free_[free_.size() - 1 - j];
        const uint64_t id = first + j;
        paths_.throughput[slot] = glm::vec3(1.f);
        paths_.radiance[slot] = glm::vec3(0.f);
        paths_.bsdf_pdf[slot] = 0.f;
        paths_.depth[slot] = 0;
        paths_.pixel[slot] = uint32_t(id % pixels);
        paths_.sample[slot] = uint32_t(id / pixels);
        const float x = float(paths_.pixel[slot] % uint32_t(s_.width)) + random(slot, pixel_x);
        const float y = float(paths_.pixel[slot] / uint32_t(s_.width)) + random(slot, pixel_y);
        glm::vec3 o, d;
        const float tmin = camera_ray(camera, s_.width, s_.height, x, y, o, d);
        camera_.set(j, o, d, tmin, INFINITY, slot);
      }
    });
    free_.resize(base);
    return n;
  }

  // Stage 2: the camera and bounce rays, in one call when one of them is small, then the
  // shading stages on each batch traced.
  void intersect_and_shade() {
    const size_t nc = camera_.size(), nb = bounce_.size();
    if (nc == 0 && nb == 0) return;
    if (nb > 0 && nc > 0 && (nc * merge_ratio < nb || nb * merge_ratio < nc)) {
      append(bounce_, camera_);
      trace(bounce_, hits_, nc);
      shade(bounce_, hits_);
      return;
    }
    if (nc > 0) {
      trace(camera_, hits_, nc);
      shade(camera_, hits_);
    }
    if (nb > 0) {
      trace(bounce_, hits_, 0);
      shade(bounce_, hits_);
    }
  }

  static void append(RayBatch& to, const RayBatch& from) {
    const size_t n = to.size();
    to.resize(n + from.size());
    tbb::parallel_for(size_t(0), from.size(), [&](size_t i) {
      to.set(n + i, from.origin(i), from.direction(i), from.tmin[i], from.tmax[i], from.path[i]);
    });
  }

  // The backend's closest hits; `camera` of the rays are on their camera ray (the rest bounce).
  // The call's time is shared between ray types and bounces by their rays.
  void trace(const RayBatch& rays, HitBatch& hits, size_t camera) {
    const auto t0 = Clock::now();
    backend_.intersect(rays, hits, alpha_.get());
    const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    const size_t n = rays.size();
    auto count = [&](RayTypeStats& s, uint64_t rays_of) {
      s.rays += rays_of;
      s.seconds += seconds * double(rays_of) / double(n);
    };
    count(stats_.by_type[size_t(RayType::primary)], camera);
    if (n == camera) return;
    count(stats_.by_type[size_t(RayType::bounce)], n - camera);
    ++stats_.bounce_calls;
    stats_.bounce_batches.push_back(uint32_t(n - camera));
    // Rays per depth (the bounce rays' paths are at depth ≥ 1).
    using Histogram = std::vector<uint64_t>;
    const Histogram by_depth = tbb::parallel_reduce(
        tbb::blocked_range<size_t>(0, n, 16384), Histogram(),
        [&](const auto& range, Histogram h) {
          for (size_t i = range.begin(); i != range.end(); ++i) {
            const uint32_t d = paths_.depth[rays.path[i]];
            if (d == 0) continue;
            if (h.size() < d) h.resize(d, 0);
            ++h[d - 1];
          }
          return h;
        },
        [](Histogram a, const Histogram& b) {
          if (a.size() < b.size()) a.resize(b.size(), 0);
          for (size_t k = 0; k < b.size(); ++k) a[k] += b[k];
          return a;
        });
    if (stats_.by_bounce.size() < by_depth.size()) stats_.by_bounce.resize(by_depth.size());
    for (size_t k = 0; k < by_depth.size(); ++k) count(stats_.by_bounce[k], by_depth[k]);
  }

  // Stages 3–6 on one traced batch: escaped, emitted, roulette, materials. Paths that end are
  // flagged for the film; shadow and bounce rays are appended to their queues.
  void shade(const RayBatch& rays, const HitBatch& hits) {
    const size_t n = rays.size();
    select(
        n, [&](size_t i) { return !hits.hit(i); }, queue_);
    escaped(rays, queue_);
    select(
        n, [&](size_t i) { return hits.hit(i); }, queue_);
    if (emitters_) emitted(rays, hits, queue_);
    roulette(rays, queue_);
    materials(rays, hits, queue_);
  }

  // Stage 3: rays that left the scene see the environment; their paths end.
  void escaped(const RayBatch& rays, const Array<uint32_t>& queue) {
    tbb::parallel_for(size_t(0), queue.size(), [&](size_t q) {
      const uint32_t i = queue[q], path = rays.path[i];
      ended_[path] = 1;
      if (!s_.environment_map) {
        paths_.radiance[path] += paths_.throughput[path] * s_.environment;
      } else if (map_) {
        // Also reachable by next-event estimation, after the first bounce: MIS.
        const glm::vec3 d = rays.direction(i);
        const float weight =
            paths_.depth[path] > 0 ? lights_.environment_weight(paths_.bsdf_pdf[path], d) : 1.f;
        paths_.radiance[path] += paths_.throughput[path] * map_->radiance(d) * weight;
      }
    });
  }

  // Stage 4: emitters hit add their emission (weighed against next-event estimation after the
  // camera ray).
  void emitted(const RayBatch& rays, const HitBatch& hits, const Array<uint32_t>& queue) {
    const Geometry& g = scene_.geometry;
    tbb::parallel_for(size_t(0), queue.size(), [&](size_t q) {
      const uint32_t i = queue[q], path = rays.path[i], tri = hits.prim[i];
      const Material& m = scene_.materials[g.material[tri]];
      if (!m.emissive()) return;
      const glm::vec3 d = rays.direction(i);
      glm::vec3 ng = g.normal(tri);
      const float area2 = glm::length(ng);
      const float cos = glm::dot(ng, d) / area2;
      if (!(cos < 0.f || m.double_sided)) return;
      float weight = 1.f;
      if (paths_.depth[path] > 0)
        weight = lights_.emitter_weight(paths_.bsdf_pdf[path], tri, hits.t[i], std::abs(cos),
                                        0.5f * area2);
      paths_.radiance[path] +=
          paths_.throughput[path] * emission_at(scene_, tri, hits.u[i], hits.v[i]) * weight;
    });
  }

  // Stage 5: paths at the depth limit end, and from roulette_depth on Russian roulette ends
  // paths of low throughput (the survivors' throughput grows to compensate). `queue` keeps the
  // survivors.
  void roulette(const RayBatch& rays, Array<uint32_t>& queue) {
    Array<uint8_t>& keep = flags_;
    keep.resize(queue.size());
    tbb::parallel_for(size_t(0), queue.size(), [&](size_t q) {
      const uint32_t path = rays.path[queue[q]];
      const int depth = int(paths_.depth[path]);
      keep[q] = depth < s_.max_depth;
      if (keep[q] && depth >= s_.roulette_depth) {
        glm::vec3& beta = paths_.throughput[path];
        const float p = std::min(1.f, std::max({beta.x, beta.y, beta.z}));
        keep[q] = random(path, Dimension::roulette) < p;
        if (keep[q]) beta /= p;
      }
      if (!keep[q]) ended_[path] = 1;
    });
    // Out of place: blocks compacting in parallel would overwrite each other's input.
    select(
        queue.size(), [&](size_t q) { return keep[q] != 0; }, survivors_);
    tbb::parallel_for(size_t(0), survivors_.size(),
                      [&](size_t k) { survivors_[k] = queue[survivors_[k]]; });
    queue.swap(survivors_);
  }

  // Stage 6: the material at each surviving hit; next-event estimation writes a shadow ray, BSDF
  // sampling a bounce ray, each in the hit's slot of scratch queues, compacted after.
  void materials(const RayBatch& rays, const HitBatch& hits, const Array<uint32_t>& queue) {
    const size_t n = queue.size();
    scratch_shadow_.resize(n);
    scratch_next_.resize(n);
    has_shadow_.assign(n, 0);
    has_next_.assign(n, 0);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1024), [&](auto range) {
      for (size_t q = range.begin(); q != range.end(); ++q) material(rays, hits, queue[q], q);
    });
    // Appended after what the queues hold (sized for all, then cut to what was written).
    const size_t shadows = shadow_.size(), nexts = next_.size();
    shadow_.resize(shadows + n);
    shadow_contribution_.resize(shadows + n);
    next_.resize(nexts + n);
    const size_t new_shadows = compact(
        n, [&](size_t q) { return has_shadow_[q] != 0; },
        [&](size_t q, size_t k) {
          const ShadowRay& s = scratch_shadow_[q];
          shadow_.set(shadows + k, s.origin, s.direction, 0.f, s.tmax, rays.path[queue[q]]);
          shadow_contribution_[shadows + k] = s.contribution;
        });
    const size_t new_nexts = compact(
        n, [&](size_t q) { return has_next_[q] != 0; },
        [&](size_t q, size_t k) {
          const ShadowRay& s = scratch_next_[q];  // a bounce ray: origin and direction
          next_.set(nexts + k, s.origin, s.direction, 0.f, INFINITY, rays.path[queue[q]]);
        });
    shadow_.resize(shadows + new_shadows);
    shadow_contribution_.resize(shadows + new_shadows);
    next_.resize(nexts + new_nexts);
  }

  void material(const RayBatch& rays, const HitBatch& hits, uint32_t i, size_t q) {
    const uint32_t path = rays.path[i];
    const glm::vec3 d = rays.direction(i);
    const Geometry& g = scene_.geometry;
    const uint32_t tri = hits.prim[i];
    glm::vec3 ng = g.normal(tri);
    ng /= glm::length(ng);
    const bool front = glm::dot(ng, d) < 0.f;
    const float u = hits.u[i], v = hits.v[i];
    const SurfacePoint surface = surface_at(scene_, tri, u, v, ng);

    // The surface point, and normals on the side the ray arrived from.
    const glm::vec3 p =
        (1.f - u - v) * g.vertex(tri, 0) + u * g.vertex(tri, 1) + v * g.vertex(tri, 2);
    if (!front) ng = -ng;
    glm::vec3 ns = surface.normal;
    if (glm::dot(ns, ng) < 0.f) ns = -ns;
    // Interpolated normals can face away from the viewer where the geometric one does not; the
    // BRDF is then evaluated around the geometric normal.
    if (glm::dot(ns, d) >= 0.f) ns = ng;
    const bool transmits = surface.brdf.transmission > 0.f && surface.brdf.metallic < 1.f;
    const Frame frame(ns);
    const ShadingPoint x{ng,
                         frame,
                         GltfBrdf(surface.brdf),
                         frame.to_local(-d),
                         offset_ray_origin(p, ng),
                         transmits ? offset_ray_origin(p, -ng) : p,
                         transmits};
    glm::vec3& beta = paths_.throughput[path];
    auto numbers = [&](Dimension dim) { return random(path, dim); };
    if (!lights_.empty()) {
      ShadowRay& shadow = scratch_shadow_[q];
      if (lights_.sample(p, x, numbers, shadow)) {
        shadow.contribution *= beta;
        has_shadow_[q] = carries_light(shadow.contribution);
      }
    }

    // BSDF sampling: reflection keeps to the arrival side, transmission crosses to the other.
    ended_[path] = 1;  // unless it bounces
    const auto s =
        x.brdf.sample(x.wo, random(path, bsdf_lobe), random(path, bsdf_u), random(path, bsdf_v));
    if (!s) return;
    const glm::vec3 wi = x.frame.to_world(s->wi);
    const glm::vec3* origin = x.origin_towards(wi, s->wi);
    if (!origin) return;
    beta *= s->weight;
    if (!carries_light(beta)) return;
    paths_.bsdf_pdf[path] = s->pdf;
    scratch_next_[q].origin = *origin;
    scratch_next_[q].direction = wi;
    has_next_[q] = 1;
    ended_[path] = 0;
  }

  // Stage 7: shadow rays that reach their light add to their path (at most one per path).
  void shadow_rays() {
    if (shadow_.size() == 0) return;
    occluded_.resize(shadow_.size());
    const auto t0 = Clock::now();
    backend_.occluded(shadow_, occluded_, alpha_.get());
    auto& by_type = stats_.by_type[size_t(RayType::shadow)];
    by_type.rays += shadow_.size();
    by_type.seconds += std::chrono::duration<double>(Clock::now() - t0).count();
    tbb::parallel_for(size_t(0), shadow_.size(), [&](size_t k) {
      if (!occluded_[k]) paths_.radiance[shadow_.path[k]] += shadow_contribution_[k];
    });
  }

  // Stage 8: the paths that ended go to the film, in slot order; their slots are free again.
  uint64_t to_film(Film& film) {
    select(
        ended_.size(), [&](size_t slot) { return ended_[slot] != 0; }, queue_);
    film.add_in_order(
        queue_.size(), [&](size_t k) { return paths_.pixel[queue_[k]]; },
        [&](size_t k) { return paths_.radiance[queue_[k]]; });
    tbb::parallel_for(size_t(0), queue_.size(), [&](size_t k) { ended_[queue_[k]] = 0; });
    // Free slots are taken from the back: the lowest-numbered first.
    const size_t had = free_.size(), ended = queue_.size();
    free_.resize(had + ended);
    tbb::parallel_for(size_t(0), ended, [&](size_t k) { free_[had + k] = queue_[ended - 1 - k]; });
    return queue_.size();
  }

  const Scene& scene_;
  Backend& backend_;
  const RenderSettings s_;
  const EnvironmentMap* map_;  // null: uniform (or black) environment, reached by BSDF sampling
  const LightSampling lights_;
  bool emitters_ = false;  // any emissive material: the emitted stage runs
  RenderStats stats_;
  std::unique_ptr<AlphaFilter> alpha_;  // null when every material is opaque

  Paths paths_;
  Array<uint8_t> ended_;  // by slot: the path ended in this iteration
  Array<uint32_t> free_;  // slots without a path
  RayBatch camera_, bounce_, next_, shadow_;
  HitBatch hits_;
  Array<uint32_t> queue_, survivors_;  // the stage's ray indices
  Array<uint8_t> flags_;
  Array<ShadowRay> scratch_shadow_, scratch_next_;
  Array<glm::vec3> shadow_contribution_;
  Array<uint8_t> has_shadow_, has_next_;
  std::vector<uint8_t> occluded_;  // a span for Backend::occluded
};

const Integrator::Registration registration{
    "path", [](const Scene& scene, Backend& backend, const RenderSettings& settings) {
      return std::make_unique<PathTracer>(scene, backend, settings);
    }};

}  // namespace
}  // namespace dacrt
