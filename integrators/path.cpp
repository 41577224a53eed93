// path: a wavefront path tracer. Each wavefront holds up to RenderSettings::wavefront live paths;
// every bounce runs the same short list of stages on whole batches:
//   camera rays → intersect → shade (escaped rays, emitters hit, Russian roulette, next-event
//   estimation, BSDF sampling) → occluded(shadow rays) → intersect(bounce rays) → …
// Surfaces reflect by the glTF metallic-roughness BRDF (materials/gltf_brdf.h) around the
// shading normal. Next-event estimation samples emissive triangles by power and is combined with
// BRDF sampling by multiple importance sampling (power heuristic), so emitters of any size and
// lobes of any width converge well. Scenes without emitters trace no shadow rays.
#include <tbb/parallel_for.h>

#include <chrono>

#include "integrators/integrator.h"
#include "integrators/lights.h"
#include "materials/sampling.h"
#include "scene/surface.h"
#include "tracer/ray.h"
#include "util/random.h"

namespace dacrt {
namespace {

using Clock = std::chrono::steady_clock;

// Random dimensions of one path vertex, for the counter-based generator.
enum Dimension : uint32_t {
  pixel_x,
  pixel_y,
  roulette,
  light_pick,
  light_u,
  light_v,
  bsdf_u,
  bsdf_v,
  bsdf_lobe,
  environment_u,
  environment_v,
  alpha  // + the ray type, + the triangle × 256: one number per ray and triangle
};

class PathTracer final : public Integrator {
 public:
  PathTracer(const Scene& scene, Backend& backend, const RenderSettings& settings)
      : scene_(scene),
        backend_(backend),
        s_(settings),
        lights_(scene),
        map_(settings.environment_map && !settings.environment_map->black()
                 ? settings.environment_map.get()
                 : nullptr),
        // Next-event estimation picks the map or the scene's lights: half and half when both.
        map_share_(map_ ? (lights_.empty() ? 1.f : 0.5f) : 0.f) {
    if (s_.camera < 0 || size_t(s_.camera) >= scene.cameras.size())
      throw Error("camera " + std::to_string(s_.camera) + " does not exist (the scene has " +
                  std::to_string(scene.cameras.size()) + ")");
    if (lights_.empty() && !map_)
      stats_.skipped.push_back(
          "shadow rays (the scene has no emitters and no lights, and no environment map)");
    std::vector<uint8_t> tested(scene.geometry.size(), 0);
    bool any = false;
    for (size_t t = 0; t < tested.size(); ++t)
      any |= tested[t] =
          scene.materials[scene.geometry.material[t]].alpha_mode != Material::AlphaMode::opaque;
    if (any) alpha_ = std::make_unique<AlphaFilter>(std::move(tested), *this);
    for (std::string& what : scene.unused_work()) stats_.skipped.push_back(std::move(what));
  }

  const RenderStats& stats() const override { return stats_; }

  void render(Film& film, Progress& progress) override {
    auto start_time = Clock::now();
    const uint64_t pixels = uint64_t(s_.width) * s_.height;
    const uint64_t total = pixels * uint64_t(s_.spp);
    const size_t wavefront = std::max<size_t>(1, s_.wavefront);
    for (uint64_t first = 0; first < total; first += wavefront) {
      const size_t n = size_t(std::min<uint64_t>(wavefront, total - first));
      generate_camera_rays(first, n);
      for (int depth = 0; rays_.size() > 0; ++depth) {
        trace(rays_, depth);
        shade(depth);
        trace_shadows();
        std::swap(rays_, next_);
      }
      for (size_t j = 0; j < n; ++j) film.add(pixel_[j], radiance_[j]);
      stats_.paths += n;
      progress.update(first + n, stats_.total_rays());
    }
    progress.finish();
    stats_.dropped_samples = film.dropped();
    stats_.seconds = std::chrono::duration<double>(Clock::now() - start_time).count();
  }

 private:
  // Alpha-masked and alpha-blended materials, seen through by the backend's hit filter. A blended
  // surface stops a ray with probability alpha, drawn from the path's random stream (so renders
  // stay deterministic and the same for every backend).
  class AlphaFilter final : public HitFilter {
   public:
    AlphaFilter(std::vector<uint8_t> tested, const PathTracer& tracer)
        : HitFilter(std::move(tested)), t_(tracer) {}
    bool accept(const RayBatch& rays, uint32_t ray, uint32_t tri, float u, float v) const override {
      const uint32_t path = rays.path[ray];
      const float xi =
          uniform_float(t_.s_.seed, t_.pixel_[path], t_.sample_[path], uint64_t(t_.depth_),
                        uint64_t(alpha) + uint64_t(rays.type) + (uint64_t(tri) << 8));
      return xi < coverage_at(t_.scene_, tri, u, v);
    }

