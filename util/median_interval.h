// MedianInterval: the median of a few timed runs and a distribution-free confidence interval for
// the true median, from order statistics (the sign-test interval; e.g. Hollander, Wolfe and
// Chicken, "Nonparametric Statistical Methods", 3rd ed., section 3.6). With the n runs sorted,
// x(1) <= ... <= x(n), the true median m lies in [x(k), x(n+1-k)] with probability
// 1 - 2 P(B <= k-1), B ~ Binomial(n, 1/2), for any continuous distribution: the number of runs
// below m is B. The interval is the narrowest of that form whose coverage reaches the level asked.
// Below n = 6 no such interval reaches 95 %: the result is then the min-max range (k = 1) with the
// coverage it has (n = 5: 93.75 %), which callers should print next to it.
#pragma once

#include <cstddef>
#include <vector>

namespace dacrt {

// Ranks of the interval, counted from 1 in the sorted sample: [x(low), x(high)], high = n+1-low.
// n = 0 gives {0, 0, 0}.
struct MedianRanks {
  size_t low = 0, high = 0;
  double coverage = 0.0;  // P(x(low) <= true median <= x(high)), exact
};

// The largest low whose coverage is at least `level`, else low = 1 (the range) with its smaller
// coverage (0 for n = 1, 0.5 for n = 2, ...).
MedianRanks median_ranks(size_t n, double level = 0.95);

struct MedianInterval {
  double median = 0.0, low = 0.0, high = 0.0;
  double coverage = 0.0;  // as MedianRanks::coverage
};

// The sample's median (the mean of the middle two for even n) and the interval of median_ranks.
// An empty sample gives all zeros.
MedianInterval median_interval(std::vector<double> samples, double level = 0.95);

}  // namespace dacrt
