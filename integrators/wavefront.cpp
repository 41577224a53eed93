#include "dacrt/integrators/wavefront.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <chrono>

#include "dacrt/materials/sampling.h"
#include "dacrt/tracer/ray.h"
#include "dacrt/util/error.h"
#include "dacrt/util/random.h"

namespace dacrt {

namespace {

using Clock = std::chrono::steady_clock;

// A camera batch smaller than this share of the bounce batch (or the other way round) is traced in
// the same call: DACRT pays per call for the triangles it partitions.
constexpr size_t merge_ratio = 8;

}  // namespace

// Alpha-masked and alpha-blended materials, seen through by the backend's hit filter. A blended
// surface stops a ray with probability alpha, drawn from the path's random stream (so renders stay
// deterministic and the same for every backend). The number is keyed by the ray's own type, which
// a merged batch does not tell: a path at depth 0 is on its camera ray.
class Wavefront::AlphaFilter final : public HitFilter {
 public:
  AlphaFilter(std::vector<uint8_t> tested, const Wavefront& w)
      : HitFilter(std::move(tested)), w_(w) {}
  bool accept(const RayBatch& rays, uint32_t ray, uint32_t tri, float u, float v) const override {
    const uint32_t path = rays.path[ray];
    const uint32_t depth = w_.paths_.depth[path];
    const RayType type = rays.type == RayType::shadow ? RayType::shadow
                         : depth == 0                 ? RayType::primary
                                                      : RayType::bounce;
    const float xi =
        uniform_float(w_.s_.seed, w_.paths_.pixel[path], w_.paths_.sample[path], uint64_t(depth),
                      uint64_t(alpha) + uint64_t(type) + (uint64_t(tri) << 8));
    return xi < coverage_at(w_.scene_, tri, u, v);
  }

