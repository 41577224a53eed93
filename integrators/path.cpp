// path (the default integrator): unidirectional path tracing. Every surface a path meets
// reflects (or, thin-walled, transmits) by the glTF metallic-roughness BRDF around the shading
// normal (materials/gltf_brdf.h), and a volume's boundary also refracts into it (materials/
// bsdf.h), where the path's media stack absorbs and sets the IORs (integrators/media.h); paths end by Russian roulette from --max-depth's roulette depth
// (3) on, or at --max-depth scattering events (default 64). At each vertex next-event estimation
// samples emissive triangles and punctual lights by power, or the environment map, and is
// combined with BSDF sampling by multiple importance sampling (integrators/light_sampling.h).
// Scenes without emitters trace no shadow rays. Runs on the wavefront loop (integrators/
// wavefront.h): the stages below are its shading stage.
//   escaped → emitted → roulette → material (NEE pushes shadow rays, BSDF sampling bounce rays),
//   all four in one pass over the batch
#include "dacrt/integrators/path.h"

#include <tbb/parallel_for.h>

#include <bit>
#include <cmath>
#include <memory>
#include <string>

#include "dacrt/materials/sampling.h"
#include "dacrt/scene/surface.h"
#include "dacrt/tracer/ray.h"

namespace dacrt {
namespace {

// The share of bounce rays from the camera's first hits that escape to the environment: a pilot
// of 32 × 32 camera rays through pixel centres and one cosine-weighted bounce from each hit
// (a Fibonacci lattice of numbers, so the same every render). Next-event estimation of a
// uniform sky pays where much of it is seen from the surfaces and other lights are sampled
// already (the sky then takes a share of shadow rays traced anyway): on the DamagedHelmet under
// a sky of 1 (384², 32 spp; its emissive parts are lights) it cut noise² by 0.73x for 1.16x the
// time, while inside the Sponza atrium, lit through its roof, the shadow rays were mostly
// blocked (noise² 0.78x for 1.7x the time).
double escaping_share(const Geometry& g, const Shot& shot, Backend& backend) {
  constexpr int grid = 32;
  RayBatch rays;
  rays.type = RayType::primary;
  const CameraProjection camera(shot.camera, shot.width, shot.height);
  for (int j = 0; j < grid; ++j)
    for (int i = 0; i < grid; ++i) {
      glm::vec3 o, d;
      const float x = (float(i) + 0.5f) * float(shot.width) / grid;
      const float y = (float(j) + 0.5f) * float(shot.height) / grid;
      const float tmin = camera.ray(x, y, o, d);
      rays.push(o, d, tmin, INFINITY, uint32_t(rays.size()));
    }
  HitBatch hits;
  hits.resize(rays.size());
  backend.intersect(rays, hits);
  RayBatch bounces;
  bounces.type = RayType::bounce;
  for (size_t k = 0; k < rays.size(); ++k) {
    if (!hits.hit(k)) continue;
    const uint32_t tri = hits.prim[k];
    const SpawnPoint at = spawn_point(g.vertex(tri, 0), g.vertex(tri, 1), g.vertex(tri, 2),
                                      hits.u[k], hits.v[k]);
    glm::vec3 n = g.unit_normal(tri);
    if (glm::dot(n, rays.direction(k)) > 0.f) n = -n;
    const float u1 = (float(bounces.size()) + 0.5f) / float(rays.size());
    const float u2 = float(std::fmod(double(bounces.size()) * 0.6180339887498949, 1.0));
    const glm::vec3 d = Frame(n).to_world(sample_cosine_hemisphere(u1, u2));
    bounces.push(offset_ray_origin(at, n), d, 0.f, INFINITY, uint32_t(k));
  }
  if (bounces.size() == 0) return 1.0;  // nothing is hit: the sky is all there is
  hits.resize(bounces.size());
  backend.intersect(bounces, hits);
  size_t escaped = 0;
  for (size_t k = 0; k < bounces.size(); ++k) escaped += !hits.hit(k);
  return double(escaped) / double(bounces.size());
}

// The constant map that samples a uniform environment as a light, or null where it is not
// sampled (black, a map given already, or `automatic` and the pilot finds the scene closed).
std::unique_ptr<const EnvironmentMap> uniform_environment(const Scene& scene, const Shot& shot,
                                                          Backend& backend,
                                                          const RenderSettings& s,
                                                          RenderStats& stats) {
  using Mode = RenderSettings::EnvironmentSampling;
  const glm::vec3 e = shot.environment;
  if (shot.environment_map || s.sample_environment == Mode::off || !(e.x + e.y + e.z > 0.f))
    return nullptr;
  if (s.sample_environment == Mode::automatic) {
    // Where nothing else is sampled, every shadow ray and light sample would be new work: the
    // dragon under a sky of 1 (1024², 64 spp) took 1.68x the time with them.
    bool lights = !shot.lights.empty();
    for (const Material& m : scene.materials) lights |= m.emitter();
    if (!lights) {
      stats.skipped.push_back("environment light samples (no other light is sampled; "
                              "--sample-environment on)");
      return nullptr;
    }
    constexpr double open = 0.25;
    const double share = escaping_share(scene.geometry, shot, backend);
    if (share < open) {
      stats.skipped.push_back("environment light samples (" +
                              std::to_string(int(std::lround(100 * share))) +
                              " % of pilot bounce rays escape; --sample-environment on)");
      return nullptr;
    }
  }
  // A constant map, which EnvironmentMap samples uniformly over the sphere (its size is moot).
  Image image(1, 1);
  for (size_t k = 0; k < image.rgb.size(); k += 3)
    image.rgb[k] = e.x, image.rgb[k + 1] = e.y, image.rgb[k + 2] = e.z;
  return std::make_unique<const EnvironmentMap>(std::move(image), "the uniform environment");
}

}  // namespace

PathTracer::PathTracer(const Scene& scene, const Shot& shot, Backend& backend,
                       const RenderSettings& settings)
    : Wavefront(scene, shot, backend, settings),
      uniform_map_(uniform_environment(scene, shot_, backend, settings, stats_)),
      map_(shot_.environment_map && !shot_.environment_map->black() ? shot_.environment_map.get()
                                                                    : uniform_map_.get()),
      lights_(scene, shot_.lights, map_, TriangleSampling::solid_angle_if_large,
              settings.light_sampler),
      media_(scene.materials) {
  if (lights_.empty())
    stats_.skipped.insert(
        stats_.skipped.begin(),
        "shadow rays (the scene has no emitters and no lights, and no environment map)");
  if (!lights_.sampler().empty()) {
    stats_.light_sampler = lights_.by_point() ? "tree" : "power";
    stats_.light_entries = lights_.sampler().entries();
  }
  for (const Material& m : scene.materials) emitters_ |= m.emissive();
  dims_ = {roulette, bsdf_u};
  if (!lights_.empty()) dims_.insert(dims_.end(), {light_pick, light_u});
  if (map_) dims_.insert(dims_.end(), {light_source, environment_u, environment_pixel_u});
  bool lambertian = true;
  for (const std::optional<GltfBrdf>& brdf : uniform_brdf_)
    lambertian &= brdf && brdf->lambertian();
  if (!lambertian) dims_.push_back(bsdf_lobe);
  drawn_ = drawn(dims_);
  for (size_t m = 0; m < scene.materials.size(); ++m) {
    const std::optional<GltfBrdf>& brdf = uniform_brdf_[m];
    const bool ours =
        s_.lambert_lanes && !map_ && brdf && brdf->lambertian() && !scene.materials[m].emissive();
    lambert_material_.push_back(ours);
    lambert_albedo_.push_back(ours ? brdf->base() : glm::vec3(0.f));
    lambert_ |= ours;
  }
  lambert_scene_ = {!scene.normals.empty(), !lights_.empty(), lights_.solid_angle(),
                    float(LightSampling::min_solid_angle), 1.f / roulette_floor};
}

static_assert(LambertIn::lanes == sampler_lanes, "a group of rays is shaded and drawn for at once");

uint32_t PathTracer::shade_lambert_lanes(const RayBatch& rays, const HitBatch& hits, size_t first,
                                         size_t lanes, const VertexNumbers* numbers, LambertIn& in,
                                         LambertOut& out) {
  const Geometry& g = scene_.geometry;
  for (size_t k = 0; k < lanes; ++k) {
    const size_t i = first + k;
    const uint32_t tri = hits.prim[i];
    in.ok[k] = hits.hit(i) && lambert_material_[g.material[tri]];
    // (Their shadow rays know nothing of absorbing media.)
    if (in.ok[k] && media_.absorbing() && stacks_[rays.path[i]].size) in.ok[k] = false;
    if (!in.ok[k]) continue;
    const uint32_t path = rays.path[i], depth = paths_.depth[path];
    const glm::vec3 d = rays.direction(i), &beta = paths_.throughput[path],
                    &albedo = lambert_albedo_[g.material[tri]];
    for (int a = 0; a < 3; ++a) {
      in.d[a][k] = d[a], in.beta[a][k] = beta[a], in.albedo[a][k] = albedo[a];
      for (int c = 0; c < 3; ++c) in.corner[c][a][k] = g.corners[tri][size_t(c)][a];
    }
    if (lambert_scene_.normals)
      for (int c = 0; c < 3; ++c)
        for (int a = 0; a < 3; ++a) in.normal[c][a][k] = scene_.normals[3 * size_t(tri) + c][a];
    in.u[k] = hits.u[i], in.v[k] = hits.v[i];
    in.below_max[k] = int(depth) < s_.max_depth;
    in.roulette[k] = int(depth) >= s_.roulette_depth;
    const VertexNumbers& u = numbers[k];
    in.u_roulette[k] = u[roulette], in.u_bsdf[0][k] = u[bsdf_u], in.u_bsdf[1][k] = u[bsdf_v];
    if (!lambert_scene_.lights) continue;
    in.u_light[0][k] = u[light_u], in.u_light[1][k] = u[light_v];
    // The light tree chooses from the hit point, on the side the ray came from.
    LightContext at;
    if (lights_.by_point()) {
      const glm::vec3 n = g.unit_normal(tri);
      at = {(1.f - hits.u[i] - hits.v[i]) * g.vertex(tri, 0) + hits.u[i] * g.vertex(tri, 1) +
                hits.v[i] * g.vertex(tri, 2),
            glm::dot(n, d) < 0.f ? n : -n};
      light_from_[path] = at;
    }
    float pmf;
    const LightSampling::AreaEmitter* e = lights_.area_emitter(u[light_pick], at, pmf);
    in.light_ok[k] = e != nullptr;
    if (!e) continue;
    for (int a = 0; a < 3; ++a) {
      for (int c = 0; c < 3; ++c) in.light_corner[c][a][k] = e->corner[c][a];
      in.light_normal[a][k] = e->normal[a], in.light_centre[a][k] = e->centre[a];
      in.light_radiance[a][k] = e->radiance[a];
    }
    in.light_radius2[k] = e->radius2, in.light_area[k] = e->area, in.light_pmf[k] = pmf;
    in.light_double_sided[k] = e->double_sided;
  }
  shade_lambert(lambert_scene_, in, int(lanes), out);
  auto vec = [](const float(&a)[3][LambertOut::lanes], size_t k) {
    return glm::vec3(a[0][k], a[1][k], a[2][k]);
  };
  for (uint32_t left = out.taken; left; left &= left - 1) {
    const int k = std::countr_zero(left);
    const size_t i = first + size_t(k);
    const uint32_t path = rays.path[i];
    paths_.throughput[path] = vec(out.beta, k);
    const glm::vec3 origin = vec(out.origin, k);
    const bool bounces = out.bounce >> k & 1;
    ended_[path] = !bounces;
    if (bounces) {
      paths_.bsdf_pdf[path] = out.pdf[k];
      scratch_next_[i].origin = origin;
      scratch_next_[i].direction = vec(out.direction, k);
      has_next_[i] = 1;
    }
    if (out.shadow >> k & 1) {
      scratch_shadow_[i] = {origin, vec(out.to_light, k), 1.f - shadow_epsilon,
                            vec(out.contribution, k)};
      has_shadow_[i] = 1;
    }
  }
  return out.taken;
}

// Stages 3–6 on one traced batch, in one pass over its rays: a ray that missed sees the
// environment (escaped); one that hit adds what it hit emits (emitted), its path may end by
// roulette, and else the material there scatters it (material). Paths that end are flagged for the
// film; shadow and bounce rays go to their queues in ray order.
void PathTracer::shade(const RayBatch& rays, const HitBatch& hits) {
  const size_t n = rays.size();
  scratch_rays(n);
  if (media_.any() && stacks_.size() < paths_.throughput.size())
    stacks_.resize(paths_.throughput.size());
  if (lights_.by_point() && light_from_.size() < paths_.throughput.size())
    light_from_.resize(paths_.throughput.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1024), [&](auto range) {
    VertexNumbers numbers[sampler_lanes];
    LambertIn in{};
    LambertOut out;
    std::unique_ptr<BrdfGroup> group =
        s_.lambert_lanes ? std::make_unique<BrdfGroup>() : nullptr;
    for (size_t first = range.begin(); first < range.end(); first += sampler_lanes) {
      const size_t lanes = std::min(sampler_lanes, range.end() - first);
      if (media_.any())
        for (size_t k = 0; k < lanes; ++k) attenuate(rays, hits, uint32_t(first + k));
      prefetch_triangles(hits, first + 3 * sampler_lanes, first + 4 * sampler_lanes);
      prefetch_textures(hits, first + 2 * sampler_lanes, first + 3 * sampler_lanes);
      draw(rays, first, lanes, dims_, numbers);
      const uint32_t taken =
          lambert_ ? shade_lambert_lanes(rays, hits, first, lanes, numbers, in, out) : 0;
      if (group) group->deferred = 0;
      for (size_t k = 0; k < lanes; ++k) {
        if (taken >> k & 1) continue;
        const size_t i = first + k;
        if (!hits.hit(i)) {
          escaped(rays, uint32_t(i));
          continue;
        }
        if (emitters_) emitted(rays, hits, uint32_t(i));
        const VertexDraw random{*this, rays.path[i], drawn_, numbers[k]};
        if (survives(rays.path[i], random))
          material(rays, hits, uint32_t(i), i, random, group.get(), int(k));
      }
      if (group && group->deferred) sample_brdf_lanes(rays, first, lanes, *group);
    }
  });
  push_rays(rays, nullptr);
}

