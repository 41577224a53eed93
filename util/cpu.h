// What vector instructions this CPU runs, asked once: the kernels with AVX2 or AVX-512 variants
// (the DACRT box and triangle tests, the Sobol numbers, the shading lanes, the light tree) choose
// them at run time with these, so the library runs on any x86-64 (and elsewhere, without them).
#pragma once

namespace dacrt {

inline bool avx2_available() {
#if defined(__x86_64__) || defined(__i386__)
  static const bool yes = __builtin_cpu_supports("avx2");
  return yes;
#else
  return false;
#endif
}

// AVX512F (the DACRT box and triangle tests' sixteen-lane variants).
inline bool avx512_available() {
#if defined(__x86_64__) || defined(__i386__)
  static const bool yes = __builtin_cpu_supports("avx512f");
  return yes;
#else
  return false;
#endif
}

}  // namespace dacrt