 private:
  const Wavefront& w_;
};

void Wavefront::Paths::resize(size_t n, bool first_hits) {
  throughput.resize(n), radiance.resize(n), pixel.resize(n), sample.resize(n);
  bsdf_pdf.resize(n), depth.resize(n);
  first.resize(first_hits ? n : 0);
}

Wavefront::Wavefront(const Scene& scene, const Shot& shot, Backend& backend,
                     const RenderSettings& settings)
    : scene_(scene),
      shot_(shot),
      backend_(backend),
      s_(settings),
      sampler_(settings.sampler, settings.seed),
      first_hits_(settings.aovs.first_hit()) {
  forward_ = -glm::vec3(shot.camera.to_world[2]);
  std::vector<uint8_t> tested(scene.geometry.size(), 0);
  bool any = false;
  for (size_t t = 0; t < tested.size(); ++t)
    any |= tested[t] =
        scene.materials[scene.geometry.material[t]].alpha_mode != Material::AlphaMode::opaque;
  if (any) alpha_ = std::make_unique<AlphaFilter>(std::move(tested), *this);
  // (An anisotropic BRDF turns with the tangent frame: made per hit. Anisotropy over a Lambert
  // base is none, and keeps the Lambert lanes.)
  for (const Material& m : scene.materials) {
    textured_ |= m.textured();
    const GltfBrdf brdf(m.brdf());
    uniform_brdf_.push_back(m.textured() || !scene.colors.empty() || brdf.anisotropic()
                                ? std::nullopt
                                : std::optional<GltfBrdf>(brdf));
  }
  for (std::string& what : scene.unused_work()) stats_.skipped.push_back(std::move(what));
  if (textured_) tiled_ = SampleOrder::tiled(uint32_t(shot.width), uint32_t(shot.height));
}

SampleOrder Wavefront::sample_order(uint32_t first, uint32_t last, uint64_t pixels) const {
  return {pixels, first, std::max(first, last) - first,
          textured_ ? SampleOrder::tiled_group : std::max<uint64_t>(pixels, 1)};
}

Wavefront::~Wavefront() = default;

uint64_t Wavefront::render(Film& film, uint32_t first, uint32_t last,
                           std::span<const uint32_t> only, const std::atomic<bool>* stop,
                           Progress& progress) {
  const auto start_time = Clock::now();
  if (film.pixels() != shot_.pixels())
    throw Error("the film has " + std::to_string(film.pixels()) + " pixels, the render " +
                std::to_string(shot_.pixels()));
  call_pixels_ = tiled_;
  if (!only.empty() && textured_) {  // the listed pixels, by tiles
    std::vector<uint8_t> listed(shot_.pixels(), 0);
    for (uint32_t p : only) listed[p] = 1;
    only_pixels_.clear();
    for (uint32_t p : tiled_)
      if (listed[p]) only_pixels_.push_back(p);
    call_pixels_ = only_pixels_;
  } else if (!only.empty()) {
    call_pixels_ = only;
  }
  const uint64_t pixels = call_pixels_.empty() ? shot_.pixels() : call_pixels_.size();
  const uint64_t begin = uint64_t(first) * pixels, end = uint64_t(std::max(first, last)) * pixels;
  order_ = sample_order(first, last, pixels);
  begin_id_ = begin;
  const size_t slots = resolve_wavefront(s_, end - begin);
  stats_.wavefront = std::max<uint64_t>(stats_.wavefront, slots);
  paths_.resize(slots, first_hits_);
  ended_.assign(slots, 0);
  free_.resize(slots);
  for (size_t j = 0; j < slots; ++j) free_[j] = uint32_t(slots - 1 - j);  // popped from the back
  bounce_.type = RayType::bounce;
  bounce_.clear();
  uint64_t next_id = begin, finished = 0;
  auto stopped = [&] { return stop && stop->load(std::memory_order_relaxed); };
  while ((next_id < end && !stopped()) || bounce_.size() > 0) {
    if (stopped())
      camera_.clear();  // no new samples (the last iteration's camera rays are traced already)
    else
      next_id += camera_rays(next_id, end);
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
    progress.update(stats_.paths + finished, stats_.total_rays());
  }
  call_pixels_ = {};
  stats_.paths += finished;
  stats_.dropped_samples = film.dropped();
  stats_.clamped_samples = film.clamped();
  stats_.seconds += std::chrono::duration<double>(Clock::now() - start_time).count();
  return next_id - begin;
}

// Stage 1: new camera samples, in the call's SampleOrder, take the free slots. Returns how many.
size_t Wavefront::camera_rays(uint64_t first_id, uint64_t end_id) {
  const size_t n = size_t(std::min<uint64_t>(free_.size(), end_id - first_id));
  const CameraProjection camera(shot_.camera, shot_.width, shot_.height);
  const uint32_t width = uint32_t(shot_.width);
  camera_.type = RayType::primary;
  camera_.resize(n);
  const size_t base = free_.size() - n;
  // The point in the pixel, and with a thin lens the point on the lens: a pinhole draws only
  // the first, so its rays (and images) are those of a camera without lens dimensions.
  constexpr Dimension jitter[] = {pixel_x}, jitter_lens[] = {pixel_x, lens_u};
  const std::span<const Dimension> dims =
      camera.thin_lens() ? std::span<const Dimension>(jitter_lens) : jitter;
  // A pinhole's rays are made a group at a time (CameraProjection::pinhole_rays).
  const bool pinhole = camera.pinhole();
  const glm::vec3 eye(camera.to_world[3]);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](auto range) {
    uint32_t pixel[sampler_lanes], sample[sampler_lanes], depth[sampler_lanes] = {};
    VertexNumbers numbers[sampler_lanes];
    static_assert(sampler_lanes % 4 == 0);
    float xs[sampler_lanes] = {}, ys[sampler_lanes] = {}, d[3][sampler_lanes], tmin[sampler_lanes];
    SampleOrder::Cursor at(order_, first_id + range.begin() - begin_id_);
    for (size_t first = range.begin(); first < range.end(); first += sampler_lanes) {
      const size_t lanes = std::min(sampler_lanes, range.end() - first);
      for (size_t k = 0; k < lanes; ++k, ++at) {
        const auto [index, s] = *at;
        pixel[k] = call_pixels_.empty() ? uint32_t(index) : call_pixels_[index], sample[k] = s;
      }
      sampler_.numbers(pixel, sample, depth, lanes, dims, numbers);
      for (size_t k = 0; k < lanes; ++k) {
        xs[k] = float(pixel[k] % width) + numbers[k][pixel_x];
        ys[k] = float(pixel[k] / width) + numbers[k][pixel_y];
      }
      if (pinhole) camera.pinhole_rays(xs, ys, (lanes + 3) & ~size_t(3), d[0], d[1], d[2], tmin);
      for (size_t k = 0; k < lanes; ++k) {
        const size_t j = first + k;
        const uint32_t slot = free_[free_.size() - 1 - j];
        paths_.throughput[slot] = glm::vec3(1.f);
        paths_.radiance[slot] = glm::vec3(0.f);
        paths_.bsdf_pdf[slot] = 0.f;
        paths_.depth[slot] = 0;
        paths_.pixel[slot] = pixel[k];
        paths_.sample[slot] = sample[k];
        if (pinhole) {
          camera_.set(j, eye, {d[0][k], d[1][k], d[2][k]}, tmin[k], INFINITY, slot);
          continue;
        }
        glm::vec3 o, dir;
        const float t = camera.thin_lens() ? camera.ray(xs[k], ys[k], numbers[k][lens_u],
                                                        numbers[k][lens_v], o, dir)
                                           : camera.ray(xs[k], ys[k], o, dir);
        camera_.set(j, o, dir, t, INFINITY, slot);
      }
    }
  });
  free_.resize(base);
  return n;
}

