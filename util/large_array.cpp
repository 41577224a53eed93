// Large arrays on huge pages (see UninitializedAllocator in large_array.h).
#include "dacrt/util/large_array.h"

#include <sys/mman.h>

#include <cstdint>

namespace dacrt {

void* allocate_large(size_t bytes) {
  void* p = ::operator new(bytes);
#ifdef MADV_HUGEPAGE
  // Advice only, for the whole 2 MiB pages inside the block (its ends stay in small pages): an
  // aligned allocation would cost up to 2 MiB more address space than asked for.
  constexpr uintptr_t huge = uintptr_t(2) << 20;
  const uintptr_t begin = (uintptr_t(p) + huge - 1) & ~(huge - 1);
  const uintptr_t end = (uintptr_t(p) + bytes) & ~(huge - 1);
  if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
#endif
  return p;
}

void* allocate_zero_pages(size_t bytes) {
  if (bytes == 0) bytes = 1;
  // Mapped at once where the system can (MAP_POPULATE): faulting them in one at a time cost
  // this VM twice the system time.
  int flags = MAP_PRIVATE | MAP_ANONYMOUS;
#ifdef MAP_POPULATE
  flags |= MAP_POPULATE;
#endif
  void* p = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, flags, -1, 0);
  if (p == MAP_FAILED) throw std::bad_alloc();
  return p;
}

void free_zero_pages(void* p, size_t bytes) {
  if (p) munmap(p, bytes == 0 ? 1 : bytes);
}

}  // namespace dacrt