   private:
    const PathTracer& t_;
  };

  float random(size_t path, int depth, Dimension dim) const {
    return uniform_float(s_.seed, pixel_[path], sample_[path], uint64_t(depth), uint64_t(dim));
  }

  void generate_camera_rays(uint64_t first, size_t n) {
    const uint64_t pixels = uint64_t(s_.width) * s_.height;
    const Camera& camera = scene_.cameras[s_.camera];
    throughput_.assign(n, glm::vec3(1.f));
    radiance_.assign(n, glm::vec3(0.f));
    bsdf_pdf_.assign(n, 0.f);
    pixel_.resize(n);
    sample_.resize(n);
    rays_.type = RayType::primary;
    rays_.resize(n);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](auto range) {
      for (size_t j = range.begin(); j != range.end(); ++j) {
        uint64_t id = first + j;
        pixel_[j] = uint32_t(id % pixels);
        sample_[j] = uint32_t(id / pixels);
        float x = float(pixel_[j] % uint32_t(s_.width)) + random(j, 0, pixel_x);
        float y = float(pixel_[j] / uint32_t(s_.width)) + random(j, 0, pixel_y);
        glm::vec3 o, d;
        const float tmin = camera_ray(camera, s_.width, s_.height, x, y, o, d);
        rays_.set(j, o, d, tmin, INFINITY, uint32_t(j));
      }
    });
  }

  void trace(const RayBatch& rays, int depth) {
    depth_ = depth;
    auto t0 = Clock::now();
    backend_.intersect(rays, hits_, alpha_.get());
    double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    auto& by_type = stats_.by_type[size_t(rays.type)];
    by_type.rays += rays.size(), by_type.seconds += seconds;
    if (rays.type == RayType::bounce) {
      if (stats_.by_bounce.size() < size_t(depth)) stats_.by_bounce.resize(depth);
      stats_.by_bounce[depth - 1].rays += rays.size();
      stats_.by_bounce[depth - 1].seconds += seconds;
    }
  }