void PathTracer::attenuate(const RayBatch& rays, const HitBatch& hits, uint32_t i) {
  const uint32_t path = rays.path[i];
  MediumStack& stack = stacks_[path];
  if (paths_.depth[path] == 0) {
    stack = {};
    return;
  }
  if (!stack.size || !media_.absorbing()) return;
  const float distance = hits.hit(i) ? hits.t[i] * glm::length(rays.direction(i)) : INFINITY;
  paths_.throughput[path] *= media_.transmittance(stack, distance);
}

// Stage 3: a ray that left the scene sees the environment; its path ends.
void PathTracer::escaped(const RayBatch& rays, uint32_t i) {
  const uint32_t path = rays.path[i];
  ended_[path] = 1;
  if (!map_) {
    paths_.radiance[path] += paths_.throughput[path] * shot_.environment;  // (0 under a black map)
  } else {
    // Also reachable by next-event estimation, after the first bounce: MIS.
    const glm::vec3 d = rays.direction(i);
    const float weight =
        paths_.depth[path] > 0 ? lights_.environment_weight(paths_.bsdf_pdf[path], d) : 1.f;
    paths_.radiance[path] += paths_.throughput[path] * map_->radiance(d) * weight;
  }
}

// Stage 4: an emitter hit adds its emission (weighed against next-event estimation after the
// camera ray).
void PathTracer::emitted(const RayBatch& rays, const HitBatch& hits, uint32_t i) {
  const Geometry& g = scene_.geometry;
  const uint32_t path = rays.path[i], tri = hits.prim[i];
  const Material& m = scene_.materials[g.material[tri]];
  if (!m.emissive()) return;
  // An unlit surface is seen by camera rays only (materials/material.h).
  if (m.unlit && paths_.depth[path] > 0) return;
  const glm::vec3 d = rays.direction(i);
  const float cos = glm::dot(g.unit_normal(tri), d);
  if (!(cos < 0.f || m.double_sided)) return;
  float weight = 1.f;
  if (paths_.depth[path] > 0)
    weight = lights_.emitter_weight(paths_.bsdf_pdf[path], tri, rays.origin(i), hits.t[i],
                                    std::abs(cos), g.area(tri),
                                    lights_.by_point() ? light_from_[path] : LightContext{});
  paths_.radiance[path] +=
      paths_.throughput[path] * emission_at(scene_, tri, hits.u[i], hits.v[i], -d) * weight;
}

