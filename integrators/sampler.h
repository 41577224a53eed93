// Samplers: where every number of a path comes from. Both are counter-based, a number depends
// only on (seed, pixel, sample index, depth, dimension), so an image is the same for any threads,
// wavefront size, pass size and exact backend.
//   independent  a hash of all five (util/random.h): white noise, error ∝ spp^-1/2.
//   sobol        (the default) Owen-scrambled Sobol points with hash-based scrambling, Burley 2020,
//                "Practical Hash-based Owen Scrambling" (JCGT 9(4)). Each pair of dimensions
//                (integrators/dimensions.h) is the first two Sobol dimensions, a (0,2)-sequence:
//                a pixel's first 2^k samples put exactly one point in each of the 2^k elementary
//                intervals of every shape. The sample index is shuffled by a nested uniform
//                (Owen) scramble of its bits, and each coordinate is Owen-scrambled by a
//                Laine–Karras-style hash, each seeded by hash(seed, pixel, depth, pair). The
//                shuffle decorrelates the pairs from each other (without it, point i of every
//                pair would fall in the same half, quarter…), the value scramble makes every
//                pixel's pattern a different randomisation, so the estimate stays unbiased.
//                A single dimension is the first Sobol dimension (van der Corput), the same way.
// Alpha tests stay on the independent hash whatever the sampler (Wavefront::AlphaFilter).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "dacrt/integrators/dimensions.h"
#include "dacrt/util/random.h"

namespace dacrt {

enum class SamplerKind : uint8_t { independent, sobol };

std::vector<std::string> sampler_names();                      // "independent", "sobol"
std::string sampler_name(SamplerKind kind);                    // one of those
bool parse_sampler(std::string_view name, SamplerKind& kind);  // false: no such sampler

// The seed as the Sobol patterns take it: mixed once per render, not for every number.
uint64_t sobol_seed_key(uint64_t seed);
// The number of `dim` for sample `index` of `pixel` at path depth `depth`, in [0, 1), from the
// seed's key.
float sobol_number_keyed(uint64_t seed_key, uint32_t pixel, uint32_t index, uint32_t depth,
                         Dimension dim);
// Both numbers of the pair that starts at `first` (a pair's component 0 in dimension_slots), the
// same as two sobol_number_keyed calls; a pair shares its pattern's seeds and index shuffle.
std::array<float, 2> sobol_pair_keyed(uint64_t seed_key, uint32_t pixel, uint32_t index,
                                      uint32_t depth, Dimension first);
// Sobol's second dimension (generator matrix: Pascal's triangle mod 2) of the index s, its 32
// bits reversed (the most significant at bit 0), unscrambled: the step inside both functions
// above and Sampler::numbers, for the tests.
uint32_t sobol_dimension1_reversed(uint32_t s);

// A vertex's numbers, by dimension (only those asked for are written).
using VertexNumbers = std::array<float, dimension_count>;
// How many vertices Sampler::numbers draws per vector instruction.
inline constexpr size_t sampler_lanes = 16;

// A sampler of one render: its kind and seed (and the seed's key).
struct Sampler {
  SamplerKind kind = SamplerKind::sobol;
  uint64_t seed = 0, key = sobol_seed_key(0);
  Sampler() = default;
  Sampler(SamplerKind k, uint64_t s) : kind(k), seed(s), key(sobol_seed_key(s)) {}

  float number(uint32_t pixel, uint32_t index, uint32_t depth, Dimension dim) const {
    if (kind == SamplerKind::independent || dim >= dimension_count)
      return uniform_float(seed, pixel, index, uint64_t(depth), uint64_t(dim));
    return sobol_number_keyed(key, pixel, index, depth, dim);
  }
  std::array<float, 2> pair(uint32_t pixel, uint32_t index, uint32_t depth, Dimension first) const {
    if (kind == SamplerKind::independent)
      return {uniform_float(seed, pixel, index, uint64_t(depth), uint64_t(first)),
              uniform_float(seed, pixel, index, uint64_t(depth), uint64_t(first) + 1)};
    return sobol_pair_keyed(key, pixel, index, depth, first);
  }
  // The numbers of `dims` (a pair by its first dimension: both are written) for `lanes`
  // vertices, vertex k at (pixel[k], index[k], depth[k]): out[k][dim] is what
  // number(pixel[k], index[k], depth[k], dim) returns, bit for bit. With AVX-512, sampler_lanes
  // Sobol vertices per instruction; with AVX2, eight.
  void numbers(const uint32_t* pixel, const uint32_t* index, const uint32_t* depth, size_t lanes,
               std::span<const Dimension> dims, VertexNumbers* out) const;
};

// The same, for one number or pair at a time (the seed mixed on each call).
inline float sobol_number(uint64_t seed, uint32_t pixel, uint32_t index, uint32_t depth,
                          Dimension dim) {
  return sobol_number_keyed(sobol_seed_key(seed), pixel, index, depth, dim);
}
inline std::array<float, 2> sobol_pair(uint64_t seed, uint32_t pixel, uint32_t index,
                                       uint32_t depth, Dimension first) {
  return sobol_pair_keyed(sobol_seed_key(seed), pixel, index, depth, first);
}
inline float sample_number(SamplerKind kind, uint64_t seed, uint32_t pixel, uint32_t index,
                           uint32_t depth, Dimension dim) {
  return Sampler(kind, seed).number(pixel, index, depth, dim);
}
inline std::array<float, 2> sample_pair(SamplerKind kind, uint64_t seed, uint32_t pixel,
                                        uint32_t index, uint32_t depth, Dimension first) {
  return Sampler(kind, seed).pair(pixel, index, depth, first);
}

}  // namespace dacrt
