// Large batch arrays on huge pages (see UninitializedAllocator in ray_batch.h).
#include "tracer/ray_batch.h"

#include <sys/mman.h>

namespace dacrt {

void* allocate_large(size_t bytes) {
  constexpr size_t huge = size_t(2) << 20;
  bytes = (bytes + huge - 1) / huge * huge;
  void* p = ::operator new(bytes, std::align_val_t(huge));
#ifdef MADV_HUGEPAGE
  madvise(p, bytes, MADV_HUGEPAGE);  // advice only: nothing to do if it is not taken
#endif
  return p;
}

}  // namespace dacrt
