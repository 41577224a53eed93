#include "integrators/sampler.h"

#include <array>

namespace dacrt {

namespace {

// Bit i becomes bit 31 − i: the bytes swapped, then the bits within each byte.
constexpr uint32_t reverse_bits(uint32_t x) {
  x = __builtin_bswap32(x);
  x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
  x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
  return ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
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

// The Owen scramble of a 32-bit fraction x is reverse(LK(reverse(x))). With y = LK(reverse(index))
// (the shuffled index s = reverse(y)), the two components need few reversals:
//   dimension 0 (van der Corput) of s is reverse(s) = y, so its scramble is reverse(LK(s));
//   dimension 1 (generator matrix: Pascal's triangle mod 2) of s is linear over GF(2), the XOR of
//   the direction numbers v_j of s's set bits, and what its scramble needs is that value
//   reversed: the XOR of reverse(v_(31−k)) over the set bits k of y, from byte tables.
constexpr std::array<std::array<uint32_t, 256>, 4> dimension1_reversed = [] {
  std::array<uint32_t, 32> v{};
  v[0] = 1u << 31;
  for (int i = 1; i < 32; ++i) v[i] = v[i - 1] ^ (v[i - 1] >> 1);
  std::array<std::array<uint32_t, 256>, 4> t{};
  for (int k = 0; k < 4; ++k)
    for (uint32_t b = 0; b < 256; ++b)
      for (int j = 0; j < 8; ++j)
        if (b >> j & 1) t[k][b] ^= reverse_bits(v[31 - (8 * k + j)]);
  return t;
}();
constexpr uint32_t dimension1_of_reversed(uint32_t r) {
  return dimension1_reversed[0][r & 0xff] ^ dimension1_reversed[1][r >> 8 & 0xff] ^
         dimension1_reversed[2][r >> 16 & 0xff] ^ dimension1_reversed[3][r >> 24];
}

// A pattern's three scramble seeds: the index shuffle's and each component's value scramble.
struct PatternSeeds {
  uint32_t index, component[2];
};
// One pattern per (seed, pixel, depth mod 2^24, slot). mix64 is a bijection: distinct keys,
// distinct patterns. `seed_key` is the seed mixed once (sobol_seed_key). The second component's
// seed is a 32-bit hash (Wellons' lowbias32) of the first's.
inline PatternSeeds pattern_seeds(uint64_t seed_key, uint32_t pixel, uint32_t depth,
                                  uint32_t slot) {
  // (The additive constant keeps seed 0, pixel 0, depth 0, slot 0 off mix64's fixed point 0.)
  const uint64_t key = uint64_t(pixel) << 32 | uint64_t(depth & 0xffffff) << 8 | slot;
  const uint64_t h = mix64(seed_key ^ (key + 0xd1b54a32d192ed03ull));
  uint32_t c1 = uint32_t(h >> 32);
  c1 ^= c1 >> 16;
  c1 *= 0x7feb352du;
  c1 ^= c1 >> 15;
  c1 *= 0x846ca68bu;
  c1 ^= c1 >> 16;
  return {uint32_t(h), {uint32_t(h >> 32), c1}};
}

// A fraction in reversed form (its most significant bit at bit 0) to a float in [0, 1): its top
// 24 bits.
inline float to_float(uint32_t reversed) {
  return float(reverse_bits(reversed) >> 8) * 0x1p-24f;
}

// y as above; each returns its component, Owen-scrambled with `seed`.
inline float component0(uint32_t y, uint32_t seed) {
  return to_float(laine_karras(reverse_bits(y), seed));
}
inline float component1(uint32_t y, uint32_t seed) {
  return to_float(laine_karras(dimension1_of_reversed(y), seed));
}

}  // namespace

std::vector<std::string> sampler_names() {
  return {"independent", "sobol"};
}

std::string sampler_name(SamplerKind kind) {
  return kind == SamplerKind::independent ? "independent" : "sobol";
}

uint64_t sobol_seed_key(uint64_t seed) {
  return mix64(seed + 0x9e3779b97f4a7c15ull);
}

float sobol_number_keyed(uint64_t seed_key, uint32_t pixel, uint32_t index, uint32_t depth,
                         Dimension dim) {
  const DimensionSlot slot = dimension_slots[dim];
  const PatternSeeds k = pattern_seeds(seed_key, pixel, depth, slot.slot);
  const uint32_t r = laine_karras(reverse_bits(index), k.index);
  return slot.component == 0 ? component0(r, k.component[0]) : component1(r, k.component[1]);
}

std::array<float, 2> sobol_pair_keyed(uint64_t seed_key, uint32_t pixel, uint32_t index,
                                      uint32_t depth, Dimension first) {
  const DimensionSlot slot = dimension_slots[first];
  const PatternSeeds k = pattern_seeds(seed_key, pixel, depth, slot.slot);
  const uint32_t r = laine_karras(reverse_bits(index), k.index);
  return {component0(r, k.component[0]), component1(r, k.component[1])};
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
