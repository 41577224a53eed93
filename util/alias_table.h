// AliasTable: a discrete distribution sampled in O(1) from one uniform float (Walker's alias
// method, with Vose's construction, "A Linear Algorithm for Generating Random Numbers with a Given
// Distribution", 1991), whose pmf() is exactly the probability sample() realises.
//
// The path's numbers are floats in [0, 1) with 24 random bits (util/random.h), so sample() can
// realise only multiples of 2⁻²⁴. The table therefore first rounds each weight to a whole number of
// those units (largest remainder, at least one unit for any positive weight, so a tiny emitter
// stays selectable with a known probability; zero weights get none), summing to exactly 2²⁴. It has
// B = 2^b buckets (the entry count rounded up to a power of two; the padding buckets have weight 0)
// and the 24 bits of u = k / 2²⁴ are split: the top b bits of k pick the bucket, the low 24 − b
// bits are the threshold t, compared with the bucket's own share (in units); t below it keeps the
// bucket's entry, otherwise its alias. Everything is integer, so pmf(i) = units(i) × 2⁻²⁴ exactly,
// and at most 2²⁴ entries can be held (more throws).
#pragma once

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

#include "dacrt/util/error.h"

namespace dacrt {

class AliasTable {
 public:
  static constexpr int kBits = 24;  // of the uniform sample() takes
  static constexpr uint32_t kUnits = 1u << kBits;

  AliasTable() = default;
  // Weights ≥ 0 and finite; all zero (or none) gives an empty table.
  explicit AliasTable(const std::vector<double>& weights) {
    const size_t n = weights.size();
    double total = 0.0;
    size_t positive = 0;
    for (double w : weights)
      if (w > 0.0) total += w, ++positive;
    if (!(total > 0.0)) return;
    if (positive > kUnits) throw Error("an alias table holds at most 2^24 entries with weight");
    units_.assign(n, 0);
    std::vector<double> remainder(n, 0.0);
    int64_t sum = 0;
    for (size_t i = 0; i < n; ++i) {
      if (!(weights[i] > 0.0)) continue;
      const double ideal = weights[i] / total * kUnits;
      units_[i] = std::max<uint32_t>(1, uint32_t(ideal));
      remainder[i] = ideal - units_[i];
      sum += units_[i];
    }
    // Largest remainder: give the missing units to (or take the excess from) the entries whose
    // rounding was furthest from their ideal; deterministic (ties by index).
    std::vector<uint32_t> order(n);
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(),
                     [&](uint32_t a, uint32_t b) { return remainder[a] > remainder[b]; });
    for (size_t k = 0; sum < kUnits; k = (k + 1) % n)
      if (units_[order[k]] > 0) ++units_[order[k]], ++sum;
    for (size_t k = n - 1; sum > kUnits; k = (k + n - 1) % n)
      if (units_[order[k]] > 1) --units_[order[k]], --sum;

    bits_ = 0;
    while ((size_t(1) << bits_) < n) ++bits_;
    const uint32_t capacity = kUnits >> bits_;  // units per bucket
    const size_t buckets = size_t(1) << bits_;
    threshold_.assign(buckets, capacity);
    alias_.resize(buckets);
    std::iota(alias_.begin(), alias_.end(), 0u);
    std::vector<uint32_t> left(buckets, 0), small, large;
    for (size_t i = 0; i < n; ++i) left[i] = units_[i];
    for (uint32_t i = 0; i < buckets; ++i) (left[i] < capacity ? small : large).push_back(i);
    while (!small.empty() && !large.empty()) {
      const uint32_t s = small.back(), l = large.back();
      small.pop_back();
      threshold_[s] = left[s];
      alias_[s] = l;
      left[l] -= capacity - left[s];
      if (left[l] < capacity) large.pop_back(), small.push_back(l);
    }
    // Integer arithmetic leaves nothing over: what remains holds exactly `capacity`.
  }

  bool empty() const { return units_.empty(); }
  size_t size() const { return units_.size(); }
  // The probability of entry i, exactly as sample() realises it for u = k / 2²⁴.
  double pmf(size_t i) const { return double(units_[i]) * (1.0 / kUnits); }
  // The same, in units of 2⁻²⁴.
  uint32_t units(size_t i) const { return units_[i]; }

  // The entry for u in [0, 1); its 24 high bits are used (a 24-bit float loses none).
  uint32_t sample(float u) const {
    const uint32_t k = std::min(kUnits - 1, uint32_t(std::max(0.f, u) * float(kUnits)));
    return sample_units(k);
  }
  // The entry for k in [0, 2²⁴): the top bits pick the bucket, the low ones are the threshold.
  uint32_t sample_units(uint32_t k) const {
    const uint32_t bucket = k >> (kBits - bits_), t = k & ((kUnits >> bits_) - 1);
    return t < threshold_[bucket] ? bucket : alias_[bucket];
  }

 private:
  int bits_ = 0;
  std::vector<uint32_t> units_;      // per entry, summing to 2²⁴
  std::vector<uint32_t> threshold_;  // per bucket, in units
  std::vector<uint32_t> alias_;      // per bucket
};

}  // namespace dacrt
