// Lambert lanes: the path tracer's shading stage for sixteen vertices at once, where they are on
// Lambert surfaces (uniform, not emissive) and next-event estimation, if any, picks an emissive
// triangle that it samples by area. That is all of the Lambert Cornell box but the rays that
// leave the scene, hit the light or sample it from nearby; the path tracer shades those (and
// every other vertex of other scenes) the general way, one at a time (integrators/path.cpp).
//
// One vertex: Russian roulette; the hit point, its normals and its spawn point; next-event
// estimation (a uniform point on the emitter's area, weighed against BSDF sampling by the power
// heuristic; the shadow segment between the two offset points); cosine-weighted BSDF sampling.
// The same code (integrators/lambert_kernel.h) runs on one lane of floats, with AVX2 on eight lanes
// per instruction (twice) and with AVX-512 on sixteen, with the same IEEE operations in the same
// order, so the answers are the same bit for bit on every CPU; which lanes it takes is part of
// those answers.
#pragma once

#include <cstdint>

namespace dacrt {

// The bounds of LightSampling::sampled_solid_angle (integrators/light_sampling.cpp), in one place
// for it and the lanes: from a point at distance D of an emitter's centre, whose ball has radius
// r, the emitter is sampled by area for sure when
// - the ball's cap is small enough: r² × solid_angle_ball ≤ min_solid_angle × D² (2π r² / D²,
//   with a margin of 0.1 %);
// - or its area over its least distance is: A × solid_angle_area_margin ≤ min_solid_angle ×
//   (D − r)², for D > r.
inline constexpr float solid_angle_ball = 2.f * 3.14159265358979f * 1.001f;
inline constexpr float solid_angle_area_margin = 1.001f;

struct LambertIn {
  static constexpr int lanes = 16;
  // 1: the lane is a hit on a uniform, non-emissive Lambert material (else it is not taken).
  alignas(64) float ok[lanes];
  alignas(64) float d[3][lanes];          // ray direction, by axis
  alignas(64) float u[lanes], v[lanes];   // the hit's barycentric weights of corners 1 and 2
  alignas(64) float corner[3][3][lanes];  // the triangle's [corner][axis]
  alignas(64) float normal[3][3][lanes];  // its vertex normals (when the scene has them)
  alignas(64) float albedo[3][lanes];     // baseColor (eval is albedo / π)
  alignas(64) float beta[3][lanes];       // the path's throughput
  // 1/0: the path is below --max-depth, at or past the roulette depth.
  alignas(64) float below_max[lanes], roulette[lanes];
  alignas(64) float u_roulette[lanes], u_bsdf[2][lanes], u_light[2][lanes];
  // The emitter next-event estimation picked: light_ok 1 when it is an area-sampled triangle
  // (LightSampling::AreaEmitter), 0 when the lane must not be taken (a punctual light, a textured
  // or alpha-tested emitter).
  alignas(64) float light_ok[lanes];
  alignas(64) float light_corner[3][3][lanes], light_normal[3][lanes], light_centre[3][lanes];
  alignas(64) float light_radius2[lanes], light_area[lanes], light_pmf[lanes];
  alignas(64) float light_radiance[3][lanes], light_double_sided[lanes];
};

struct LambertOut {
  static constexpr int lanes = LambertIn::lanes;
  alignas(64) float beta[3][lanes];       // the throughput after roulette and the bounce
  alignas(64) float pdf[lanes];           // the bounce direction's solid-angle pdf
  alignas(64) float origin[3][lanes];     // of both rays: the hit point offset towards the viewer
  alignas(64) float direction[3][lanes];  // the bounce ray's
  alignas(64) float to_light[3][lanes];   // the shadow segment (tmax 1 − shadow_epsilon)
  alignas(64) float contribution[3][lanes];  // the shadow ray's, throughput included
  uint32_t taken, shadow, bounce;            // lane masks (shadow and bounce within taken)
};

struct LambertScene {
  bool normals;  // the scene has vertex normals (LambertIn::normal is filled)
  bool lights;   // next-event estimation runs (LambertIn::light_* is filled)
  // Large, near emitters are sampled by solid angle (LightSampling::min_solid_angle, as a float):
  // the lanes that might be are not taken.
  bool solid_angle;
  float min_solid_angle;
  float roulette_scale;  // 1 / PathTracer::roulette_floor: p = min(1, max(β) × roulette_scale)
};

// The kernel's instances: one float at a time (any CPU), eight lanes with AVX2, sixteen with
// AVX-512 (AVX512F and AVX512DQ).
enum class LambertLanes { one, avx2, avx512 };
inline constexpr LambertLanes lambert_instances[] = {LambertLanes::one, LambertLanes::avx2,
                                                     LambertLanes::avx512};
const char* name(LambertLanes instance);
// True if this CPU runs that instance.
bool lambert_available(LambertLanes instance);
bool lambert_avx512_available();
// The widest instance this CPU runs (what shade_lambert uses).
LambertLanes lambert_widest();
// Shades the lanes [0, lanes) of `in` by the widest instance this CPU runs (the same bits as any).
void shade_lambert(const LambertScene& scene, const LambertIn& in, int lanes, LambertOut& out);
// The same by one instance, which the CPU must run (for the tests).
void shade_lambert(LambertLanes instance, const LambertScene& scene, const LambertIn& in,
                   int lanes, LambertOut& out);
// The same, one lane at a time whatever the CPU.
void shade_lambert_scalar(const LambertScene& scene, const LambertIn& in, int lanes,
                          LambertOut& out);

// BRDF lanes: the BSDF sampling of the general glTF BRDF (materials/gltf_brdf.h) for sixteen
// vertices at once, where the BRDF is plain: not Lambert's, no coat or sheen, isotropic, no
// transmission, no iridescence (GltfBrdf::plain). The path tracer prepares each vertex one at a
// time (its hit record, textures, next-event estimation) and leaves the direction to these lanes:
// GltfBrdf::sample's lobe choice, cosine or visible-normal direction, pdf and weight, the world
// direction by the shading frame, and whether it leaves on the viewer's side of the geometric
// normal. The same operations in the same order as GltfBrdf's, so the same bits, on every lane type
// (the visible normal's cos and sin are std::cos and std::sin, called per lane).
struct BrdfIn {
  static constexpr int lanes = 16;
  alignas(64) float ok[lanes];  // 1: the lane is taken
  alignas(64) float wo[3][lanes];   // towards the viewer, in the shading frame
  alignas(64) float u_lobe[lanes], u[2][lanes];
  // GltfBrdf's base colour, metallic, α, dielectric F0 and F90.
  alignas(64) float base[3][lanes], metallic[lanes], alpha[lanes], f0[3][lanes], f90[lanes];
  alignas(64) float frame[3][3][lanes];  // the shading frame's s, t and n, by axis
  alignas(64) float ng[3][lanes];        // the geometric normal, on the viewer's side
};

struct BrdfOut {
  static constexpr int lanes = BrdfIn::lanes;
  alignas(64) float wi[3][lanes];      // the sampled direction, in the world
  alignas(64) float weight[3][lanes];  // eval · cos θi / pdf
  alignas(64) float pdf[lanes];
  uint32_t sampled;  // lanes with a direction that leaves above both normals
};

// Samples the lanes [0, lanes) of `in` by the widest instance this CPU runs (AVX2 or one float).
void sample_brdf(const BrdfIn& in, int lanes, BrdfOut& out);
// The same by one instance (LambertLanes::one or avx2, which the CPU must run; for the tests).
void sample_brdf(LambertLanes instance, const BrdfIn& in, int lanes, BrdfOut& out);

}  // namespace dacrt
