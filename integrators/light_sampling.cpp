// Next-event estimation and MIS (see light_sampling.h): the environment map, emissive triangles
// and punctual lights as shadow rays.
#include "dacrt/integrators/light_sampling.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/constants.hpp>

#include "dacrt/integrators/lambert_lanes.h"
#include "dacrt/integrators/spherical_triangle.h"
#include "dacrt/scene/surface.h"
#include "dacrt/tracer/ray.h"

namespace dacrt {
namespace {

glm::dvec3 corner(const Geometry& g, uint32_t tri, int k) {
  return glm::dvec3(g.vertex(tri, k));
}

}  // namespace

LightSampling::LightSampling(const Scene& scene, std::span<const PunctualLight> lights,
                             const EnvironmentMap* map, TriangleSampling triangles,
                             LightPicking picking)
    : scene_(scene),
      punctual_(lights),
      // auto chooses as it does without an environment (LightSampler::tree_threshold): beside a
      // sampled sky of 1 the tree won on DamagedHelmet (15 452 emissive triangles, 256²: equal
      // noise in 0.84x the time) and on 64 lamps (noise² 0.68x at equal time).
      lights_(scene, lights, picking),
      map_(map),
      // Next-event estimation picks the map or the scene's lights: half and half when both.
      map_share_(map_ ? (lights_.empty() ? 1.f : 0.5f) : 0.f),
      triangles_(triangles),
      area_emitters_(lights_.empty() ? 0 : lights_.entries()) {
  if (map_) return;
  const Geometry& g = scene.geometry;
  for (size_t entry = 0; entry < lights_.triangles(); ++entry) {
    const uint32_t tri = lights_.triangle(entry);
    const Material& m = scene.materials[g.material[tri]];
    const LightSampler::Emitter& e = *lights_.emitter(tri);
    if (!m.uniform_emission() || m.unlit || m.alpha_mode != Material::AlphaMode::opaque) continue;
    if (!(e.area >= 0x1p-60 && e.area <= 0x1p60)) continue;
    area_emitters_[entry] = AreaEmitter{{g.vertex(tri, 0), g.vertex(tri, 1), g.vertex(tri, 2)},
                                        e.normal,
                                        e.centre,
                                        m.emission,
                                        e.radius2,
                                        float(e.area),
                                        m.double_sided};
  }
}

double LightSampling::sampled_solid_angle(const glm::vec3& o, uint32_t tri) const {
  if (triangles_ == TriangleSampling::area) return 0.0;
  const Geometry& g = scene_.geometry;
  // Most points see most emitters under far less than min_solid_angle, and two cheap bounds of the
  // triangle's Ω tell so, without the exact Ω (normalisations and an atan2 in double): with a
  // ball around the triangle (out to its farthest corner from a centre, radius r, at distance D),
  // - the ball's cap, 2π (1 − √(1 − r²/D²)) < 2π r²/D²;
  // - A / (D − r)² for D > r: Ω = ∫ cos θ / d² dA over the triangle, whose points are all at
  //   least D − r away (on the Lambert Cornell box this one is the tighter one for most points).
  // In float, with a margin far above its rounding; the answer is the same either way. The
  // Lambert lanes repeat both (integrators/lambert_kernel.h).
  glm::vec3 centre;
  float r2, area;
  if (const LightSampler::Emitter* e = lights_.emitter(tri)) {
    centre = e->centre, r2 = e->radius2, area = float(e->area);
  } else {  // (an emitter that is never sampled, found by BSDF sampling)
    const glm::vec3 &v0 = g.vertex(tri, 0), &v1 = g.vertex(tri, 1), &v2 = g.vertex(tri, 2);
    centre = (v0 + v1 + v2) * (1.f / 3.f);
    r2 = std::max({glm::dot(v0 - centre, v0 - centre), glm::dot(v1 - centre, v1 - centre),
                   glm::dot(v2 - centre, v2 - centre)});
    area = float(g.area(tri));
  }
  const glm::vec3 to = centre - o;
  const float d2 = glm::dot(to, to);
  if (r2 < INFINITY && d2 < INFINITY) {
    if (solid_angle_ball * r2 <= float(min_solid_angle) * d2) return 0.0;
    const float gap = std::sqrt(d2) - std::sqrt(r2);
    if (gap > 0.f && solid_angle_area_margin * area <= float(min_solid_angle) * (gap * gap))
      return 0.0;
  }
  const glm::dvec3 c0 = corner(g, tri, 0), c1 = corner(g, tri, 1), c2 = corner(g, tri, 2);
  const double omega = triangle_solid_angle(glm::dvec3(o), c0, c1, c2);
  return omega > min_solid_angle && omega < max_solid_angle ? omega : 0.0;
}

// Towards the environment map, weighed against BSDF sampling (MIS).
bool LightSampling::environment(const ShadingPoint& x, const glm::vec4& u, ShadowRay& out) const {
  const EnvironmentMap::Sample es = map_->sample(u);
  const float pdf = map_share_ * es.pdf;
  if (!(pdf > 0.f)) return false;
  const glm::vec3 wi_local = x.frame.to_local(es.direction);
  const glm::vec3* origin = x.origin_towards(es.direction, wi_local);
  if (!origin) return false;
  const float weight = power_heuristic(pdf, x.brdf.pdf(x.wo, wi_local));
  out = {*origin, es.direction, INFINITY,
         x.brdf.eval(x.wo, wi_local) * es.radiance * (std::abs(wi_local.z) * weight / pdf)};
  return carries_light(out.contribution);
}

// Towards an emitter picked by power: a point on an emissive triangle (MIS with BSDF sampling) or
// a punctual light.
bool LightSampling::emitter(const glm::vec3& p, const ShadingPoint& x, float pick, float u1,
                            float u2, ShadowRay& out) const {
  const Geometry& g = scene_.geometry;
  LightSampler::Sample ls = lights_.sample(pick, u1, u2, context(p, x));
  ls.pmf *= 1.f - map_share_;
  if (ls.light >= 0) return punctual(p, punctual_[size_t(ls.light)], ls.pmf, x, out);
  // Large and near: the point is where a direction uniform in the triangle's solid angle meets
  // it (the area sample above is discarded), and the pdf is pmf / Ω.
  const double omega = sampled_solid_angle(p, ls.triangle);
  if (omega > 0.0) {
    const glm::dvec3 o(p), p0 = corner(g, ls.triangle, 0), e1 = corner(g, ls.triangle, 1) - p0,
                           e2 = corner(g, ls.triangle, 2) - p0;
    const glm::dvec3 dir =
        sample_spherical_triangle(glm::normalize(p0 - o), glm::normalize(p0 + e1 - o),
                                  glm::normalize(p0 + e2 - o), omega, u1, u2);
    const glm::dvec3 n = glm::cross(e1, e2);
    const double t = glm::dot(n, p0 - o) / glm::dot(n, dir);
    if (!(t > 0.0 && std::isfinite(t))) return false;
    // The barycentric coordinates of the hit, clamped onto the triangle against rounding.
    const glm::dvec3 r = o + t * dir - p0;
    const double d11 = glm::dot(e1, e1), d12 = glm::dot(e1, e2), d22 = glm::dot(e2, e2);
    const double r1 = glm::dot(r, e1), r2 = glm::dot(r, e2), det = d11 * d22 - d12 * d12;
    double b1 = std::max(0.0, (d22 * r1 - d12 * r2) / det);
    double b2 = std::max(0.0, (d11 * r2 - d12 * r1) / det);
    if (b1 + b2 > 1.0) b1 /= b1 + b2, b2 = 1.0 - b1;
    ls.barycentric = glm::vec2(float(b1), float(b2));
    ls.point = glm::vec3(p0 + b1 * e1 + b2 * e2);
  }
  const Material& light = scene_.materials[g.material[ls.triangle]];
  // In double: the squared distance over- or underflows float in scenes scaled by 1e±30.
  const glm::dvec3 to = glm::dvec3(ls.point) - glm::dvec3(p);
  const double dist2 = glm::dot(to, to);
  if (!(dist2 > 0.0)) return false;
  const glm::vec3 wi(to / std::sqrt(dist2));
  glm::vec3 emission = emission_at(scene_, ls.triangle, ls.barycentric.x, ls.barycentric.y, -wi);
  // An alpha-tested emitter shines only as much as it stops rays there.
  if (light.alpha_mode != Material::AlphaMode::opaque)
    emission *= coverage_at(scene_, ls.triangle, ls.barycentric.x, ls.barycentric.y);
  const LightSampler::Emitter& e = *lights_.emitter(ls.triangle);
  const glm::vec3 nl = e.normal;
  float cos_light = -glm::dot(wi, nl);
  if (light.double_sided) cos_light = std::abs(cos_light);
  const glm::vec3 wi_local = x.frame.to_local(wi);
  const glm::vec3* origin = x.origin_towards(wi, wi_local);
  if (cos_light <= 0.f || !origin) return false;
  const float light_pdf = emitter_density(ls.pmf, omega, dist2, cos_light, e.area);
  const float weight = power_heuristic(light_pdf, x.brdf.pdf(x.wo, wi_local));
  // The segment runs between the two offset points, so neither surface can occlude it, and ends
  // short of the emitter by shadow_epsilon of its length (the t of a hit there rounds).
  const SpawnPoint end = spawn_point(g.vertex(ls.triangle, 0), g.vertex(ls.triangle, 1),
                                     g.vertex(ls.triangle, 2), ls.barycentric.x, ls.barycentric.y);
  const glm::vec3 target = offset_ray_origin(end, glm::dot(nl, wi) < 0.f ? nl : -nl);
  out = {*origin, target - *origin, 1.f - shadow_epsilon,
         x.brdf.eval(x.wo, wi_local) * emission * (std::abs(wi_local.z) * weight / light_pdf)};
  return carries_light(out.contribution);
}

// Towards a punctual light: a delta, so no MIS (BSDF sampling never finds it). The shadow segment
// ends at the light, or leaves the scene towards a directional one.
bool LightSampling::punctual(const glm::vec3& p, const PunctualLight& light, float pmf,
                             const ShadingPoint& x, ShadowRay& out) const {
  const bool directional = light.type == PunctualLight::Type::directional;
  const glm::vec3 to = directional ? light.direction : p - light.position;  // light → point
  const glm::dvec3 to_double(to);  // its squared length over- or underflows float beyond 1e±19
  const double dist = std::sqrt(glm::dot(to_double, to_double));
  if (!(dist > 0.0)) return false;
  const glm::vec3 wi(-to_double / dist);
  const glm::vec3 wi_local = x.frame.to_local(wi);
  const glm::vec3* origin = x.origin_towards(wi, wi_local);
  if (!origin) return false;
  const glm::vec3 c =
      x.brdf.eval(x.wo, wi_local) * light.irradiance_towards(to) * (std::abs(wi_local.z) / pmf);
  if (directional)
    out = {*origin, wi, INFINITY, c};
  else
    out = {*origin, light.position - *origin, 1.f, c};
  return carries_light(out.contribution);
}

}  // namespace dacrt
