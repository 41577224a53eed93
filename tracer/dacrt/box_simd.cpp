// Vector versions of the ray/box slab test (Ray::box_hits) over RayRef records, bit for bit the
// scalar test's answers (see box_simd.h).
#include "dacrt/tracer/dacrt/box_simd.h"

#ifdef DACRT_X86
#include <immintrin.h>

#include <algorithm>
#include <cstddef>

namespace dacrt::kernel {

// The first eight floats of eight records (o, d, tmin, far), one field per register: record k's
// value in lane k. Each record's two halves are loaded whole and transposed in registers (two 4×4
// transposes per 128-bit half): eight gathers of eight lanes each cost several times as much on
// CPUs whose gathers are microcoded.
__attribute__((target("avx2"))) inline void load_fields(const float* r, __m256 (&f)[8]) {
  for (int half = 0; half < 2; ++half) {
    __m256 row[4];  // record k's floats [4 half, 4 half + 4) in the low lane, record k + 4's high
    for (int k = 0; k < 4; ++k)
      row[k] = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(r + 9 * k + 4 * half)),
                                    _mm_loadu_ps(r + 9 * (k + 4) + 4 * half), 1);
    const __m256 t0 = _mm256_unpacklo_ps(row[0], row[1]), t1 = _mm256_unpackhi_ps(row[0], row[1]);
    const __m256 t2 = _mm256_unpacklo_ps(row[2], row[3]), t3 = _mm256_unpackhi_ps(row[2], row[3]);
    f[4 * half + 0] = _mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(1, 0, 1, 0));
    f[4 * half + 1] = _mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(3, 2, 3, 2));
    f[4 * half + 2] = _mm256_shuffle_ps(t1, t3, _MM_SHUFFLE(1, 0, 1, 0));
    f[4 * half + 3] = _mm256_shuffle_ps(t1, t3, _MM_SHUFFLE(3, 2, 3, 2));
  }
}

// Ray::box_hits for the records p[0..n), n <= 64, eight per AVX2 instruction: the same operations
// in the same order (_mm256_min_ps(b, a) is std::min(a, b) exactly, NaN and signed zeros
// included), so the mask is bit for bit the scalar test's. Bit i is p[i]; nothing past p[n - 1] is
// read.
__attribute__((target("avx2"))) uint64_t box_mask_avx2(const RayRef* p, int n, const Box& box,
                                                       float magnitude) {
  static_assert(sizeof(RayRef) == 9 * sizeof(float) && offsetof(RayRef, d) == 12 &&
                offsetof(RayRef, tmin) == 24 && offsetof(RayRef, far) == 28);
  const float* base = reinterpret_cast<const float*>(p);
  __m256 lo[3], hi[3];
  for (int a = 0; a < 3; ++a) lo[a] = _mm256_set1_ps(box.lo[a]), hi[a] = _mm256_set1_ps(box.hi[a]);
  const __m256 sign = _mm256_set1_ps(-0.f), mag = _mm256_set1_ps(magnitude),
               scale = _mm256_set1_ps(0x1p-16f), tiny = _mm256_set1_ps(1e-30f),
               one = _mm256_set1_ps(1.f);
  uint64_t mask = 0;
  for (int g = 0; 8 * g < n; ++g) {
    const float* r = base + 72 * g;
    // A last group of fewer than eight records is copied into zeros; its empty lanes are masked
    // off below.
    const int left = n - 8 * g;
    alignas(32) float tail[72];
    if (left < 8) {
      std::fill(tail, tail + 72, 0.f);
      std::copy(r, r + 9 * left, tail);
      r = tail;
    }
    __m256 f[8];
    load_fields(r, f);
    __m256 o[3], inv[3];
    for (int a = 0; a < 3; ++a) {
      o[a] = f[a];
      // Ray::inverse: 1/d, with |d| < 1e-30 replaced by ±1e-30
      const __m256 d = f[3 + a];
      const __m256 small = _mm256_cmp_ps(_mm256_andnot_ps(sign, d), tiny, _CMP_LT_OQ);
      const __m256 clamped = _mm256_or_ps(_mm256_and_ps(sign, d), tiny);
      inv[a] = _mm256_div_ps(one, _mm256_blendv_ps(d, clamped, small));
    }
    __m256 near = f[6], far = f[7];
    // Ray::pad_for: 2^-16 (max |o| + magnitude)
    const __m256 om =
        _mm256_max_ps(_mm256_max_ps(_mm256_andnot_ps(sign, o[0]), _mm256_andnot_ps(sign, o[1])),
                      _mm256_andnot_ps(sign, o[2]));
    const __m256 pad = _mm256_mul_ps(scale, _mm256_add_ps(om, mag));
    for (int a = 0; a < 3; ++a) {
      const __m256 ta = _mm256_mul_ps(_mm256_sub_ps(_mm256_sub_ps(lo[a], pad), o[a]), inv[a]);
      const __m256 tb = _mm256_mul_ps(_mm256_sub_ps(_mm256_add_ps(hi[a], pad), o[a]), inv[a]);
      near = _mm256_max_ps(_mm256_min_ps(tb, ta), near);  // std::max(near, std::min(ta, tb))
      far = _mm256_min_ps(_mm256_max_ps(tb, ta), far);    // std::min(far, std::max(ta, tb))
    }
    uint32_t hit = uint32_t(_mm256_movemask_ps(_mm256_cmp_ps(near, far, _CMP_LE_OQ)));
    if (left < 8) hit &= (1u << left) - 1u;
    mask |= uint64_t(hit) << (8 * g);
  }
  return mask;
}

