// The wavefront stages' parallel building blocks. Each is deterministic: its output is the same,
// in the same order, for any number of threads, so that the path tracer's batches, and with them
// the image, do not depend on the machine.
#pragma once

#include <tbb/parallel_for.h>

#include <cstdint>
#include <numeric>
#include <vector>

namespace dacrt {

// Calls emit(i, k) for the indices i in [0, n) with keep(i), in increasing order of i, k counting
// them from 0; returns how many were kept. Blocks are counted in parallel, then each emits from
// its offset, so emit may write position k of an output without locks, but not of its input: a
// block may run before the one whose elements it overwrites.
template <class Keep, class Emit>
size_t compact(size_t n, Keep keep, Emit emit) {
  constexpr size_t block = 8192;
  const size_t blocks = (n + block - 1) / block;
  std::vector<size_t> offset(blocks + 1, 0);
  tbb::parallel_for(size_t(0), blocks, [&](size_t b) {
    size_t count = 0;
    for (size_t i = b * block, end = std::min(n, (b + 1) * block); i < end; ++i) count += keep(i);
    offset[b + 1] = count;
  });
  std::partial_sum(offset.begin(), offset.end(), offset.begin());
  tbb::parallel_for(size_t(0), blocks, [&](size_t b) {
    size_t k = offset[b];
    for (size_t i = b * block, end = std::min(n, (b + 1) * block); i < end; ++i)
      if (keep(i)) emit(i, k++);
  });
  return offset[blocks];
}

// The indices i in [0, n) with keep(i), in increasing order.
template <class Keep, class Out>
void select(size_t n, Keep keep, Out& out) {
  out.resize(n);
  out.resize(compact(n, keep, [&](size_t i, size_t k) { out[k] = uint32_t(i); }));
}

}  // namespace dacrt
