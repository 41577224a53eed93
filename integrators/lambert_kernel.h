// The Lambert lanes' vertex (integrators/lambert_lanes.h), written once for any lane type L:
//   L::F     a float per lane, with + − × ÷ and comparisons giving an L::M (a lane mask);
//   L::load / L::store / L::mask  between F (or M) and lane k of the LambertIn/LambertOut arrays;
// and, found by overload, vmin, vmax (x86's minps/maxps: the second operand on a tie or a NaN),
// vabs, vsqrt, sel (per-lane select), unmask, next_up and next_down; the BRDF lanes (brdf_sample,
// below) also vcos_sin. Only correctly rounded IEEE
// operations are used, so a lane's answer does not depend on the lane type.
//
// Included by exactly three files, each of which compiles it for its lane type: lambert_lanes.cpp
// (one float), lambert_lanes_avx2.cpp (eight) and lambert_lanes_avx512.cpp (sixteen), the last two
// under their target pragmas. Everything is in an anonymous namespace: each file has its own copy,
// compiled for its own instruction set.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>

#include "dacrt/integrators/lambert_lanes.h"

namespace dacrt {
namespace {

// One lane of floats.
inline float vmin(float a, float b) {
  return a < b ? a : b;
}
inline float vmax(float a, float b) {
  return a > b ? a : b;
}
inline float vabs(float a) {
  return std::bit_cast<float>(std::bit_cast<uint32_t>(a) & 0x7fffffffu);
}
inline float vsqrt(float a) {
  return __builtin_sqrtf(a);
}
inline float sel(bool m, float a, float b) {
  return m ? a : b;
}
inline bool unmask(bool m) {
  return !m;
}
// tracer/ray.h's next_float_up and next_float_down.
inline float next_up(float v) {
  if (v == 0.f) return 0x1p-149f;
  const uint32_t bits = std::bit_cast<uint32_t>(v);
  return std::bit_cast<float>(v > 0.f ? bits + 1u : bits - 1u);
}
inline float next_down(float v) {
  return -next_up(-v);
}
// std::cos and std::sin (lane types call them lane by lane: no vector code rounds as they do).
inline void vcos_sin(float x, float& c, float& s) {
  c = std::cos(x), s = std::sin(x);
}

template <class F>
struct V3 {
  F x, y, z;
};
template <class F>
V3<F> operator+(const V3<F>& a, const V3<F>& b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
template <class F>
V3<F> operator-(const V3<F>& a, const V3<F>& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
template <class F>
V3<F> operator-(const V3<F>& a) {
  return {-a.x, -a.y, -a.z};
}
template <class F>
V3<F> operator*(const F& s, const V3<F>& a) {
  return {s * a.x, s * a.y, s * a.z};
}
template <class F>
V3<F> operator*(const V3<F>& a, const V3<F>& b) {
  return {a.x * b.x, a.y * b.y, a.z * b.z};
}
template <class F>
F dot(const V3<F>& a, const V3<F>& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class F>
V3<F> cross(const V3<F>& a, const V3<F>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class F>
V3<F> vabs(const V3<F>& a) {
  return {vabs(a.x), vabs(a.y), vabs(a.z)};
}
template <class F>
V3<F> vmax(const V3<F>& a, const V3<F>& b) {
  return {vmax(a.x, b.x), vmax(a.y, b.y), vmax(a.z, b.z)};
}
template <class F>
F max3(const V3<F>& a) {
  return vmax(vmax(a.x, a.y), a.z);
}
template <class M, class F>
V3<F> sel(M m, const V3<F>& a, const V3<F>& b) {
  return {sel(m, a.x, b.x), sel(m, a.y, b.y), sel(m, a.z, b.z)};
}
template <class M, class F>
M carries(const V3<F>& c) {
  return (c.x > F(0.f)) | (c.y > F(0.f)) | (c.z > F(0.f));
}

// materials/sampling.h's sample_cosine_hemisphere up to its z: the concentric map of (u1, u2) to
// the unit disk, (x, y).
template <class F>
void concentric_disk(F u1, F u2, F& x, F& y) {
  const F one = F(1.f), zero = F(0.f);
  const F sa = F(2.f) * u1 - one, sb = F(2.f) * u2 - one;
  const auto a_major = vabs(sa) > vabs(sb);
  const F r = sel(a_major, sa, sb), minor = sel(a_major, sb, sa);
  const F angle = F(0.785398163397448309616f) * (minor / sel(r != zero, r, one));
  const F x2 = angle * angle;
  const F cos_psi =
      one + x2 * (F(-1.f / 2) + x2 * (F(1.f / 24) + x2 * (F(-1.f / 720) + x2 * F(1.f / 40320))));
  const F sin_psi =
      angle * (one + x2 * (F(-1.f / 6) +
                           x2 * (F(1.f / 120) + x2 * (F(-1.f / 5040) + x2 * F(1.f / 362880)))));
  x = r * sel(a_major, cos_psi, sin_psi), y = r * sel(a_major, sin_psi, cos_psi);
}

template <class L>
V3<typename L::F> load3(const float (&a)[3][LambertIn::lanes], int k) {
  return {L::load(a[0], k), L::load(a[1], k), L::load(a[2], k)};
}
template <class L>
void store3(float (&a)[3][LambertIn::lanes], int k, const V3<typename L::F>& v) {
  L::store(a[0], k, v.x), L::store(a[1], k, v.y), L::store(a[2], k, v.z);
}

// tracer/ray.h's spawn_point (its float case): the point of triangle (a, b, c) at weights (u, v)
// moved 16 ulps towards the centroid, and its error bound.
template <class F>
void spawn(const V3<F>& a, const V3<F>& b, const V3<F>& c, const V3<F>& e1, const V3<F>& e2, F u,
           F v, V3<F>& p, V3<F>& error) {
  const F third = F(1.f / 3.f);
  const F du = third - u, dv = third - v;
  const F move = F(16 * 0x1p-24f) * max3(vmax(vmax(vabs(a), vabs(b)), vabs(c)));
  const F distance = max3(vabs(du * e1 + dv * e2));
  const auto moves = distance > F(0.f);
  const F k = vmin(F(0.5f), move / distance);
  u = sel(moves, u + k * du, u), v = sel(moves, v + k * dv, v);
  const V3<F> ue1 = u * e1, ve2 = v * e2;
  p = a + (ue1 + ve2);
  const F margin = F(0x1p-18f) * max3(vmax(vabs(e1), vabs(e2)));
  const V3<F> e = F(float(4.1 * 0x1p-24)) * (vabs(ue1) + vabs(ve2));
  const V3<F> bound = F(1.01f * 0x1p-24f) * vabs(p);
  error = {bound.x + (e.x + margin), bound.y + (e.y + margin), bound.z + (e.z + margin)};
}

// tracer/ray.h's offset_ray_origin.
template <class F>
V3<F> offset(const V3<F>& p, const V3<F>& error, const V3<F>& n) {
  const F d = dot(vabs(n), error);
  const V3<F> o = p + d * n;
  auto nudge = [](F x, F nk) {
    return sel(nk > F(0.f), next_up(x), sel(nk < F(0.f), next_down(x), x));
  };
  return {nudge(o.x, n.x), nudge(o.y, n.y), nudge(o.z, n.z)};
}

template <class L>
void lambert_vertex(const LambertScene& scene, const LambertIn& in, int k, LambertOut& out) {
  using F = typename L::F;
  using M = decltype(F(0.f) < F(0.f));
  auto ld = [&](const float* a) { return L::load(a, k); };
  constexpr float inv_pi = 0.318309886183790671538f;
  const F zero(0.f), one(1.f);
  M taken = ld(in.ok) > F(0.5f);

  // The triangle and its unit normal (Geometry::unit_normal's float case).
  const V3<F> a = load3<L>(in.corner[0], k), b = load3<L>(in.corner[1], k),
              c = load3<L>(in.corner[2], k);
  const V3<F> e1 = b - a, e2 = c - a;
  const F edges = e1.x + e1.y + e1.z + e2.x + e2.y + e2.z;
  taken &= vabs(edges) < F(__builtin_inff());
  const V3<F> n = cross(e1, e2);
  const F l2 = dot(n, n);
  taken &= (l2 >= F(0x1p-100f)) & (l2 < F(0x1p100f));
  const F len = vsqrt(l2);
  const V3<F> ng_front = {n.x / len, n.y / len, n.z / len};

  // Russian roulette (PathTracer::survives).
  V3<F> beta = load3<L>(in.beta, k);
  const M roulette = ld(in.roulette) > F(0.5f);
  const F p_keep = vmin(one, max3(beta) * F(scene.roulette_scale));
  const M alive = (ld(in.below_max) > F(0.5f)) & (unmask(roulette) | (ld(in.u_roulette) < p_keep));
  beta = sel(roulette, V3<F>{beta.x / p_keep, beta.y / p_keep, beta.z / p_keep}, beta);

  // The normals on the viewer's side (Wavefront::hit_at).
  const V3<F> d = load3<L>(in.d, k);
  const V3<F> ng = sel(dot(ng_front, d) < zero, ng_front, -ng_front);
  V3<F> ns = ng_front;
  const F u = ld(in.u), v = ld(in.v);
  if (scene.normals) {
    const F w = one - u - v;
    const V3<F> interpolated = w * load3<L>(in.normal[0], k) + u * load3<L>(in.normal[1], k) +
                               v * load3<L>(in.normal[2], k);
    const F length = vsqrt(dot(interpolated, interpolated));
    ns = sel(length > zero,
             V3<F>{interpolated.x / length, interpolated.y / length, interpolated.z / length}, ns);
  }
  ns = sel(dot(ns, ng) < zero, -ns, ns);
  ns = sel(dot(ns, d) >= zero, ng, ns);
  V3<F> p, error;
  spawn(a, b, c, e1, e2, u, v, p, error);
  const V3<F> origin = offset(p, error, ng);
  // The BRDF is 0 unless the viewer is above the shading normal.
  const M lit = alive & (-dot(d, ns) > zero);
  const V3<F> albedo = load3<L>(in.albedo, k);

  // Next-event estimation: a uniform point on the emitter's area.
  M shadow = lit & unmask(lit);  // none
  V3<F> contribution{zero, zero, zero}, to_light{zero, zero, zero};
  if (scene.lights) {
    const M light_ok = ld(in.light_ok) > F(0.5f);
    taken &= unmask(lit & unmask(light_ok));
    const V3<F> la = load3<L>(in.light_corner[0], k), lb = load3<L>(in.light_corner[1], k),
                lc = load3<L>(in.light_corner[2], k);
    const V3<F> le1 = lb - la, le2 = lc - la;
    if (scene.solid_angle) {  // (from p, as LightSampling::emitter asks sampled_solid_angle)
      const V3<F> to_centre = load3<L>(in.light_centre, k) - p;
      const F d2 = dot(to_centre, to_centre), r2 = ld(in.light_radius2);
      // LightSampling::sampled_solid_angle's two bounds: the ball's cap, and A / (D − r)².
      const F gap = vsqrt(d2) - vsqrt(r2), min_omega(scene.min_solid_angle);
      const M area = (r2 < F(__builtin_inff())) & (d2 < F(__builtin_inff())) &
                     ((F(solid_angle_ball) * r2 <= min_omega * d2) |
                      ((gap > zero) & (F(solid_angle_area_margin) * ld(in.light_area) <=
                                       min_omega * (gap * gap))));
      taken &= unmask(lit & unmask(area));
    }
    const F s = vsqrt(ld(in.u_light[0])), u2 = ld(in.u_light[1]);
    const F bu = s * (one - u2), bv = s * u2;
    const V3<F> to = (la + (bu * le1 + bv * le2)) - p;
    const F dist2 = dot(to, to);
    // Beyond this range the distance is for LightSampling::emitter's double precision.
    taken &= unmask(lit & unmask((dist2 >= F(0x1p-60f)) & (dist2 <= F(0x1p60f))));
    const F dist = vsqrt(dist2);
    const V3<F> wi = {to.x / dist, to.y / dist, to.z / dist};
    const V3<F> nl = load3<L>(in.light_normal, k);
    const F cos_signed = -dot(wi, nl);
    const F cos_light = sel(ld(in.light_double_sided) > F(0.5f), vabs(cos_signed), cos_signed);
    const F cos_surface = dot(wi, ns);
    shadow = lit & (cos_light > zero) & (cos_surface > zero) & (dot(wi, ng) > zero);
    const F light_pdf = ld(in.light_pmf) * (dist2 / (cos_light * ld(in.light_area)));
    const F bsdf_pdf = cos_surface * F(inv_pi);
    const F ratio = bsdf_pdf / light_pdf;
    const F weight = one / (one + ratio * ratio);
    const F scale = cos_surface * weight / light_pdf;
    const V3<F> radiance = load3<L>(in.light_radiance, k);
    const V3<F> f = F(inv_pi) * albedo;
    contribution = scale * (f * radiance) * beta;
    shadow &= carries<M>(contribution);
    // The segment ends at the emitter's spawn point, offset towards this side.
    V3<F> q, q_error;
    spawn(la, lb, lc, le1, le2, bu, bv, q, q_error);
    const M facing = dot(nl, wi) < zero;
    to_light = offset(q, q_error, sel(facing, nl, -nl)) - origin;
  }

  // Cosine-weighted BSDF sampling (materials/sampling.h's sample_cosine_hemisphere).
  F lx, ly;
  concentric_disk(ld(in.u_bsdf[0]), ld(in.u_bsdf[1]), lx, ly);
  const F lz = vsqrt(vmax(zero, one - lx * lx - ly * ly));
  // To the world around ns (materials/sampling.h's Frame).
  const F sign = sel(ns.z < zero, F(-1.f), one);
  const F fa = F(-1.f) / (sign + ns.z), fb = ns.x * ns.y * fa;
  const V3<F> fs = {one + sign * ns.x * ns.x * fa, sign * fb, -sign * ns.x};
  const V3<F> ft = {fb, sign + ns.y * ns.y * fa, -ns.y};
  const V3<F> wi = lx * fs + ly * ft + lz * ns;
  const V3<F> next_beta = beta * albedo;
  const M bounce = lit & (lz > zero) & (dot(wi, ng) > zero) & carries<M>(next_beta);

  store3<L>(out.beta, k, next_beta);
  L::store(out.pdf, k, lz * F(inv_pi));
  store3<L>(out.origin, k, origin);
  store3<L>(out.direction, k, wi);
  store3<L>(out.to_light, k, to_light);
  store3<L>(out.contribution, k, contribution);
  L::mask(out.taken, k, taken);
  L::mask(out.shadow, k, taken & shadow);
  L::mask(out.bounce, k, taken & bounce);
}


// The BRDF lanes (integrators/lambert_lanes.h): GltfBrdf::sample of a plain BRDF, operation for
// operation (materials/gltf_brdf.cpp: base_sample, lobes, fresnel, base_pdf, specular_pdf,
// base_eval, the GGX pieces), then Frame::to_world and ShadingPoint::origin_towards. Every
// comparison keeps its scalar form, so NaNs go the same way.
template <class F>
struct BrdfLane {
  using M = decltype(F(0.f) < F(0.f));
  V3<F> base, f0;
  F metallic, alpha, f90;

  static F luminance(const V3<F>& c) {
    return F(0.2126f) * c.x + F(0.7152f) * c.y + F(0.0722f) * c.z;
  }
  static V3<F> normalize(const V3<F>& v) {  // glm::normalize: v · (1 / √(v·v))
    const F r = F(1.f) / vsqrt(dot(v, v));
    return {v.x * r, v.y * r, v.z * r};
  }
  // std::clamp(x, 0, 1) and std::max(0, x).
  static F clamp01(F x) { return sel(x < F(0.f), F(0.f), sel(F(1.f) < x, F(1.f), x)); }
  static F max0(F x) { return sel(F(0.f) < x, x, F(0.f)); }

  F ggx_d(F cos_h) const {
    const F a2 = alpha * alpha, t = cos_h * cos_h * (a2 - F(1.f)) + F(1.f);
    return sel(cos_h <= F(0.f), F(0.f), a2 / (F(3.14159265358979323846f) * t * t));
  }
  F ggx_lambda(F c) const {
    const F a2 = alpha * alpha, c2 = c * c;
    return F(0.5f) * (vsqrt(a2 + (F(1.f) - a2) * c2) / c - F(1.f));
  }
  F ggx_visibility(F co, F ci) const {
    const F a2 = alpha * alpha;
    const F so = vsqrt(a2 + (F(1.f) - a2) * co * co), si = vsqrt(a2 + (F(1.f) - a2) * ci * ci);
    return F(0.5f) / (ci * so + co * si);
  }
  V3<F> visible_normal(const V3<F>& wo, F u1, F u2) const {
    const V3<F> v = normalize({alpha * wo.x, alpha * wo.y, wo.z});
    const F len2 = v.x * v.x + v.y * v.y;
    const F len = vsqrt(len2);
    const V3<F> t1 = sel(len2 > F(0.f), V3<F>{-v.y / len, v.x / len, F(0.f) / len},
                         V3<F>{F(1.f), F(0.f), F(0.f)});
    const V3<F> t2 = cross(v, t1);
    const F r = vsqrt(u1), phi = F(6.28318530717958647692f) * u2;
    F c, s;
    vcos_sin(phi, c, s);
    const F p1 = r * c;
    const F sh = F(0.5f) * (F(1.f) + v.z);
    const F p2 = (F(1.f) - sh) * vsqrt(max0(F(1.f) - p1 * p1)) + sh * r * s;
    const F w = vsqrt(max0(F(1.f) - p1 * p1 - p2 * p2));
    const V3<F> n = (p1 * t1 + p2 * t2) + w * v;
    return normalize({alpha * n.x, alpha * n.y, max0(n.z)});
  }
  struct Fresnel {
    V3<F> dielectric, metal;
    F base;
  };
  Fresnel fresnel(F cos_theta) const {
    const F m = F(1.f) - clamp01(cos_theta), m2 = m * m, w = m2 * m2 * m;
    const V3<F> fd = {f0.x + (f90 - f0.x) * w, f0.y + (f90 - f0.y) * w, f0.z + (f90 - f0.z) * w};
    const V3<F> fm = {base.x + (F(1.f) - base.x) * w, base.y + (F(1.f) - base.y) * w,
                      base.z + (F(1.f) - base.z) * w};
    F largest = fd.x;  // std::max({x, y, z}): the first of the largest
    largest = sel(largest < fd.y, fd.y, largest);
    largest = sel(largest < fd.z, fd.z, largest);
    return {fd, fm, F(1.f) - largest};
  }
  struct Lobes {
    F specular, diffuse, transmission;
  };
  Lobes lobes(F wo_z) const {
    const Fresnel f = fresnel(wo_z);
    const F specular =
        (F(1.f) - metallic) * luminance(f.dielectric) + metallic * luminance(f.metal);
    const F b = (F(1.f) - metallic) * f.base * luminance(base);
    const F diffuse = (F(1.f) - F(0.f)) * b, transmission = F(0.f) * b;  // (transmission 0)
    const F total = specular + diffuse + transmission;
    const M some = total > F(0.f);
    return {sel(some, specular / total, F(0.5f)), sel(some, diffuse / total, F(0.5f)),
            sel(some, transmission / total, F(0.f))};
  }
  F specular_pdf(const V3<F>& wo, const V3<F>& wi) const {
    const V3<F> h = normalize(wo + wi);
    const F g1 = F(1.f) / (F(1.f) + ggx_lambda(wo.z));
    return sel(dot(wo, h) <= F(0.f), F(0.f), g1 * ggx_d(h.z) / (F(4.f) * wo.z));
  }
};

template <class L>
void brdf_sample(const BrdfIn& in, int k, BrdfOut& out) {
  using F = typename L::F;
  using M = decltype(F(0.f) < F(0.f));
  auto ld = [&](const float* a) { return L::load(a, k); };
  constexpr float inv_pi = 0.318309886183790671538f;
  const F zero(0.f), one(1.f);
  const BrdfLane<F> b{load3<L>(in.base, k), load3<L>(in.f0, k), ld(in.metallic), ld(in.alpha),
                      ld(in.f90)};
  const V3<F> wo = load3<L>(in.wo, k);
  const F u_lobe = ld(in.u_lobe), u1 = ld(in.u[0]), u2 = ld(in.u[1]);
  M ok = (ld(in.ok) > F(0.5f)) & unmask(wo.z <= zero);

  // base_sample: the lobe, then its direction.
  const typename BrdfLane<F>::Lobes p = b.lobes(wo.z);
  const M diffuse = (u_lobe >= p.specular) &
                    ((u_lobe < p.specular + p.diffuse) | unmask(p.transmission > zero));
  // materials/sampling.h's sample_cosine_hemisphere.
  F lx, ly;
  concentric_disk(u1, u2, lx, ly);
  const V3<F> cosine = {lx, ly, vsqrt(b.max0(one - lx * lx - ly * ly))};
  // The specular reflection of wo about a visible normal.
  const V3<F> h = b.visible_normal(wo, u1, u2);
  const F two_cos = F(2.f) * dot(wo, h);
  const V3<F> reflected = {two_cos * h.x - wo.x, two_cos * h.y - wo.y, two_cos * h.z - wo.z};
  ok &= diffuse | unmask(reflected.z <= zero);
  // (No mirroring: without transmission the specular branch is taken only below p.specular.)
  const V3<F> wi = sel(diffuse, cosine, reflected);
  ok &= unmask(wi.z == zero);

  // base_pdf (wo.z > 0 and wi.z > 0 here).
  const F cos_pdf = sel(wi.z > zero, wi.z * F(inv_pi), zero);
  const F density = p.specular * b.specular_pdf(wo, wi) + p.diffuse * cos_pdf;
  ok &= (density > zero) & (vabs(density) < F(__builtin_inff()));

  // base_eval.
  const V3<F> hv = BrdfLane<F>::normalize(wo + wi);
  const F specular = b.ggx_d(hv.z) * b.ggx_visibility(wo.z, wi.z);
  const typename BrdfLane<F>::Fresnel f = b.fresnel(dot(wo, hv));
  const F diffuse_scale = (one - zero) * f.base;
  auto channel = [&](F base, F fd, F fm) {
    const F dielectric = diffuse_scale * base * F(inv_pi) + fd * specular;
    return (one - b.metallic) * dielectric + b.metallic * fm * specular;
  };
  const V3<F> eval = {channel(b.base.x, f.dielectric.x, f.metal.x),
                      channel(b.base.y, f.dielectric.y, f.metal.y),
                      channel(b.base.z, f.dielectric.z, f.metal.z)};
  const F scale = vabs(wi.z) / density;
  const V3<F> weight = {eval.x * scale, eval.y * scale, eval.z * scale};

  // To the world (Frame::to_world), above both normals (ShadingPoint::origin_towards).
  const V3<F> s = load3<L>(in.frame[0], k), t = load3<L>(in.frame[1], k),
              n = load3<L>(in.frame[2], k);
  const V3<F> world = wi.x * s + wi.y * t + wi.z * n;
  ok &= (wi.z > zero) & (dot(world, load3<L>(in.ng, k)) > zero);

  store3<L>(out.wi, k, world);
  store3<L>(out.weight, k, weight);
  L::store(out.pdf, k, density);
  L::mask(out.sampled, k, ok);
}

}  // namespace
}  // namespace dacrt
