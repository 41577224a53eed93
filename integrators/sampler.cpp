#include "dacrt/integrators/sampler.h"

#include <immintrin.h>

#include <array>

#include "dacrt/util/cpu.h"

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
//   reversed. v_j has bit 31 − m set where the binomial C(j, m) is odd, that is (Lucas) where m's
//   bits are a subset of j's, so bit m of the reversed value is the XOR of s's bits j ⊇ m: a
//   superset sum over the five bits of the bit position, one shift-and-XOR step per bit.
constexpr uint32_t dimension1_reversed(uint32_t s) {
  s ^= (s >> 1) & 0x55555555u;
  s ^= (s >> 2) & 0x33333333u;
  s ^= (s >> 4) & 0x0f0f0f0fu;
  s ^= (s >> 8) & 0x00ff00ffu;
  return s ^ s >> 16;
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
  return to_float(laine_karras(dimension1_reversed(reverse_bits(y)), seed));
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

uint32_t sobol_dimension1_reversed(uint32_t s) {
  return dimension1_reversed(s);
}

namespace {

#define DACRT_AVX512_SOBOL __attribute__((target("avx512f,avx512dq,avx512bw")))

bool avx512_sobol_available() {
  static const bool yes = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
                          __builtin_cpu_supports("avx512bw");
  return yes;
}

// GCC 12's intrinsics leave the passthrough operand of their masked builtins undefined on purpose
// (_mm512_undefined_*), which -Wmaybe-uninitialized reports inside the headers.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"

// The scalar functions above, sixteen lanes at a time; the same integer operations in the same
// order, so the same bits.
struct Lanes16 {
  __m512i pixel, index, depth;
};

DACRT_AVX512_SOBOL inline __m512i reverse_bits16(__m512i x) {
  // Bytes reversed within each 32-bit lane, then the bits of each byte by a nibble table.
  const __m512i bytes = _mm512_set4_epi32(0x0c0d0e0f, 0x08090a0b, 0x04050607, 0x00010203);
  const __m512i nibbles = _mm512_broadcast_i32x4(_mm_setr_epi8(
      0x0, 0x8, 0x4, 0xc, 0x2, 0xa, 0x6, 0xe, 0x1, 0x9, 0x5, 0xd, 0x3, 0xb, 0x7, 0xf));
  const __m512i low4 = _mm512_set1_epi8(0x0f);
  x = _mm512_shuffle_epi8(x, bytes);
  const __m512i lo = _mm512_and_si512(x, low4);
  const __m512i hi = _mm512_and_si512(_mm512_srli_epi16(x, 4), low4);
  return _mm512_or_si512(_mm512_slli_epi16(_mm512_shuffle_epi8(nibbles, lo), 4),
                         _mm512_shuffle_epi8(nibbles, hi));
}

DACRT_AVX512_SOBOL inline __m512i mul32(__m512i x, uint32_t c) {
  return _mm512_mullo_epi32(x, _mm512_set1_epi32(int(c)));
}

DACRT_AVX512_SOBOL inline __m512i laine_karras16(__m512i x, __m512i seed) {
  x = _mm512_add_epi32(x, seed);
  x = _mm512_xor_si512(x, mul32(x, 0x6c50b47cu));
  x = _mm512_xor_si512(x, mul32(x, 0xb82f1e52u));
  x = _mm512_xor_si512(x, mul32(x, 0xc7afe638u));
  x = _mm512_xor_si512(x, mul32(x, 0x8d22f6e6u));
  return x;
}

DACRT_AVX512_SOBOL inline __m512i mix64_8(__m512i x) {
  x = _mm512_xor_si512(x, _mm512_srli_epi64(x, 30));
  x = _mm512_mullo_epi64(x, _mm512_set1_epi64(int64_t(0xbf58476d1ce4e5b9ull)));
  x = _mm512_xor_si512(x, _mm512_srli_epi64(x, 27));
  x = _mm512_mullo_epi64(x, _mm512_set1_epi64(int64_t(0x94d049bb133111ebull)));
  return _mm512_xor_si512(x, _mm512_srli_epi64(x, 31));
}

DACRT_AVX512_SOBOL inline __m512i join(__m256i lo, __m256i hi) {
  return _mm512_inserti64x4(_mm512_castsi256_si512(lo), hi, 1);
}

// pattern_seeds of the sixteen lanes: the index seeds and both components' seeds.
struct Seeds16 {
  __m512i index, c0, c1;
};
DACRT_AVX512_SOBOL Seeds16 pattern_seeds16(uint64_t seed_key, const Lanes16& l, uint32_t slot) {
  const __m512i key_xor = _mm512_set1_epi64(int64_t(seed_key));
  const __m512i add = _mm512_set1_epi64(int64_t(0xd1b54a32d192ed03ull));
  const __m512i depth =
      _mm512_slli_epi32(_mm512_and_si512(l.depth, _mm512_set1_epi32(0xffffff)), 8);
  const __m512i low = _mm512_or_si512(depth, _mm512_set1_epi32(int(slot)));
  __m256i h_lo[2], h_hi[2];
  for (int half = 0; half < 2; ++half) {
    const __m256i p =
        half ? _mm512_extracti64x4_epi64(l.pixel, 1) : _mm512_castsi512_si256(l.pixel);
    const __m256i q = half ? _mm512_extracti64x4_epi64(low, 1) : _mm512_castsi512_si256(low);
    const __m512i key =
        _mm512_or_si512(_mm512_slli_epi64(_mm512_cvtepu32_epi64(p), 32), _mm512_cvtepu32_epi64(q));
    const __m512i h = mix64_8(_mm512_xor_si512(key_xor, _mm512_add_epi64(key, add)));
    h_lo[half] = _mm512_cvtepi64_epi32(h);
    h_hi[half] = _mm512_cvtepi64_epi32(_mm512_srli_epi64(h, 32));
  }
  Seeds16 s;
  s.index = join(h_lo[0], h_lo[1]);
  s.c0 = join(h_hi[0], h_hi[1]);
  __m512i c1 = s.c0;
  c1 = _mm512_xor_si512(c1, _mm512_srli_epi32(c1, 16));
  c1 = mul32(c1, 0x7feb352du);
  c1 = _mm512_xor_si512(c1, _mm512_srli_epi32(c1, 15));
  c1 = mul32(c1, 0x846ca68bu);
  s.c1 = _mm512_xor_si512(c1, _mm512_srli_epi32(c1, 16));
  return s;
}

DACRT_AVX512_SOBOL inline __m512 to_float16(__m512i reversed) {
  const __m512i bits = _mm512_srli_epi32(reverse_bits16(reversed), 8);
  return _mm512_mul_ps(_mm512_cvtepi32_ps(bits), _mm512_set1_ps(0x1p-24f));
}

// dimension1_reversed of each lane.
DACRT_AVX512_SOBOL inline __m512i dimension1_reversed16(__m512i s) {
  const uint32_t masks[4] = {0x55555555u, 0x33333333u, 0x0f0f0f0fu, 0x00ff00ffu};
  for (int k = 0; k < 4; ++k)
    s = _mm512_xor_si512(
        s, _mm512_and_si512(_mm512_srli_epi32(s, 1 << k), _mm512_set1_epi32(int(masks[k]))));
  return _mm512_xor_si512(s, _mm512_srli_epi32(s, 16));
}

DACRT_AVX512_SOBOL void sobol_numbers16(uint64_t seed_key, const uint32_t* pixel,
                                        const uint32_t* index, const uint32_t* depth, size_t lanes,
                                        std::span<const Dimension> dims, VertexNumbers* out) {
  const __mmask16 live = __mmask16((1u << lanes) - 1u);
  Lanes16 l;
  l.pixel = _mm512_maskz_loadu_epi32(live, pixel);
  l.index = _mm512_maskz_loadu_epi32(live, index);
  l.depth = _mm512_maskz_loadu_epi32(live, depth);
  const __m512i reversed_index = reverse_bits16(l.index);
  alignas(64) float c[2][sampler_lanes];
  for (const Dimension dim : dims) {
    const DimensionSlot slot = dimension_slots[dim];
    const Seeds16 k = pattern_seeds16(seed_key, l, slot.slot);
    const __m512i r = laine_karras16(reversed_index, k.index);
    const bool both = slot.pair;
    const __m512i shuffled = reverse_bits16(r);  // s
    if (both || slot.component == 0)
      _mm512_store_ps(c[0], to_float16(laine_karras16(shuffled, k.c0)));
    if (both || slot.component == 1)
      _mm512_store_ps(c[1], to_float16(laine_karras16(dimension1_reversed16(shuffled), k.c1)));
    for (size_t j = 0; j < lanes; ++j) {
      if (both) {
        out[j][dim] = c[0][j];
        out[j][dim + 1] = c[1][j];
      } else {
        out[j][dim] = c[slot.component][j];
      }
    }
  }
}

// The same with AVX2, eight lanes at a time (CPUs without AVX-512): 64-bit products from 32-bit
// ones, and the nibble tables by two eight-entry permutes. Again the same integer operations.
#define DACRT_AVX2_SOBOL __attribute__((target("avx2")))

DACRT_AVX2_SOBOL inline __m256i reverse_bits8(__m256i x) {
  const __m256i bytes = _mm256_setr_epi8(3, 2, 1, 0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12, 3,
                                         2, 1, 0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12);
  const __m256i nibbles = _mm256_setr_epi8(0x0, 0x8, 0x4, 0xc, 0x2, 0xa, 0x6, 0xe, 0x1, 0x9, 0x5,
                                           0xd, 0x3, 0xb, 0x7, 0xf, 0x0, 0x8, 0x4, 0xc, 0x2, 0xa,
                                           0x6, 0xe, 0x1, 0x9, 0x5, 0xd, 0x3, 0xb, 0x7, 0xf);
  const __m256i low4 = _mm256_set1_epi8(0x0f);
  x = _mm256_shuffle_epi8(x, bytes);
  const __m256i lo = _mm256_and_si256(x, low4);
  const __m256i hi = _mm256_and_si256(_mm256_srli_epi16(x, 4), low4);
  return _mm256_or_si256(_mm256_slli_epi16(_mm256_shuffle_epi8(nibbles, lo), 4),
                         _mm256_shuffle_epi8(nibbles, hi));
}

DACRT_AVX2_SOBOL inline __m256i mul32_8(__m256i x, uint32_t c) {
  return _mm256_mullo_epi32(x, _mm256_set1_epi32(int(c)));
}

DACRT_AVX2_SOBOL inline __m256i laine_karras8(__m256i x, __m256i seed) {
  x = _mm256_add_epi32(x, seed);
  x = _mm256_xor_si256(x, mul32_8(x, 0x6c50b47cu));
  x = _mm256_xor_si256(x, mul32_8(x, 0xb82f1e52u));
  x = _mm256_xor_si256(x, mul32_8(x, 0xc7afe638u));
  x = _mm256_xor_si256(x, mul32_8(x, 0x8d22f6e6u));
  return x;
}

// The low 64 bits of x × c in each 64-bit lane.
DACRT_AVX2_SOBOL inline __m256i mul64_4(__m256i x, uint64_t c) {
  const __m256i c_lo = _mm256_set1_epi64x(int64_t(c & 0xffffffffu));
  const __m256i c_hi = _mm256_set1_epi64x(int64_t(c >> 32));
  const __m256i cross = _mm256_add_epi64(_mm256_mul_epu32(_mm256_srli_epi64(x, 32), c_lo),
                                         _mm256_mul_epu32(x, c_hi));
  return _mm256_add_epi64(_mm256_mul_epu32(x, c_lo), _mm256_slli_epi64(cross, 32));
}

DACRT_AVX2_SOBOL inline __m256i mix64_4(__m256i x) {
  x = _mm256_xor_si256(x, _mm256_srli_epi64(x, 30));
  x = mul64_4(x, 0xbf58476d1ce4e5b9ull);
  x = _mm256_xor_si256(x, _mm256_srli_epi64(x, 27));
  x = mul64_4(x, 0x94d049bb133111ebull);
  return _mm256_xor_si256(x, _mm256_srli_epi64(x, 31));
}

// What pattern_seeds8 keeps of a vertex across its dimensions: each lane's pattern key before
// the slot, pixel << 32 | (depth mod 2^24) << 8, with mix64's additive constant added (the slot
// fills the key's low byte, which is zero here, so key + constant = this + slot), lanes 0, 1, 4,
// 5 in `a` and 2, 3, 6, 7 in `b` (the order _mm256_unpack*_epi32 and _mm256_shuffle_ps keep).
struct Keys8 {
  __m256i a, b;
};
DACRT_AVX2_SOBOL inline Keys8 pattern_keys8(__m256i pixel, __m256i depth) {
  const __m256i add = _mm256_set1_epi64x(int64_t(0xd1b54a32d192ed03ull));
  const __m256i low = _mm256_slli_epi32(_mm256_and_si256(depth, _mm256_set1_epi32(0xffffff)), 8);
  return {_mm256_add_epi64(_mm256_unpacklo_epi32(low, pixel), add),
          _mm256_add_epi64(_mm256_unpackhi_epi32(low, pixel), add)};
}

// pattern_seeds of the eight lanes for one slot: the index seeds and component 0's; component
// 1's from component 0's by seed1_8.
struct Seeds8 {
  __m256i index, c0;
};
DACRT_AVX2_SOBOL inline Seeds8 pattern_seeds8(uint64_t seed_key, const Keys8& keys, uint32_t slot) {
  const __m256i key_xor = _mm256_set1_epi64x(int64_t(seed_key));
  const __m256i s = _mm256_set1_epi64x(int64_t(slot));
  const __m256 a =
      _mm256_castsi256_ps(mix64_4(_mm256_xor_si256(key_xor, _mm256_add_epi64(keys.a, s))));
  const __m256 b =
      _mm256_castsi256_ps(mix64_4(_mm256_xor_si256(key_xor, _mm256_add_epi64(keys.b, s))));
  // The hashes' low words (the index seeds) and high words (component 0's), lanes in order.
  return {_mm256_castps_si256(_mm256_shuffle_ps(a, b, _MM_SHUFFLE(2, 0, 2, 0))),
          _mm256_castps_si256(_mm256_shuffle_ps(a, b, _MM_SHUFFLE(3, 1, 3, 1)))};
}
DACRT_AVX2_SOBOL inline __m256i seed1_8(__m256i c1) {
  c1 = _mm256_xor_si256(c1, _mm256_srli_epi32(c1, 16));
  c1 = mul32_8(c1, 0x7feb352du);
  c1 = _mm256_xor_si256(c1, _mm256_srli_epi32(c1, 15));
  c1 = mul32_8(c1, 0x846ca68bu);
  return _mm256_xor_si256(c1, _mm256_srli_epi32(c1, 16));
}

DACRT_AVX2_SOBOL inline __m256 to_float8(__m256i reversed) {
  const __m256i bits = _mm256_srli_epi32(reverse_bits8(reversed), 8);
  return _mm256_mul_ps(_mm256_cvtepi32_ps(bits), _mm256_set1_ps(0x1p-24f));
}

// dimension1_reversed of each lane.
DACRT_AVX2_SOBOL inline __m256i dimension1_reversed8(__m256i s) {
  const uint32_t masks[4] = {0x55555555u, 0x33333333u, 0x0f0f0f0fu, 0x00ff00ffu};
  for (int k = 0; k < 4; ++k)
    s = _mm256_xor_si256(
        s, _mm256_and_si256(_mm256_srli_epi32(s, 1 << k), _mm256_set1_epi32(int(masks[k]))));
  return _mm256_xor_si256(s, _mm256_srli_epi32(s, 16));
}

DACRT_AVX2_SOBOL void sobol_numbers8(uint64_t seed_key, const uint32_t* pixel,
                                     const uint32_t* index, const uint32_t* depth, size_t lanes,
                                     std::span<const Dimension> dims, VertexNumbers* out) {
  // The lanes past `lanes` read as zero (a masked load touches none of their memory).
  __m256i pixels, indices, depths;
  if (lanes == 8) {
    pixels = _mm256_loadu_si256((const __m256i*)pixel);
    indices = _mm256_loadu_si256((const __m256i*)index);
    depths = _mm256_loadu_si256((const __m256i*)depth);
  } else {
    const __m256i live = _mm256_cmpgt_epi32(_mm256_set1_epi32(int(lanes)),
                                            _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
    pixels = _mm256_maskload_epi32((const int*)pixel, live);
    indices = _mm256_maskload_epi32((const int*)index, live);
    depths = _mm256_maskload_epi32((const int*)depth, live);
  }
  const Keys8 keys = pattern_keys8(pixels, depths);
  const __m256i reversed_index = reverse_bits8(indices);
  alignas(32) float c[2][8];
  for (const Dimension dim : dims) {
    const DimensionSlot slot = dimension_slots[dim];
    const Seeds8 k = pattern_seeds8(seed_key, keys, slot.slot);
    const __m256i r = laine_karras8(reversed_index, k.index);
    const bool both = slot.pair;
    const __m256i shuffled = reverse_bits8(r);  // s
    if (both || slot.component == 0)
      _mm256_store_ps(c[0], to_float8(laine_karras8(shuffled, k.c0)));
    if (both || slot.component == 1)
      _mm256_store_ps(c[1],
                      to_float8(laine_karras8(dimension1_reversed8(shuffled), seed1_8(k.c0))));
    for (size_t j = 0; j < lanes; ++j) {
      if (both) {
        out[j][dim] = c[0][j];
        out[j][dim + 1] = c[1][j];
      } else {
        out[j][dim] = c[slot.component][j];
      }
    }
  }
}

#pragma GCC diagnostic pop

}  // namespace

void Sampler::numbers(const uint32_t* pixel, const uint32_t* index, const uint32_t* depth,
                      size_t lanes, std::span<const Dimension> dims, VertexNumbers* out) const {
  if (kind == SamplerKind::sobol && avx512_sobol_available()) {
    for (size_t first = 0; first < lanes; first += sampler_lanes)
      sobol_numbers16(key, pixel + first, index + first, depth + first,
                      std::min(sampler_lanes, lanes - first), dims, out + first);
    return;
  }
  if (kind == SamplerKind::sobol && avx2_available()) {
    for (size_t first = 0; first < lanes; first += 8)
      sobol_numbers8(key, pixel + first, index + first, depth + first,
                     std::min(size_t(8), lanes - first), dims, out + first);
    return;
  }
  for (size_t j = 0; j < lanes; ++j)
    for (const Dimension dim : dims) {
      if (dimension_slots[dim].pair) {
        const auto p = pair(pixel[j], index[j], depth[j], dim);
        out[j][dim] = p[0];
        out[j][dim + 1] = p[1];
      } else {
        out[j][dim] = number(pixel[j], index[j], depth[j], dim);
      }
    }
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
