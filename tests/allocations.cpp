// Replaces the global operator new and delete with counting ones (see allocations.h).
#include "allocations.h"

#include <atomic>
#include <malloc.h>

#include <algorithm>
#include <cstdlib>
#include <new>

namespace {

std::atomic<uint64_t> current{0}, highest{0};

void count(uint64_t n) {
  const uint64_t now = current.fetch_add(n) + n;
  uint64_t seen = highest.load();
  while (now > seen && !highest.compare_exchange_weak(seen, now)) {
  }
}

// No header in front of the blocks (LeakSanitizer would take the pointers libraries keep to be
// interior ones, and report them): a block's size is what malloc_usable_size says, at least what
// was asked for, so the counts can only err upwards.
void* allocate(size_t n) {
  void* p = std::malloc(n ? n : 1);
  if (!p) throw std::bad_alloc();
  count(malloc_usable_size(p));
  return p;
}

void release(void* p) {
  if (!p) return;
  current -= malloc_usable_size(p);
  std::free(p);
}

void* allocate(size_t n, std::align_val_t al) {
  const size_t align = std::max(sizeof(void*), size_t(al));
  void* p = std::aligned_alloc(align, (std::max<size_t>(n, 1) + align - 1) / align * align);
  if (!p) throw std::bad_alloc();
  count(malloc_usable_size(p));
  return p;
}

void release(void* p, std::align_val_t) {
  release(p);
}

}  // namespace

namespace dacrt::test {

AllocationWatch::AllocationWatch() : base_(current.load()) {
  highest.store(base_);
}

uint64_t AllocationWatch::live() {
  return current.load();
}

uint64_t AllocationWatch::peak() const {
  const uint64_t h = highest.load();
  return h > base_ ? h - base_ : 0;
}

}  // namespace dacrt::test

void* operator new(size_t n) {
  return allocate(n);
}
void* operator new[](size_t n) {
  return allocate(n);
}
void* operator new(size_t n, const std::nothrow_t&) noexcept {
  try {
    return allocate(n);
  } catch (...) {
    return nullptr;
  }
}
void* operator new[](size_t n, const std::nothrow_t&) noexcept {
  try {
    return allocate(n);
  } catch (...) {
    return nullptr;
  }
}
void* operator new(size_t n, std::align_val_t a) {
  return allocate(n, a);
}
void* operator new[](size_t n, std::align_val_t a) {
  return allocate(n, a);
}
void operator delete(void* p) noexcept {
  release(p);
}
void operator delete[](void* p) noexcept {
  release(p);
}
void operator delete(void* p, size_t) noexcept {
  release(p);
}
void operator delete[](void* p, size_t) noexcept {
  release(p);
}
void operator delete(void* p, std::align_val_t a) noexcept {
  release(p, a);
}
void operator delete[](void* p, std::align_val_t a) noexcept {
  release(p, a);
}
void operator delete(void* p, size_t, std::align_val_t a) noexcept {
  release(p, a);
}
void operator delete[](void* p, size_t, std::align_val_t a) noexcept {
  release(p, a);
}
