#include "integrators/sampler.h"

#include <array>

namespace dacrt {

namespace {

constexpr uint32_t reverse_bits(uint32_t x) {
  x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
  x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
  x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
  x = ((x >> 8) & 0x00ff00ffu) | ((x & 0x00ff00ffu) << 8);
  return (x >> 16) | (x << 16);
}

// Sobol dimension 0 (van der Corput) and 1 (generator matrix: Pascal's triangle mod 2), as 32-bit
// fractions.
constexpr uint32_t dimension0(uint32_t index) {
  return reverse_bits(index);
}
// Dimension 1 by bytes of the index: the XOR of the direction numbers of its set bits, 8 at a
// time from a table built at compile time.
constexpr std::array<std::array<uint32_t, 256>, 4> dimension1_bytes = [] {
  std::array<uint32_t, 32> v{};
  v[0] = 1u << 31;
  for (int i = 1; i < 32; ++i) v[i] = v[i - 1] ^ (v[i - 1] >> 1);
  std::array<std::array<uint32_t, 256>, 4> t{};
  for (int k = 0; k < 4; ++k)
    for (uint32_t b = 0; b < 256; ++b)
      for (int j = 0; j < 8; ++j)
        if (b >> j & 1) t[k][b] ^= v[8 * k + j];
  return t;
}();
constexpr uint32_t dimension1(uint32_t index) {
  return dimension1_bytes[0][index & 0xff] ^ dimension1_bytes[1][index >> 8 & 0xff] ^
         dimension1_bytes[2][index >> 16 & 0xff] ^ dimension1_bytes[3][index >> 24];
}

// Burley's Laine–Karras-style permutation: each bit is flipped by a hash of itself and the bits
// below it only. On reversed bits that is a nested uniform (Owen) scramble: each bit of the
// fraction is flipped by a hash of the bits above it.
constexpr uint32_t laine_karras(uint32_t x, uint32_t seed) {
  x += seed;
  x ^= x * 0x6c50b47cu;
  x ^= x * 0xb82f1e52u;
  x ^= x * 0xc7afe638u;
  x ^= x * 0x8d22f6e6u;
  return x;
}
constexpr uint32_t owen_scramble(uint32_t x, uint32_t seed) {
  return reverse_bits(laine_karras(reverse_bits(x), seed));
}

// Component `component` (0 or 1) of sample `index` of the pattern seeded by `seed`, as a 32-bit
// fraction. All components of a pattern share the index shuffle.
constexpr uint32_t sample_bits(uint32_t index, uint32_t component, uint64_t seed) {
  const uint32_t shuffled = owen_scramble(index, uint32_t(seed));
  const uint32_t x = component == 0 ? dimension0(shuffled) : dimension1(shuffled);
  return owen_scramble(x, uint32_t(mix64(seed + component + 1) >> 32));
}

}  // namespace

std::vector<std::string> sampler_names() {
  return {"independent", "sobol"};
}

std::string sampler_name(SamplerKind kind) {
  return kind == SamplerKind::independent ? "independent" : "sobol";
}

float sobol_number(uint64_t seed, uint32_t pixel, uint32_t index, uint32_t depth, Dimension dim) {
  const DimensionSlot slot = dimension_slots[dim];
  const uint64_t pattern = hash(seed, pixel, uint64_t(depth) << 8 | slot.slot);
  return float(sample_bits(index, slot.component, pattern) >> 8) * 0x1p-24f;
}

bool parse_sampler(std::string_view name, SamplerKind& kind) {
  if (name == "independent")
    kind = SamplerKind::independent;
  else if (name == "sobol")
    kind = SamplerKind::sobol;
  else
    return false;
  return true;
}

}  // namespace dacrt
