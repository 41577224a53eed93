// Branch-free in-place partition for the DACRT kernel's hot loops (ray filtering and triangle
// splitting), after Edelkamp and Weiß, "BlockQuicksort: Avoiding Branch Mispredictions in
// Quicksort", ESA 2016. The predicate is evaluated for a block of elements from each end without
// branching on its result, the positions of misplaced elements are recorded, and they are swapped
// in pairs: the unpredictable branch per element of std::partition (a ray that hits a box or not is
// a coin flip) becomes a loop of fixed length.
#pragma once

#include <algorithm>
#include <bit>
#include <cstdint>
#include <utility>

namespace dacrt {

// Reorders [first, last) so that the elements satisfying a predicate come first; returns the end
// of them. Not stable, like std::partition. `classify(p, n)` returns the predicate of p[0..n),
// 1 <= n <= 64, as the bits of a mask (bit i for p[i], no bits from n on), so that it can test
// several elements per instruction; it must be a pure function of the elements.
template <typename T, typename Classify>
T* block_partition(T* first, T* last, Classify classify) {
  constexpr int block = 64;
  // Offsets of misplaced elements in the current end blocks (and, at the end, in what is left).
  uint8_t left[2 * block], right[2 * block];
  int num_left = 0, num_right = 0, start_left = 0, start_right = 0;
  while (last - first > 2 * block) {
    if (num_left == 0) {  // elements of the left block that belong right
      start_left = 0;
      for (uint64_t m = ~uint64_t(classify(first, block)); m; m &= m - 1)
        left[num_left++] = uint8_t(std::countr_zero(m));
    }
    if (num_right == 0) {  // elements of the right block (offsets from last - 1) that belong left
      start_right = 0;
      // Bit 63 - i of the mask is element last - 1 - i: count from the top.
      for (uint64_t m = classify(last - block, block); m;) {
        const int i = std::countl_zero(m);
        right[num_right++] = uint8_t(i);
        m &= ~(uint64_t(1) << (63 - i));
      }
    }
    const int n = std::min(num_left, num_right);
    for (int j = 0; j < n; ++j)
      std::swap(first[left[start_left + j]], *(last - 1 - right[start_right + j]));
    num_left -= n, num_right -= n, start_left += n, start_right += n;
    if (num_left == 0) first += block;
    if (num_right == 0) last -= block;
  }
  // Left of first everything satisfies the predicate, from last on nothing does. What is between
  // (at most two blocks, partly resolved) is classified afresh and its misplaced elements swapped
  // in pairs.
  const int n = int(last - first);
  if (n == 0) return first;
  uint8_t flag[2 * block];
  if (n > block) {  // two overlapping blocks cover it
    const uint64_t head = classify(first, block), tail = classify(last - block, block);
    for (int i = 0; i < block; ++i) flag[i] = uint8_t((head >> i) & 1u);
    for (int i = 0; i < block; ++i) flag[n - block + i] = uint8_t((tail >> i) & 1u);
  } else {
    const uint64_t all = classify(first, n);
    for (int i = 0; i < n; ++i) flag[i] = uint8_t((all >> i) & 1u);
  }
  int count = 0;
  for (int i = 0; i < n; ++i) count += flag[i];
  int num = 0, other = 0;
  for (int i = 0; i < count; ++i) left[num] = uint8_t(i), num += !flag[i];
  for (int i = count; i < n; ++i) right[other] = uint8_t(i), other += flag[i];
  for (int j = 0; j < num; ++j) std::swap(first[left[j]], first[right[j]]);
  return first + count;
}

// The same with the predicate evaluated one element at a time, without branching on it.
template <typename T, typename Pred>
T* block_partition_by(T* first, T* last, Pred pred) {
  auto classify = [&](const T* p, int n) {
    uint64_t m = 0;
    for (int i = 0; i < n; ++i) m |= uint64_t(bool(pred(p[i]))) << i;
    return m;
  };
  return block_partition(first, last, classify);
}

}  // namespace dacrt
