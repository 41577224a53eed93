// Surface: what a material looks like at one point of a triangle, with its textures, vertex
// colours and normal map applied. The path tracer asks once per hit; materials without textures
// and scenes without vertex colours skip the uv and colour work entirely.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>

#include "scene/scene.h"

namespace dacrt {

struct SurfacePoint {
  // The shading normal: interpolated, then normal-mapped; on the triangle's front side (the side
  // its counter-clockwise winding faces), unit length.
  glm::vec3 normal;
  BrdfParams brdf;
  glm::vec3 emission;  // radiance leaving the front (and, if double-sided, the back)
  float alpha;         // coverage: baseColorFactor.a × texture × vertex colour
};

// At barycentrics (u, v) of triangle `tri` (the point (1 − u − v)·p0 + u·p1 + v·p2), whose unit
// geometric normal is `ng` (front side).
SurfacePoint surface_at(const Scene& scene, uint32_t tri, float u, float v, const glm::vec3& ng);

// Just the coverage there (what the hit filter of alpha-tested materials needs).
float alpha_at(const Scene& scene, uint32_t tri, float u, float v);

// Whether a ray stops at that point of an alpha-tested material: MASK compares the coverage with
// the cutoff; BLEND stops with probability alpha, decided by `xi` (uniform in [0, 1)). Always
// for OPAQUE.
bool alpha_accepts(const Scene& scene, uint32_t tri, float u, float v, float xi);

// Just the emitted radiance there (what next-event estimation needs of a light sample).
glm::vec3 emission_at(const Scene& scene, uint32_t tri, float u, float v);

// A per-corner attribute interpolated at (u, v).
template <class T>
T interpolate(const T* corners, float u, float v) {
  return (1.f - u - v) * corners[0] + u * corners[1] + v * corners[2];
}

}  // namespace dacrt
