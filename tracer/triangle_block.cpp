// The 8-wide watertight triangle filter (see triangle_block.h). Compiled for AVX2 by a function
// attribute and chosen at run time, so the library still runs on any x86-64 (and elsewhere).
#include "tracer/triangle_block.h"

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#define DACRT_X86 1
#endif

namespace dacrt {

#ifdef DACRT_X86

bool avx2_available() {
  static const bool yes = __builtin_cpu_supports("avx2");
  return yes;
}

bool avx512_available() {
  static const bool yes = __builtin_cpu_supports("avx512f");
  return yes;
}

__attribute__((target("avx2"))) inline __m256 abs8(__m256 v) {
  return _mm256_andnot_ps(_mm256_set1_ps(-0.f), v);
}
__attribute__((target("avx2"))) inline __m256 max3(const __m256* v) {
  return _mm256_max_ps(_mm256_max_ps(abs8(v[0]), abs8(v[1])), abs8(v[2]));
}

// Mirrors intersect_triangle line by line; -ffp-contract=off keeps every multiply and add apart.
__attribute__((target("avx2"))) uint32_t block_candidates(const TriangleBlock& b, const Ray& r,
                                                          float tmin, float tmax) {
  const __m256 ox = _mm256_set1_ps(r.o[r.kx]), oy = _mm256_set1_ps(r.o[r.ky]),
               oz = _mm256_set1_ps(r.o[r.kz]);
  const __m256 sx = _mm256_set1_ps(r.sx), sy = _mm256_set1_ps(r.sy), sz = _mm256_set1_ps(r.sz);
  __m256 x[3], y[3], z[3];  // corners translated to the origin and sheared
  for (int c = 0; c < 3; ++c) {
    const __m256 ax = _mm256_sub_ps(_mm256_load_ps(b.p[c][r.kx]), ox);
    const __m256 ay = _mm256_sub_ps(_mm256_load_ps(b.p[c][r.ky]), oy);
    const __m256 az = _mm256_sub_ps(_mm256_load_ps(b.p[c][r.kz]), oz);
    x[c] = _mm256_sub_ps(ax, _mm256_mul_ps(sx, az));
    y[c] = _mm256_sub_ps(ay, _mm256_mul_ps(sy, az));
    z[c] = _mm256_mul_ps(sz, az);
  }
  // e_k = p·q' − p'·q over the other two corners, as in intersect_triangle.
  const __m256 e0 =
      _mm256_sub_ps(_mm256_mul_ps(x[2], y[1]), _mm256_mul_ps(y[2], x[1]));  // cx·by − cy·bx
  const __m256 e1 =
      _mm256_sub_ps(_mm256_mul_ps(x[0], y[2]), _mm256_mul_ps(y[0], x[2]));  // ax·cy − ay·cx
  const __m256 e2 =
      _mm256_sub_ps(_mm256_mul_ps(x[1], y[0]), _mm256_mul_ps(y[1], x[0]));  // bx·ay − by·ax
  const __m256 zero = _mm256_setzero_ps();
  const __m256 any_zero = _mm256_or_ps(
      _mm256_or_ps(_mm256_cmp_ps(e0, zero, _CMP_EQ_OQ), _mm256_cmp_ps(e1, zero, _CMP_EQ_OQ)),
      _mm256_cmp_ps(e2, zero, _CMP_EQ_OQ));
  const __m256 any_neg = _mm256_or_ps(
      _mm256_or_ps(_mm256_cmp_ps(e0, zero, _CMP_LT_OQ), _mm256_cmp_ps(e1, zero, _CMP_LT_OQ)),
      _mm256_cmp_ps(e2, zero, _CMP_LT_OQ));
  const __m256 any_pos = _mm256_or_ps(
      _mm256_or_ps(_mm256_cmp_ps(e0, zero, _CMP_GT_OQ), _mm256_cmp_ps(e1, zero, _CMP_GT_OQ)),
      _mm256_cmp_ps(e2, zero, _CMP_GT_OQ));
  const __m256 det = _mm256_add_ps(_mm256_add_ps(e0, e1), e2);
  const __m256 abs_det = _mm256_andnot_ps(_mm256_set1_ps(-0.f), det);
  const __m256 det_ok = _mm256_and_ps(_mm256_cmp_ps(det, zero, _CMP_NEQ_OQ),
                                      _mm256_cmp_ps(abs_det, _mm256_set1_ps(INFINITY), _CMP_LT_OQ));
  const __m256 t =
      _mm256_div_ps(_mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(e0, z[0]), _mm256_mul_ps(e1, z[1])),
                                  _mm256_mul_ps(e2, z[2])),
                    det);
  // In range, or not finite, or within a bound of 0 that is at least intersect_triangle's error
  // bound delta_t (the scalar test then decides with t in double, whatever the range). The bound
  // is cruder than the scalar one: with M the largest |x|, |y| or |z| of the sheared corners,
  // delta_t <= 3 (2 gamma(3) max|e| M + 2 (gamma(2) + 4 gamma(5)) M^3) / |det|; the constants
  // here are more than twice those, so that rounding cannot take the bound below delta_t.
  const __m256 m = _mm256_max_ps(_mm256_max_ps(max3(x), max3(y)), max3(z));
  const __m256 max_e = _mm256_max_ps(_mm256_max_ps(abs8(e0), abs8(e1)), abs8(e2));
  const __m256 bound = _mm256_div_ps(
      _mm256_add_ps(_mm256_mul_ps(_mm256_mul_ps(_mm256_set1_ps(3e-6f), max_e), m),
                    _mm256_mul_ps(_mm256_mul_ps(_mm256_mul_ps(_mm256_set1_ps(2e-5f), m), m), m)),
      abs_det);
  const __m256 t_ok =
      _mm256_or_ps(_mm256_or_ps(_mm256_and_ps(_mm256_cmp_ps(t, _mm256_set1_ps(tmin), _CMP_GE_OQ),
                                              _mm256_cmp_ps(t, _mm256_set1_ps(tmax), _CMP_LE_OQ)),
                                _mm256_cmp_ps(abs8(t), _mm256_set1_ps(INFINITY), _CMP_NLT_UQ)),
                   _mm256_cmp_ps(abs8(t), bound, _CMP_NGT_UQ));
  const __m256 accept =
      _mm256_and_ps(_mm256_andnot_ps(_mm256_and_ps(any_neg, any_pos), det_ok), t_ok);
  const uint32_t lanes = (1u << b.n) - 1u;
  return uint32_t(_mm256_movemask_ps(_mm256_or_ps(accept, any_zero))) & lanes;
}

#else

bool avx2_available() {
  return false;
}
bool avx512_available() {
  return false;
}
uint32_t block_candidates(const TriangleBlock& b, const Ray&, float, float) {
  return (1u << b.n) - 1u;  // never called; every lane is a candidate
}

#endif

}  // namespace dacrt