// GCC 12's AVX-512 headers start masked intrinsics from _mm512_undefined_*(), which
// -Wmaybe-uninitialized reports once inlined (GCC bug 105593, fixed in GCC 13).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

// |x| for AVX512F, which has float logic only as integer logic.
__attribute__((target("avx512f"))) inline __m512 abs_avx512(__m512 x) {
  return _mm512_castsi512_ps(
      _mm512_andnot_epi32(_mm512_set1_epi32(int32_t(0x80000000u)), _mm512_castps_si512(x)));
}

// Where field f of record r of a group of 16 lies among the group's 144 floats, loaded as nine
// registers: float 9r + f, in the register pair (2q, 2q + 1) with q = (9r + f) / 32 (the ninth
// register alone for q = 4). transpose[f][q] holds the index of each lane within its pair, and
// which lanes the pair serves; a field is five two-register permutes merged by those masks,
// instead of a gather (this test is the kernel's hottest loop).
struct TransposeTable {
  alignas(64) int32_t index[8][5][16];
  uint16_t lanes[8][5];
};
constexpr TransposeTable transpose_table() {
  TransposeTable t{};
  for (int f = 0; f < 8; ++f)
    for (int r = 0; r < 16; ++r) {
      const int at = 9 * r + f, q = at / 32;
      t.index[f][q][r] = at % 32;
      t.lanes[f][q] |= uint16_t(1u << r);
    }
  return t;
}
constexpr TransposeTable transpose = transpose_table();

// Field f of the group's records, lane r from record r.
__attribute__((target("avx512f"))) inline __m512 field_avx512(const __m512* regs, int f) {
  __m512 v = _mm512_permutex2var_ps(
      regs[0], _mm512_load_si512(reinterpret_cast<const void*>(transpose.index[f][0])), regs[1]);
  for (int q = 1; q < 5; ++q) {
    const __m512i index = _mm512_load_si512(reinterpret_cast<const void*>(transpose.index[f][q]));
    const __m512 w = q < 4 ? _mm512_permutex2var_ps(regs[2 * q], index, regs[2 * q + 1])
                           : _mm512_permutexvar_ps(index, regs[8]);
    v = _mm512_mask_mov_ps(v, __mmask16(transpose.lanes[f][q]), w);
  }
  return v;
}

// box_mask_avx2 sixteen rays per instruction. The records are read as nine contiguous registers
// (masked past the last record, so nothing beyond it is read) and transposed in registers.
__attribute__((target("avx512f"))) uint64_t box_mask_avx512(const RayRef* p, int n, const Box& box,
                                                            float magnitude) {
  const float* base = reinterpret_cast<const float*>(p);
  __m512 lo[3], hi[3];
  for (int a = 0; a < 3; ++a) lo[a] = _mm512_set1_ps(box.lo[a]), hi[a] = _mm512_set1_ps(box.hi[a]);
  const __m512i sign = _mm512_set1_epi32(int32_t(0x80000000u));
  const __m512 mag = _mm512_set1_ps(magnitude), scale = _mm512_set1_ps(0x1p-16f),
               tiny = _mm512_set1_ps(1e-30f), one = _mm512_set1_ps(1.f);
  uint64_t mask = 0;
  for (int g = 0; 16 * g < n; ++g) {
    const float* r = base + 144 * g;
    const int left = n - 16 * g;
    const __mmask16 live = left >= 16 ? __mmask16(0xffff) : __mmask16((1u << left) - 1u);
    __m512 regs[9];
    const int floats = 9 * std::min(left, 16);
    for (int k = 0; k < 9; ++k) {
      const int in = std::clamp(floats - 16 * k, 0, 16);
      regs[k] = in == 16 ? _mm512_loadu_ps(r + 16 * k)
                         : _mm512_maskz_loadu_ps(__mmask16((1u << in) - 1u), r + 16 * k);
    }
    __m512 o[3], inv[3];
    for (int a = 0; a < 3; ++a) {
      o[a] = field_avx512(regs, a);
      const __m512 d = field_avx512(regs, 3 + a);
      const __mmask16 small = _mm512_cmp_ps_mask(abs_avx512(d), tiny, _CMP_LT_OQ);
      const __m512 clamped = _mm512_castsi512_ps(_mm512_or_epi32(
          _mm512_and_epi32(sign, _mm512_castps_si512(d)), _mm512_castps_si512(tiny)));
      inv[a] = _mm512_div_ps(one, _mm512_mask_blend_ps(small, d, clamped));
    }
    __m512 near = field_avx512(regs, 6), far = field_avx512(regs, 7);
    const __m512 om =
        _mm512_max_ps(_mm512_max_ps(abs_avx512(o[0]), abs_avx512(o[1])), abs_avx512(o[2]));
    const __m512 pad = _mm512_mul_ps(scale, _mm512_add_ps(om, mag));
    for (int a = 0; a < 3; ++a) {
      const __m512 ta = _mm512_mul_ps(_mm512_sub_ps(_mm512_sub_ps(lo[a], pad), o[a]), inv[a]);
      const __m512 tb = _mm512_mul_ps(_mm512_sub_ps(_mm512_add_ps(hi[a], pad), o[a]), inv[a]);
      near = _mm512_max_ps(_mm512_min_ps(tb, ta), near);
      far = _mm512_min_ps(_mm512_max_ps(tb, ta), far);
    }
    mask |= uint64_t(_mm512_mask_cmp_ps_mask(live, near, far, _CMP_LE_OQ)) << (16 * g);
  }
  return mask;
}
#pragma GCC diagnostic pop

}  // namespace dacrt::kernel
#endif
