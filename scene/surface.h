// Surface: what a material looks like at one point of a triangle, with its textures, vertex
// colours and normal map applied. The path tracer asks once per hit; materials without textures
// and scenes without vertex colours skip the uv and colour work entirely.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>

#include "dacrt/scene/scene.h"

namespace dacrt {

struct SurfacePoint {
  // The shading normal: interpolated, then normal-mapped; on the triangle's front side (the side
  // its counter-clockwise winding faces), unit length.
  glm::vec3 normal;
  BrdfParams brdf;
  glm::vec3 emission;  // radiance leaving the front (and, if double-sided, the back)
  // KHR_materials_clearcoat's normal: the clearcoat normal map's, else the interpolated normal
  // (not the base's normal map); on the front side, unit length. (BrdfParams::clearcoat_normal
  // is this in the shading frame: the integrator's brdf_at puts it there.)
  glm::vec3 coat_normal;
  // KHR_materials_anisotropy's direction of increased roughness (brdf.anisotropy > 0 only): the
  // tangent frame's (tangent, bitangent) · the rotated direction, world space, unit, in the plane
  // of the interpolated normal. Where the triangle has no tangents, the frame is an arbitrary one
  // around the interpolated normal (the loader warns). The integrator's brdf_at puts it in the
  // shading frame as BrdfParams::anisotropy_direction.
  glm::vec3 anisotropy_direction{0.f};
};

// At barycentrics (u, v) of triangle `tri` (the point (1 − u − v)·p0 + u·p1 + v·p2), whose unit
// geometric normal is `ng` (front side).
SurfacePoint surface_at(const Scene& scene, uint32_t tri, float u, float v, const glm::vec3& ng);

// Just alpha there: baseColorFactor.a × texture × vertex colour.
float alpha_at(const Scene& scene, uint32_t tri, float u, float v);

// The probability that a ray stops there: 1 for OPAQUE, 0 or 1 for MASK (alpha against the
// cutoff), alpha for BLEND. Rays stop where a uniform xi in [0, 1) is below it (the hit filter);
// next-event estimation weighs an emitter's light by it.
float coverage_at(const Scene& scene, uint32_t tri, float u, float v);

// Asks the cache for the texels surface_at would read there (materials/texture.h: prefetch).
void prefetch_surface(const Scene& scene, uint32_t tri, float u, float v);

// Just the emitted radiance there towards unit direction `towards` (what next-event estimation
// needs of a light sample): the emission, its texture and (unlit) vertex colours, and under a
// clearcoat, × 1 − clearcoat · F(towards · n_c) (KHR_materials_clearcoat's "Emission").
glm::vec3 emission_at(const Scene& scene, uint32_t tri, float u, float v, const glm::vec3& towards);

// A per-corner attribute interpolated at (u, v).
template <class T>
T interpolate(const T* corners, float u, float v) {
  return (1.f - u - v) * corners[0] + u * corners[1] + v * corners[2];
}

}  // namespace dacrt
