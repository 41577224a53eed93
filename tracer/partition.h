// Branch-free in-place partition for the DACRT kernel's hot loops (ray filtering and triangle
// splitting), after Edelkamp and Weiß, "BlockQuicksort: Avoiding Branch Mispredictions in
// Quicksort", ESA 2016. The predicate is evaluated for a block of elements from each end without
// branching on its result, the positions of misplaced elements are recorded, and they are swapped
// in pairs: the unpredictable branch per element of std::partition (a ray that hits a box or not is
// a coin flip) becomes a loop of fixed length.
#pragma once

#include <algorithm>
#include <cstdint>
#include <utility>

namespace dacrt {

// Reorders [first, last) so that the elements satisfying `pred` come first; returns the end of
// them. Not stable, like std::partition. `pred` must be a pure function of the element.
template <typename T, typename Pred>
T* block_partition(T* first, T* last, Pred pred) {
  constexpr int block = 64;
  uint8_t left[block], right[block];  // offsets of misplaced elements in the current end blocks
  int num_left = 0, num_right = 0, start_left = 0, start_right = 0;
  while (last - first > 2 * block) {
    if (num_left == 0) {
      start_left = 0;
      for (int i = 0; i < block; ++i) {
        left[num_left] = uint8_t(i);
        num_left += !pred(first[i]);
      }
    }
    if (num_right == 0) {
      start_right = 0;
      for (int i = 0; i < block; ++i) {
        right[num_right] = uint8_t(i);
        num_right += bool(pred(*(last - 1 - i)));
      }
    }
    const int n = std::min(num_left, num_right);
    for (int j = 0; j < n; ++j)
      std::swap(first[left[start_left + j]], *(last - 1 - right[start_right + j]));
    num_left -= n, num_right -= n, start_left += n, start_right += n;
    if (num_left == 0) first += block;
    if (num_right == 0) last -= block;
  }
  // Left of first everything satisfies pred, from last on nothing does; what is between (at most
  // two partly resolved blocks) is finished the ordinary way.
  return std::partition(first, last, pred);
}

}  // namespace dacrt
