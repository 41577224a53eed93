// The ray/box slab test (Ray::box_hits) for up to 64 RayRef records at once, eight rays per AVX2
// instruction or sixteen per AVX-512 one: the same operations in the same order as the scalar test,
// so the answers are bit for bit the same and the recursion does not depend on the CPU. Bit i of
// the mask is p[i]; nothing past p[n - 1] is read.
#pragma once

#if defined(__x86_64__) || defined(__i386__)
#define DACRT_X86 1
#endif

#include <cstdint>

#include "dacrt/tracer/dacrt/records.h"

namespace dacrt::kernel {

#ifdef DACRT_X86
uint64_t box_mask_avx2(const RayRef* p, int n, const Box& box, float magnitude);
uint64_t box_mask_avx512(const RayRef* p, int n, const Box& box, float magnitude);
#endif

}  // namespace dacrt::kernel
