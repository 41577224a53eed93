// The random dimensions of one path vertex, allocated once, here. A path's numbers depend only on
// (seed, pixel, sample index, depth, dimension), so the image is the same for any thread count,
// wavefront size or exact backend. The sampler (integrators/sampler.h) draws each pair from one
// 2D low-discrepancy pattern and each single dimension from a 1D one; `dimension_slots` says
// which is which.
#pragma once

#include <array>
#include <cstdint>

namespace dacrt {

enum Dimension : uint32_t {
  pixel_x,  // pair: camera (the point in the pixel)
  pixel_y,
  lens_u,  // pair: the point on a thin lens (drawn only with an aperture)
  lens_v,
  light_pick,  // single: which light
  light_u,     // pair: the point on that light
  light_v,
  bsdf_lobe,  // single: which lobe of the BSDF
  bsdf_u,     // pair: the direction in that lobe
  bsdf_v,
  roulette,       // single: Russian roulette
  environment_u,  // pair: the environment map's row and column (two alias tables)
  environment_v,
  light_source,         // single: the environment map or the scene's emitters (light_pick then says
                        // which emitter; one number each, so the alias table keeps all 24 bits)
  environment_pixel_u,  // pair: the point inside the environment pixel chosen
  environment_pixel_v,
  alpha,  // + the ray type, + the triangle × 256: one number per ray and triangle, always
          // independent (a ray may test many triangles, none of them a pattern's dimension)
  dimension_count = alpha,
  // single, drawn from the independent hash (beyond the patterns, as alpha, and clear of alpha's
  // numbers, alpha + 0…2 + triangle × 256): the colour channel a path picks at its first
  // dispersive material (integrators/media.h)
  wavelength = alpha + 8,
};

// Where a dimension sits in the sampler's patterns: pattern `slot` (its own scramble seeds), and
// component 0 or 1 of it; a single dimension has pair false and uses component 0 only.
struct DimensionSlot {
  uint32_t slot, component;
  bool pair;
};

inline constexpr std::array<DimensionSlot, dimension_count> dimension_slots = {{
    {0, 0, true},   // pixel_x
    {0, 1, true},   // pixel_y
    {1, 0, true},   // lens_u
    {1, 1, true},   // lens_v
    {2, 0, false},  // light_pick
    {3, 0, true},   // light_u
    {3, 1, true},   // light_v
    {4, 0, false},  // bsdf_lobe
    {5, 0, true},   // bsdf_u
    {5, 1, true},   // bsdf_v
    {6, 0, false},  // roulette
    {7, 0, true},   // environment_u
    {7, 1, true},   // environment_v
    {8, 0, false},  // light_source
    {9, 0, true},   // environment_pixel_u
    {9, 1, true},   // environment_pixel_v
}};

}  // namespace dacrt
