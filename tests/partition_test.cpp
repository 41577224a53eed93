// block_partition (tracer/partition.h): the same split as std::partition, in place, for every size
// around its block boundaries, with the per-element and the 64-at-a-time predicate.
#include "dacrt/tracer/partition.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <vector>

#include "dacrt/util/random.h"

using namespace dacrt;

namespace {

void check_partition(std::vector<uint32_t> v, uint32_t threshold, bool masked) {
  auto pred = [&](uint32_t x) { return x < threshold; };
  uint32_t *first = v.data(), *last = v.data() + v.size();
  auto classify = [&](const uint32_t* p, int n) {
    REQUIRE(n >= 1);
    REQUIRE(n <= 64);
    REQUIRE(p >= first);
    REQUIRE(p + n <= last);  // never reads past the range
    uint64_t m = 0;
    for (int i = 0; i < n; ++i) m |= uint64_t(pred(p[i])) << i;
    return m;
  };
  std::vector<uint32_t> before = v;
  uint32_t* mid =
      masked ? block_partition(first, last, classify) : block_partition_by(first, last, pred);
  const size_t split = size_t(mid - v.data());
  CHECK(split == size_t(std::count_if(before.begin(), before.end(), pred)));
  CHECK(std::all_of(v.begin(), v.begin() + split, pred));
  CHECK(std::none_of(v.begin() + split, v.end(), pred));
  std::sort(before.begin(), before.end());
  std::sort(v.begin(), v.end());
  CHECK(v == before);  // a permutation: nothing lost or duplicated
}

}  // namespace

TEST_CASE("block_partition splits like std::partition at every size and ratio") {
  Pcg32 rng(3);
  for (size_t n : {0, 1, 2, 63, 64, 65, 127, 128, 129, 130, 191, 192, 255, 256, 257, 1000, 4099}) {
    for (uint32_t threshold : {0u, 1u, 50u, 99u, 100u}) {  // none, few, half, most, all
      INFO("n = " << n << ", threshold = " << threshold);
      std::vector<uint32_t> v(n);
      for (auto& x : v) x = rng.below(100);
      check_partition(v, threshold, false);
      check_partition(v, threshold, true);
    }
  }
}