// Stage 2: the camera and bounce rays, in one call when one of them is small, then the first
// hits and the shading stage on each batch traced.
void Wavefront::intersect_and_shade() {
  const size_t nc = camera_.size(), nb = bounce_.size();
  if (nc == 0 && nb == 0) return;
  auto run = [&](const RayBatch& rays, size_t camera) {
    trace(rays, hits_, camera);
    if (first_hits_ && camera > 0) first_hits(rays, hits_);
    shade(rays, hits_);
  };
  if (nb > 0 && nc > 0 && (nc * merge_ratio < nb || nb * merge_ratio < nc)) {
    append(bounce_, camera_);
    run(bounce_, nc);
    return;
  }
  if (nc > 0) run(camera_, nc);
  if (nb > 0) run(bounce_, 0);
}

void Wavefront::append(RayBatch& to, const RayBatch& from) {
  const size_t n = to.size();
  to.resize(n + from.size());
  tbb::parallel_for(size_t(0), from.size(), [&](size_t i) {
    to.set(n + i, from.origin(i), from.direction(i), from.tmin[i], from.tmax[i], from.path[i]);
  });
}

// The backend's closest hits; `camera` of the rays are on their camera ray (the rest bounce).
// The call's time is shared between ray types and bounces by their rays.
void Wavefront::trace(const RayBatch& rays, HitBatch& hits, size_t camera) {
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

void Wavefront::draw(const RayBatch& rays, size_t first, size_t lanes,
                     std::span<const Dimension> dims, VertexNumbers* out) const {
  // The paths' state is scattered over the wavefront's arrays (tens of MiB): that of the rays two
  // groups on is fetched while these are shaded.
  for (size_t j = first + 2 * lanes, end = std::min(rays.size(), first + 3 * lanes); j < end; ++j) {
    const uint32_t path = rays.path[j];
    __builtin_prefetch(&paths_.pixel[path]);
    __builtin_prefetch(&paths_.sample[path]);
    __builtin_prefetch(&paths_.depth[path], 1);
    __builtin_prefetch(&paths_.throughput[path], 1);
    __builtin_prefetch(&paths_.radiance[path], 1);
    __builtin_prefetch(&paths_.bsdf_pdf[path], 1);
    __builtin_prefetch(&ended_[path], 1);
  }
  uint32_t pixel[sampler_lanes], sample[sampler_lanes], depth[sampler_lanes];
  for (size_t k = 0; k < lanes; ++k) {
    const uint32_t path = rays.path[first + k];
    pixel[k] = paths_.pixel[path], sample[k] = paths_.sample[path], depth[k] = paths_.depth[path];
  }
  sampler_.numbers(pixel, sample, depth, lanes, dims, out);
}

void Wavefront::prefetch_textures(const HitBatch& hits, size_t first, size_t end) const {
  if (!textured_) return;
  for (size_t i = first; i < std::min(end, hits.size()); ++i)
    if (hits.hit(i)) prefetch_surface(scene_, hits.prim[i], hits.u[i], hits.v[i]);
}

void Wavefront::prefetch_triangles(const HitBatch& hits, size_t first, size_t end) const {
  const Geometry& g = scene_.geometry;
  // (Each array's element `tri`; a vertex's three attributes may cross a cache line: both ends.)
  auto both_ends = [](const auto* p, size_t bytes) {
    __builtin_prefetch(p);
    __builtin_prefetch(reinterpret_cast<const char*>(p) + bytes - 1);
  };
  for (size_t i = first; i < std::min(end, hits.size()); ++i) {
    if (!hits.hit(i)) continue;
    const uint32_t tri = hits.prim[i];
    __builtin_prefetch(&g.material[tri]);
    both_ends(&g.corners[tri], sizeof(Geometry::Corners));
    if (!scene_.normals.empty()) both_ends(&scene_.normals[3 * size_t(tri)], 3 * sizeof(glm::vec3));
    if (!scene_.texcoords.empty() && !scene_.texcoords[0].empty())
      both_ends(&scene_.texcoords[0][3 * size_t(tri)], 3 * sizeof(glm::vec2));
    if (!scene_.tangents.empty())
      both_ends(&scene_.tangents[3 * size_t(tri)], 3 * sizeof(glm::vec4));
  }
}

Wavefront::Hit Wavefront::hit_at(const RayBatch& rays, const HitBatch& hits, uint32_t i) const {
  const glm::vec3 d = rays.direction(i);
  const Geometry& g = scene_.geometry;
  const uint32_t tri = hits.prim[i];
  const glm::vec3 ng = g.unit_normal(tri);
  const bool front = glm::dot(ng, d) < 0.f;
  const float u = hits.u[i], v = hits.v[i];
  const SpawnPoint at = spawn_point(g.vertex(tri, 0), g.vertex(tri, 1), g.vertex(tri, 2), u, v);
  Hit h{at.p, ng, ng, surface_at(scene_, tri, u, v, ng), at.error};
  if (!front) h.ng = -h.ng;
  h.ns = h.surface.normal;
  if (glm::dot(h.ns, h.ng) < 0.f) h.ns = -h.ns;
  // Interpolated normals can face away from the viewer where the geometric one does not; the
  // BRDF is then evaluated around the geometric normal.
  if (glm::dot(h.ns, d) >= 0.f) h.ns = h.ng;
  return h;
}

BrdfParams Wavefront::framed_params(const Hit& h) const {
  BrdfParams p = h.surface.brdf;
  const Frame frame(h.ns);
  if (p.clearcoat > 0.f) {
    // On the arrival side, as hit_at turns the shading normal.
    const glm::vec3 n = glm::dot(h.surface.coat_normal, h.ng) < 0.f ? -h.surface.coat_normal
                                                                    : h.surface.coat_normal;
    p.clearcoat_normal = frame.to_local(n);  // (GltfBrdf takes the normal where z <= 0)
  }
  if (p.anisotropy > 0.f) {
    // Projected onto the shading normal's tangent plane (GltfBrdf normalises it, and takes
    // (1, 0) where it is zero: a direction along the normal).
    const glm::vec3 t = frame.to_local(h.surface.anisotropy_direction);
    p.anisotropy_direction = {t.x, t.y};
  }
  return p;
}

FirstHit Wavefront::first_hit_at(const RayBatch& rays, const HitBatch& hits, uint32_t i) const {
  FirstHit f;
  if (!hits.hit(i)) return f;
  const Hit h = hit_at(rays, hits, i);
  f.hit = true;
  f.albedo = h.surface.brdf.base_color;
  f.normal = h.ns;
  f.position = h.p;
  f.depth = hits.t[i] * glm::dot(rays.direction(i), forward_);
  return f;
}

// What each camera ray of the batch saw first (paths at depth 0 are on their camera ray).
void Wavefront::first_hits(const RayBatch& rays, const HitBatch& hits) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, rays.size(), 1024), [&](auto range) {
    for (size_t i = range.begin(); i != range.end(); ++i)
      if (paths_.depth[rays.path[i]] == 0)
        paths_.first[rays.path[i]] = first_hit_at(rays, hits, uint32_t(i));
  });
}