  // Shading writes at most one shadow ray and one bounce ray per incoming ray, each into the
  // incoming ray's slot; the slots are compacted afterwards.
  void shade(int depth) {
    const size_t n = rays_.size();
    shadow_.type = RayType::shadow;
    shadow_.resize(n);
    next_.type = RayType::bounce;
    next_.resize(n);
    shadow_contribution_.resize(n);
    has_shadow_.assign(n, 0);
    has_next_.assign(n, 0);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1024), [&](auto range) {
      for (size_t i = range.begin(); i != range.end(); ++i) shade_one(i, depth);
    });
    compact(shadow_, has_shadow_, &shadow_contribution_);
    compact(next_, has_next_, nullptr);
  }

  void shade_one(size_t i, int depth) {
    const uint32_t path = rays_.path[i];
    const glm::vec3 d = rays_.direction(i);
    glm::vec3& beta = throughput_[path];
    if (!hits_.hit(i)) {
      if (!s_.environment_map) {
        radiance_[path] += beta * s_.environment;
      } else if (map_) {
        // Also reachable by next-event estimation, after the first bounce: MIS.
        const float weight =
            depth > 0 ? power_heuristic(bsdf_pdf_[path], map_share_ * map_->pdf(d)) : 1.f;
        radiance_[path] += beta * map_->radiance(d) * weight;
      }
      return;
    }
    const Geometry& g = scene_.geometry;
    const uint32_t tri = hits_.prim[i];
    const Material& m = scene_.materials[g.material[tri]];
    glm::vec3 ng = g.normal(tri);
    const float area2 = glm::length(ng);
    ng /= area2;
    const bool front = glm::dot(ng, d) < 0.f;
    const float u = hits_.u[i], v = hits_.v[i];
    const SurfacePoint surface = surface_at(scene_, tri, u, v, ng);

    if (m.emissive() && (front || m.double_sided)) {
      float weight = 1.f;
      if (depth > 0) {
        float t = hits_.t[i];
        float light_pdf = (1.f - map_share_) * lights_.pmf(tri) * t * t /
                          (std::abs(glm::dot(ng, d)) * 0.5f * area2);
        weight = power_heuristic(bsdf_pdf_[path], light_pdf);
      }
      radiance_[path] += beta * surface.emission * weight;
    }
    if (depth >= s_.max_depth) return;
    if (depth >= s_.roulette_depth) {
      float q = std::min(1.f, std::max({beta.x, beta.y, beta.z}));
      if (random(path, depth, roulette) >= q) return;
      beta /= q;
    }

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
    const Vertex x{ng,
                   frame,
                   GltfBrdf(surface.brdf),
                   frame.to_local(-d),
                   offset_ray_origin(p, ng),
                   transmits ? offset_ray_origin(p, -ng) : p,
                   transmits};

    if (!lights_.empty() || map_) next_event(i, path, depth, p, x);

    // BSDF sampling: reflection keeps to the arrival side, transmission crosses to the other.
    const auto s = x.brdf.sample(x.wo, random(path, depth, bsdf_lobe), random(path, depth, bsdf_u),
                                 random(path, depth, bsdf_v));
    if (!s) return;
    const glm::vec3 wi = x.frame.to_world(s->wi);
    const glm::vec3* origin = x.origin_towards(wi, s->wi);
    if (!origin) return;
    beta *= s->weight;
    if (!(beta.x > 0.f || beta.y > 0.f || beta.z > 0.f)) return;
    bsdf_pdf_[path] = s->pdf;
    next_.set(i, *origin, wi, 0.f, INFINITY, path);
    has_next_[i] = 1;
  }

  // A shading point as next-event estimation and BSDF sampling see it.
  struct Vertex {
    glm::vec3 ng;  // geometric normal, on the side the ray arrived from
    Frame frame;   // around the shading normal, on the same side
    GltfBrdf brdf;
    glm::vec3 wo;            // towards the viewer, local
    glm::vec3 above, below;  // ray origins offset to either side (below only if it transmits)
    bool transmits;
    // Where a ray leaving along wi (wi_local in the frame) starts, or null if the BSDF sends no
    // light that way: the shading and geometric normals must agree on the side, and only a
    // transmissive material reaches the other one.
    const glm::vec3* origin_towards(const glm::vec3& wi, const glm::vec3& wi_local) const {
      if (wi_local.z > 0.f && glm::dot(wi, ng) > 0.f) return &above;
      if (transmits && wi_local.z < 0.f && glm::dot(wi, ng) < 0.f) return &below;
      return nullptr;
    }
  };

  void next_event(size_t i, uint32_t path, int depth, const glm::vec3& p, const Vertex& x) {
    const Geometry& g = scene_.geometry;
    float pick = random(path, depth, light_pick);
    if (pick < map_share_) return environment(i, path, depth, x);
    pick = std::min((pick - map_share_) / (1.f - map_share_), 0x1.fffffep-1f);
    LightSampler::Sample ls =
        lights_.sample(pick, random(path, depth, light_u), random(path, depth, light_v));
    ls.pmf *= 1.f - map_share_;
    if (ls.light >= 0) return punctual(i, path, p, scene_.lights[size_t(ls.light)], ls.pmf, x);
    const Material& light = scene_.materials[g.material[ls.triangle]];
    glm::vec3 emission = emission_at(scene_, ls.triangle, ls.barycentric.x, ls.barycentric.y);
    // An alpha-tested emitter shines only as much as it stops rays there.
    if (light.alpha_mode != Material::AlphaMode::opaque)
      emission *= coverage_at(scene_, ls.triangle, ls.barycentric.x, ls.barycentric.y);
    glm::vec3 to = ls.point - p;
    float dist2 = glm::dot(to, to);
    if (!(dist2 > 0.f)) return;
    glm::vec3 wi = to / std::sqrt(dist2);
    glm::vec3 nl = g.normal(ls.triangle);
    float light_area = 0.5f * glm::length(nl);
    nl = glm::normalize(nl);
    float cos_light = -glm::dot(wi, nl);
    if (light.double_sided) cos_light = std::abs(cos_light);
    const glm::vec3 wi_local = x.frame.to_local(wi);
    const glm::vec3* origin = x.origin_towards(wi, wi_local);
    if (cos_light <= 0.f || !origin) return;
    float light_pdf = ls.pmf * dist2 / (cos_light * light_area);
    float weight = power_heuristic(light_pdf, x.brdf.pdf(x.wo, wi_local));
    glm::vec3 c = throughput_[path] * x.brdf.eval(x.wo, wi_local) * emission *
                  (std::abs(wi_local.z) * weight / light_pdf);
    // The segment runs between the two offset points, so neither surface can occlude it.
    glm::vec3 target = offset_ray_origin(ls.point, glm::dot(nl, wi) < 0.f ? nl : -nl);
    queue_shadow(i, path, *origin, target - *origin, 1.f, c);
  }

  // Puts a shadow ray in slot i that adds `c` to the path if nothing occludes it; none if c is 0.
  void queue_shadow(size_t i, uint32_t path, const glm::vec3& origin, const glm::vec3& direction,
                    float tmax, const glm::vec3& c) {
    if (!(c.x > 0.f || c.y > 0.f || c.z > 0.f)) return;
    shadow_.set(i, origin, direction, 0.f, tmax, path);
    shadow_contribution_[i] = c;
    has_shadow_[i] = 1;
  }

  // Next-event estimation towards the environment map, weighed against BSDF sampling (MIS).
  void environment(size_t i, uint32_t path, int depth, const Vertex& x) {
    const EnvironmentMap::Sample es =
        map_->sample(random(path, depth, environment_u), random(path, depth, environment_v));
    const float pdf = map_share_ * es.pdf;
    if (!(pdf > 0.f)) return;
    const glm::vec3 wi_local = x.frame.to_local(es.direction);
    const glm::vec3* origin = x.origin_towards(es.direction, wi_local);
    if (!origin) return;
    const float weight = power_heuristic(pdf, x.brdf.pdf(x.wo, wi_local));
    const glm::vec3 c = throughput_[path] * x.brdf.eval(x.wo, wi_local) * es.radiance *
                        (std::abs(wi_local.z) * weight / pdf);
    queue_shadow(i, path, *origin, es.direction, INFINITY, c);
  }

  // Next-event estimation towards a punctual light: a delta, so no MIS (BSDF sampling never
  // finds it). The shadow segment ends at the light, or leaves the scene towards a directional one.
  void punctual(size_t i, uint32_t path, const glm::vec3& p, const PunctualLight& light, float pmf,
                const Vertex& x) {
    const bool directional = light.type == PunctualLight::Type::directional;
    const glm::vec3 to = directional ? light.direction : p - light.position;  // light → point
    const float dist = glm::length(to);
    if (!(dist > 0.f)) return;
    const glm::vec3 wi = -to / dist;
    const glm::vec3 wi_local = x.frame.to_local(wi);
    const glm::vec3* origin = x.origin_towards(wi, wi_local);
    if (!origin) return;
    const glm::vec3 c = throughput_[path] * x.brdf.eval(x.wo, wi_local) *
                        light.irradiance_towards(to) * (std::abs(wi_local.z) / pmf);
    if (directional)
      queue_shadow(i, path, *origin, wi, INFINITY, c);
    else
      queue_shadow(i, path, *origin, light.position - *origin, 1.f, c);
  }

  void trace_shadows() {
    if (shadow_.size() == 0) return;
    occluded_.resize(shadow_.size());
    auto t0 = Clock::now();
    backend_.occluded(shadow_, occluded_, alpha_.get());
    auto& by_type = stats_.by_type[size_t(RayType::shadow)];
    by_type.rays += shadow_.size();
    by_type.seconds += std::chrono::duration<double>(Clock::now() - t0).count();
    for (size_t k = 0; k < shadow_.size(); ++k)
      if (!occluded_[k]) radiance_[shadow_.path[k]] += shadow_contribution_[k];
  }

  // Keeps the slots whose flag is set, in order.
  static void compact(RayBatch& rays, const std::vector<uint8_t>& keep,
                      std::vector<glm::vec3>* payload) {
    size_t out = 0;
    for (size_t i = 0; i < keep.size(); ++i) {
      if (!keep[i]) continue;
      if (out != i) {
        rays.set(out, rays.origin(i), rays.direction(i), rays.tmin[i], rays.tmax[i], rays.path[i]);
        if (payload) (*payload)[out] = (*payload)[i];
      }
      ++out;
    }
    rays.resize(out);
    if (payload) payload->resize(out);
  }

  const Scene& scene_;
  Backend& backend_;
  const RenderSettings s_;
  const LightSampler lights_;
  const EnvironmentMap* map_;  // null: uniform (or black) environment, reached by BRDF sampling
  const float map_share_;      // probability that next-event estimation samples the map
  RenderStats stats_;
  std::unique_ptr<AlphaFilter> alpha_;  // null when every material is opaque
  int depth_ = 0;                       // of the batch being traced (shadow rays: their vertex's)

  // The wavefront's paths, indexed by RayBatch::path.
  std::vector<glm::vec3> throughput_, radiance_;
  std::vector<uint32_t> pixel_, sample_;
  std::vector<float> bsdf_pdf_;  // solid-angle pdf of the direction the path's last ray took
  // The batches of the current bounce.
  RayBatch rays_, next_, shadow_;
  HitBatch hits_;
  std::vector<glm::vec3> shadow_contribution_;
  std::vector<uint8_t> has_shadow_, has_next_, occluded_;
};

const Integrator::Registration registration{
    "path", [](const Scene& scene, Backend& backend, const RenderSettings& settings) {
      return std::make_unique<PathTracer>(scene, backend, settings);
    }};

}  // namespace
}  // namespace dacrt
