#include "dacrt/util/median_interval.h"

#include <algorithm>
#include <cmath>

namespace dacrt {

MedianRanks median_ranks(size_t n, double level) {
  if (n == 0) return {};
  // P(B = i), in log space so that 2^-n never underflows.
  const double ln_total = std::lgamma(double(n) + 1.0) - double(n) * std::log(2.0);
  auto pmf = [&](size_t i) {
    return std::exp(ln_total - std::lgamma(double(i) + 1.0) - std::lgamma(double(n - i) + 1.0));
  };
  // below = P(B <= low - 1), grown one term per step; low stays under the middle (2 low <= n).
  size_t low = 1;
  double below = pmf(0);
  while (2 * (low + 1) <= n && 1.0 - 2.0 * (below + pmf(low)) >= level) below += pmf(low++);
  const double coverage = 2 * low > n ? 0.0 : std::max(0.0, 1.0 - 2.0 * below);
  return {low, n + 1 - low, coverage};
}

MedianInterval median_interval(std::vector<double> samples, double level) {
  const size_t n = samples.size();
  if (n == 0) return {};
  std::sort(samples.begin(), samples.end());
  const MedianRanks r = median_ranks(n, level);
  const double median = n % 2 ? samples[n / 2] : 0.5 * (samples[n / 2 - 1] + samples[n / 2]);
  return {median, samples[r.low - 1], samples[r.high - 1], r.coverage};
}

}  // namespace dacrt