void Wavefront::select_rays(const HitBatch& hits, size_t n, bool hit) {
  select(
      n, [&](size_t i) { return hits.hit(i) == hit; }, queue_);
}

void Wavefront::scratch_rays(size_t n) {
  scratch_shadow_.resize(n);
  scratch_next_.resize(n);
  has_shadow_.assign(n, 0);
  has_next_.assign(n, 0);
}

void Wavefront::push_rays(const RayBatch& rays, const Array<uint32_t>* queue, float shadow_tmin) {
  const size_t n = queue ? queue->size() : rays.size();
  auto path = [&](size_t q) { return rays.path[queue ? (*queue)[q] : q]; };
  // Appended after what the queues hold (sized for all, then cut to what was written).
  const size_t shadows = shadow_.size(), nexts = next_.size();
  shadow_.resize(shadows + n);
  shadow_contribution_.resize(shadows + n);
  next_.resize(nexts + n);
  const size_t new_shadows = compact(
      n, [&](size_t q) { return has_shadow_[q] != 0; },
      [&](size_t q, size_t k) {
        const ShadowRay& s = scratch_shadow_[q];
        shadow_.set(shadows + k, s.origin, s.direction, shadow_tmin, s.tmax, path(q));
        shadow_contribution_[shadows + k] = s.contribution;
      });
  const size_t new_nexts = compact(
      n, [&](size_t q) { return has_next_[q] != 0; },
      [&](size_t q, size_t k) {
        const ShadowRay& s = scratch_next_[q];  // a bounce ray: origin and direction
        next_.set(nexts + k, s.origin, s.direction, 0.f, INFINITY, path(q));
      });
  shadow_.resize(shadows + new_shadows);
  shadow_contribution_.resize(shadows + new_shadows);
  next_.resize(nexts + new_nexts);
}

// Shadow rays that reach their light add to their path (at most one per path).
void Wavefront::shadow_rays() {
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

// The paths that ended go to the film, in slot order; their slots are free again.
uint64_t Wavefront::to_film(Film& film) {
  select(
      ended_.size(), [&](size_t slot) { return ended_[slot] != 0; }, queue_);
  const bool first = first_hits_ && film.aovs().first_hit();
  film.add_in_order(
      queue_.size(), [&](size_t k) { return paths_.pixel[queue_[k]]; },
      [&](size_t k) { return paths_.radiance[queue_[k]]; },
      [&](size_t k) { return first ? &paths_.first[queue_[k]] : nullptr; });
  tbb::parallel_for(size_t(0), queue_.size(), [&](size_t k) { ended_[queue_[k]] = 0; });
  // Free slots are taken from the back: the lowest-numbered first.
  const size_t had = free_.size(), ended = queue_.size();
  free_.resize(had + ended);
  tbb::parallel_for(size_t(0), ended, [&](size_t k) { free_[had + k] = queue_[ended - 1 - k]; });
  return queue_.size();
}

}  // namespace dacrt