// Stage 5: a path at the depth limit ends, and from roulette_depth on Russian roulette ends paths
// of low throughput (the survivors' throughput grows to compensate). True if the path goes on.
// A path survives with probability min(1, max(β) / roulette_floor), so survivors keep a
// throughput of at least roulette_floor (in their largest component). Ending paths sooner saves
// time but adds noise: on the Lambert Cornell box (256², 64 spp, noise² × seconds, lower is
// better) a floor of 1 cost 1.16× what 1/2 costs, 1/3 1.00×, and √β (Cycles' rule) 1.01×; on
// scenes/cornell-box.gltf (32 spp) 1 cost 1.08× and √β 1.02×.
bool PathTracer::survives(uint32_t path, const VertexDraw& random) {
  const int depth = int(paths_.depth[path]);
  bool keep = depth < s_.max_depth;
  if (keep && depth >= s_.roulette_depth) {
    glm::vec3& beta = paths_.throughput[path];
    const float p = std::min(1.f, std::max({beta.x, beta.y, beta.z}) * (1.f / roulette_floor));
    keep = random(Dimension::roulette) < p;
    if (keep) beta /= p;
  }
  if (!keep) ended_[path] = 1;
  return keep;
}

// Stage 6: the material at a surviving hit; next-event estimation writes a shadow ray, BSDF
// sampling a bounce ray, each in the ray's slot q of the scratch queues.
void PathTracer::material(const RayBatch& rays, const HitBatch& hits, uint32_t i, size_t q,
                          const VertexDraw& random, BrdfGroup* group, int k) {
  const uint32_t path = rays.path[i], tri = hits.prim[i], mat = scene_.geometry.material[tri];
  const glm::vec3 d = rays.direction(i);
  const Hit h = hit_at(rays, hits, i);
  const glm::vec3 &p = h.p, &ng = h.ng, &ns = h.ns;
  const SurfacePoint& surface = h.surface;
  const bool transmits = surface.brdf.transmission > 0.f && surface.brdf.metallic < 1.f;
  glm::vec3& beta = paths_.throughput[path];
  // A volume's boundary (integrators/media.h): refractive, with the IORs of the media on its two
  // sides; a dispersive one first makes the path follow one colour channel.
  MediumStack* stack = transmits && media_.medium(mat) ? &stacks_[path] : nullptr;
  const bool front = stack && glm::dot(scene_.geometry.unit_normal(tri), d) < 0.f;
  if (stack && media_.medium(mat)->dispersion > 0.f && stack->channel < 0) {
    const int c = std::min(2, int(3.f * random(wavelength)));
    glm::vec3 one(0.f);
    one[c] = 3.f * beta[c];
    beta = one;
    stack->channel = int8_t(c);
  }
  const Frame frame(ns);
  const ShadingPoint x{ng,
                       frame,
                       stack ? Bsdf::volume(framed_params(h), media_.eta(*stack, mat, front), front)
                             : Bsdf(brdf_at(h, tri)),
                       frame.to_local(-d),
                       offset_ray_origin({p, h.p_error}, ng),
                       transmits ? offset_ray_origin({p, h.p_error}, -ng) : p,
                       transmits};
  if (lights_.by_point()) light_from_[path] = LightSampling::context(p, x);
  if (!lights_.empty()) {
    ShadowRay& shadow = scratch_shadow_[q];
    auto pairs = [&](Dimension first) { return random.pair(first); };
    if (lights_.sample(p, x, random, pairs, shadow)) {
      shadow.contribution *= beta;
      if (media_.absorbing()) {
        // The shadow ray runs in the medium on its side of the surface.
        MediumStack beyond = stacks_[path];
        if (stack && glm::dot(shadow.direction, ng) < 0.f) Media::cross(beyond, mat, front);
        shadow.contribution *=
            media_.transmittance(beyond, shadow.tmax * glm::length(shadow.direction));
      }
      has_shadow_[q] = carries_light(shadow.contribution);
    }
  }

  // BSDF sampling: reflection keeps to the arrival side, transmission crosses to the other.
  ended_[path] = 1;  // unless it bounces
  const auto [u1, u2] = random.pair(bsdf_u);
  // (A Lambert surface has one lobe: its number is not drawn.)
  const float u_lobe = x.brdf.lambertian() ? 0.f : random(bsdf_lobe);
  if (group && !stack && !transmits && !x.brdf.dielectric() && x.brdf.gltf().plain()) {
    // The BRDF lanes sample it with the group's others (sample_brdf_lanes).
    BrdfIn& in = group->in;
    const GltfBrdf& brdf = x.brdf.gltf();
    for (int a = 0; a < 3; ++a) {
      in.wo[a][k] = x.wo[a], in.base[a][k] = brdf.base()[a], in.f0[a][k] = brdf.f0()[a];
      in.frame[0][a][k] = x.frame.s[a], in.frame[1][a][k] = x.frame.t[a];
      in.frame[2][a][k] = x.frame.n[a], in.ng[a][k] = ng[a];
    }
    in.u_lobe[k] = u_lobe, in.u[0][k] = u1, in.u[1][k] = u2;
    in.metallic[k] = brdf.metallic(), in.alpha[k] = brdf.alpha(), in.f90[k] = brdf.f90();
    group->above[k] = x.above;
    group->deferred |= 1u << k;
    return;
  }
  const auto s = x.brdf.sample(x.wo, u_lobe, u1, u2);
  if (!s) return;
  const glm::vec3 wi = x.frame.to_world(s->wi);
  const glm::vec3* origin = x.origin_towards(wi, s->wi);
  if (!origin) return;
  beta *= s->weight;
  if (!carries_light(beta)) return;
  if (stack && s->wi.z < 0.f) Media::cross(*stack, mat, front);
  bounce(q, path, *origin, wi, s->pdf);
}

