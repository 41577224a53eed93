// The random dimensions of one path vertex, for the counter-based generator (util/random.h): a
// path's numbers depend only on (seed, pixel, sample index, depth, dimension), so the image is the
// same for any thread count, wavefront size or exact backend. Allocated once, here.
#pragma once

#include <cstdint>

namespace dacrt {

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

}  // namespace dacrt
