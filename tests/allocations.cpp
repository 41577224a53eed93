// Replaces the global operator new and delete with counting ones (see allocations.h). Each block
// carries its size in a header in front of it.
#include "allocations.h"

#include <atomic>
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

constexpr size_t header = 16;  // keeps malloc's 16-byte alignment

void* allocate(size_t n) {
  auto* p = static_cast<unsigned char*>(std::malloc(n + header));
  if (!p) throw std::bad_alloc();
  *reinterpret_cast<size_t*>(p) = n;
  count(n);
  return p + header;
}

void release(void* q) {
  if (!q) return;
  auto* p = static_cast<unsigned char*>(q) - header;
  current -= *reinterpret_cast<size_t*>(p);
  std::free(p);
}

// Aligned blocks: a header of `align` bytes (at least 16), with the size and the header's length
// just in front of the block.
void* allocate(size_t n, std::align_val_t al) {
  const size_t align = std::max(header, size_t(al));
  const size_t total = (n + align + align - 1) / align * align;
  auto* p = static_cast<unsigned char*>(std::aligned_alloc(align, total));
  if (!p) throw std::bad_alloc();
  auto* q = p + align;
  reinterpret_cast<size_t*>(q)[-2] = n;
  reinterpret_cast<size_t*>(q)[-1] = align;
  count(n);
  return q;
}

void release(void* q, std::align_val_t) {
  if (!q) return;
  auto* b = static_cast<unsigned char*>(q);
  current -= reinterpret_cast<size_t*>(b)[-2];
  std::free(b - reinterpret_cast<size_t*>(b)[-1]);
}

}  // namespace

namespace dacrt::test {

AllocationWatch::AllocationWatch() : base_(current.load()) {
  highest.store(base_);
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