void PathTracer::bounce(size_t q, uint32_t path, const glm::vec3& origin,
                        const glm::vec3& direction, float pdf) {
  paths_.bsdf_pdf[path] = pdf;
  scratch_next_[q].origin = origin;
  scratch_next_[q].direction = direction;
  has_next_[q] = 1;
  ended_[path] = 0;
}

// The BSDF sampling material() left to the BRDF lanes, for the group's rays [first, first + lanes):
// what material() does after x.brdf.sample, lane by lane.
void PathTracer::sample_brdf_lanes(const RayBatch& rays, size_t first, size_t lanes,
                                   BrdfGroup& group) {
  for (size_t k = 0; k < lanes; ++k) group.in.ok[k] = group.deferred >> k & 1;
  sample_brdf(group.in, int(lanes), group.out);
  const BrdfOut& out = group.out;
  for (uint32_t left = out.sampled & group.deferred; left; left &= left - 1) {
    const int k = std::countr_zero(left);
    const size_t i = first + size_t(k);
    const uint32_t path = rays.path[i];
    glm::vec3& beta = paths_.throughput[path];
    beta *= glm::vec3(out.weight[0][k], out.weight[1][k], out.weight[2][k]);
    if (!carries_light(beta)) continue;
    bounce(i, path, group.above[k], glm::vec3(out.wi[0][k], out.wi[1][k], out.wi[2][k]),
           out.pdf[k]);
  }
}

const Integrator::Registration registration{
    "path",
    [](const Scene& scene, const Shot& shot, Backend& backend, const RenderSettings& settings) {
      return std::make_unique<PathTracer>(scene, shot, backend, settings);
    }};

}  // namespace dacrt
