// Large arrays: std::vector with an allocator that neither zeroes what resize() adds nor keeps
// them on 4 KiB pages. Used by the ray batches, the path tracer's queues and the textures.
#pragma once

#include <cstddef>
#include <memory>
#include <new>
#include <utility>
#include <vector>

namespace dacrt {

// An allocator for large arrays (the batches, queues and kernel records, the textures' texels):
// - the elements resize() adds are default-initialised (uninitialised, for the plain types of a
//   batch) instead of zeroed: batches are written right after they grow, and the path tracer's
//   queues grow every iteration, where zeroing them first was a memset per ray (a decoded
//   texture is written whole by its decoder);
// - the whole 2 MiB pages inside a block are advised to be backed by huge pages
//   (madvise(MADV_HUGEPAGE), honoured where transparent huge pages are set to `madvise` or
//   `always`): first touching a wavefront's state in 4 KiB pages was a quarter of a render here,
//   and texture lookups at random points of images of 16 MiB missed the TLB on 4 KiB pages.
// ::operator new(bytes), with that advice.
void* allocate_large(size_t bytes);
template <class T>
struct UninitializedAllocator : std::allocator<T> {
  template <class U>
  struct rebind {
    using other = UninitializedAllocator<U>;
  };
  UninitializedAllocator() = default;
  template <class U>
  UninitializedAllocator(const UninitializedAllocator<U>&) noexcept {}
  // allocate_large is ::operator new (its alignment) plus the advice, which it gives only where
  // a whole 2 MiB page lies inside the block.
  static_assert(alignof(T) <= __STDCPP_DEFAULT_NEW_ALIGNMENT__);
  T* allocate(size_t n) { return static_cast<T*>(allocate_large(n * sizeof(T))); }
  void deallocate(T* p, size_t) { ::operator delete(static_cast<void*>(p)); }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    if constexpr (sizeof...(Args) == 0)
      ::new (static_cast<void*>(p)) U;
    else
      ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};
template <class T, class U>
bool operator==(const UninitializedAllocator<T>&, const UninitializedAllocator<U>&) {
  return true;
}
// A std::vector whose resize() does not zero, on huge pages where it is large.
template <class T>
using Array = std::vector<T, UninitializedAllocator<T>>;

// Whole pages from the system (mmap), page-aligned and zero, mapped at once (MAP_POPULATE,
// where there is one): `bytes` of zeros without a pass writing them. std::bad_alloc when the
// system has none.
void* allocate_zero_pages(size_t bytes);
void free_zero_pages(void* p, size_t bytes);
// An allocator of zero pages whose construct() leaves what it is given as it is (zero): a
// std::vector<T, ZeroPageAllocator<T>>(n) of plain T is n zeros without a memset over them (a
// film's sums: the system zeroes its pages as it maps them, in one call instead of a fault a
// page), and its data() is page-aligned.
template <class T>
struct ZeroPageAllocator {
  using value_type = T;
  ZeroPageAllocator() = default;
  template <class U>
  ZeroPageAllocator(const ZeroPageAllocator<U>&) noexcept {}
  T* allocate(size_t n) { return static_cast<T*>(allocate_zero_pages(n * sizeof(T))); }
  void deallocate(T* p, size_t n) { free_zero_pages(p, n * sizeof(T)); }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    if constexpr (sizeof...(Args) == 0)
      ::new (static_cast<void*>(p)) U;
    else
      ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};
template <class T, class U>
bool operator==(const ZeroPageAllocator<T>&, const ZeroPageAllocator<U>&) {
  return true;
}

}  // namespace dacrt
