// Fixed-point sums, so that a film's sums do not depend on the order its samples arrive in:
// every value is rounded once, on its own, to a multiple of 2^-F in a signed 128-bit integer,
// and integers add exactly. Samples [0, a) and [a, b) rendered apart (other processes, other
// machines, a resumed render) then add up to the bits of [0, b) rendered at once, and any
// reduction tree gives the same film.
//
// Two scales: values (radiance, first-hit values) in 2^-64 steps, squares (for variance
// estimates) in 2^-46 steps. Values are clamped to ±value_limit = 2^30 (about 1.07e9), where a
// square still fits: 2^60 × 2^46 × max_samples (2^20) < 2^127, so no sum can overflow.
// Values known to be small (a surface's albedo, in [0, 1], and unit normals) are clamped to
// ±bounded_limit = 2^10 instead, so that their sums, below 2^(64 + 10 + 20), fit in 96 bits.
#pragma once

#include <cmath>
#include <cstdint>

namespace dacrt {

__extension__ using Fixed = __int128;

inline constexpr int value_bits = 64;   // fraction bits of a value
inline constexpr int square_bits = 46;  // fraction bits of a square
inline constexpr double value_limit = 0x1p30;
inline constexpr double bounded_limit = 0x1p10;  // albedo and normal values (Film::bounded)
inline constexpr uint32_t max_samples = 1u << 20;  // per pixel: the most --spp allows

constexpr double pow2(int e) {
  double p = 1.0;
  for (; e > 0; --e) p *= 2.0;
  for (; e < 0; ++e) p *= 0.5;
  return p;
}

// v × 2^F rounded toward zero, for |v| ≤ 2^M (M = 30 for values, 60 for squares). Two exact
// double → int64 conversions, no 128-bit one (a library call): the part above a split point
// S = F + M − 62 bits below the binary point, y = v × 2^(F − S) (below 2^62), then the
// fraction y − trunc(y) (exact) scaled by 2^S.
template <int F, int M>
inline Fixed to_fixed(double v) {
  constexpr int split = F + M - 62;
  constexpr double down = pow2(F - split), up = pow2(split);
  const double y = v * down;  // exact: a power of two
  const int64_t whole = int64_t(y);
  const int64_t rest = int64_t((y - double(whole)) * up);
  return Fixed(whole) * (Fixed(1) << split) + Fixed(rest);
}

template <int F>
inline Fixed to_fixed(double v) {
  return to_fixed<F, F == value_bits ? 30 : 60>(v);
}

template <int F>
inline double from_fixed(Fixed x) {
  constexpr double scale = pow2(-F);
  return double(x) * scale;
}

}  // namespace dacrt
