// Fixed-point sums, so that a film's sums do not depend on the order its samples arrive in:
// every value is rounded once, on its own, to a multiple of 2^-F in a signed 128-bit integer,
// and integers add exactly. Samples [0, a) and [a, b) rendered apart (other processes, other
// machines, a resumed render) then add up to the bits of [0, b) rendered at once, and any
// reduction tree gives the same film.
//
// Two scales: values (radiance, first-hit values) in 2^-64 steps, squares (for variance
// estimates) in 2^-46 steps. Values are clamped to ±value_limit = 2^30 (about 1.07e9), where a
// square still fits: 2^60 × 2^46 × max_samples (2^20) < 2^127, so no sum can overflow.
#pragma once

#include <cmath>
#include <cstdint>

namespace dacrt {

__extension__ using Fixed = __int128;

inline constexpr int value_bits = 64;   // fraction bits of a value
inline constexpr int square_bits = 46;  // fraction bits of a square
inline constexpr double value_limit = 0x1p30;
inline constexpr uint32_t max_samples = 1u << 20;  // per pixel: the most --spp allows

constexpr double pow2(int e) {
  double p = 1.0;
  for (; e > 0; --e) p *= 2.0;
  for (; e < 0; ++e) p *= 0.5;
  return p;
}

// v × 2^F rounded down (v × 2^(F − 64) must be below 2^63 in magnitude): the whole part and
// the fraction are converted apart, which is exact and much faster than a 128-bit conversion.
template <int F>
inline Fixed to_fixed(double v) {
  constexpr double down = pow2(F - 64), up = pow2(64);
  const double y = v * down;  // exact: a power of two
  const double whole = std::floor(y);
  const uint64_t low = uint64_t((y - whole) * up);  // y − whole is exact, in [0, 1)
  return Fixed(int64_t(whole)) * (Fixed(1) << 64) + Fixed(low);
}

template <int F>
inline double from_fixed(Fixed x) {
  constexpr double scale = pow2(-F);
  return double(x) * scale;
}

}  // namespace dacrt
