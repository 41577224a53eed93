// The probabilities light sampling claims are the ones it realises: the alias table
// (util/alias_table.h) enumerated over all 2²⁴ inputs, the environment map's pdf against its
// sampling (χ²), and the power heuristic at infinite, huge and zero pdfs.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include "chi2.h"
#include "dacrt/materials/sampling.h"
#include "dacrt/scene/environment.h"
#include "dacrt/util/alias_table.h"
#include "dacrt/util/random.h"

using namespace dacrt;

namespace {

// How often each entry comes out over every input the table can see (all 2²⁴ of them).
std::vector<uint32_t> realised_counts(const AliasTable& table) {
  std::vector<uint32_t> count(table.size(), 0);
  for (uint32_t k = 0; k < AliasTable::kUnits; ++k) ++count[table.sample_units(k)];
  return count;
}

}  // namespace

TEST_CASE("light pmf: a million equal emitters and one of 1e-9 of the power, exactly") {
  constexpr size_t n = 1000000;
  std::vector<double> power(n, 1.0);
  power.push_back(1e-9 * double(n) / (1.0 - 1e-9));  // 1e-9 of the total, itself included
  power.push_back(0.0);                              // black: never picked
  const AliasTable table(power);
  const std::vector<uint32_t> count = realised_counts(table);
  CHECK(count[n] > 0);  // the tiny emitter is selectable
  CHECK(table.pmf(n) > 0.0);
  CHECK(count[n + 1] == 0);
  CHECK(table.pmf(n + 1) == 0.0);
  size_t wrong = 0;
  for (size_t i = 0; i < table.size(); ++i)
    if (table.pmf(i) != double(count[i]) / AliasTable::kUnits) ++wrong;
  CHECK(wrong == 0);
  // The floats sample() takes reach the same entries as their 24 bits.
  CHECK(table.sample(0x1p-24f * float(0x123456)) == table.sample_units(0x123456));
  CHECK(table.sample(0x1.fffffep-1f) == table.sample_units(AliasTable::kUnits - 1));
  // The rounding to 2⁻²⁴ stays within one unit of the powers.
  const double total = double(n) / (1.0 - 1e-9);
  CHECK(std::abs(table.pmf(0) - 1.0 / total) <= 0x1p-24);
}

TEST_CASE("light pmf: sums to 1") {
  Pcg32 rng(3);
  for (size_t n : {1u, 2u, 3u, 7u, 1000u, 65537u}) {
    std::vector<double> w(n);
    for (double& x : w) x = std::pow(10.0, 12.0 * rng.uniform() - 6.0);
    const AliasTable table(w);
    double sum = 0.0;
    for (size_t i = 0; i < n; ++i) sum += table.pmf(i);
    CHECK(std::abs(sum - 1.0) <= 1e-12);
    if (n <= 1000) {
      const std::vector<uint32_t> count = realised_counts(table);
      for (size_t i = 0; i < n; ++i) CHECK(table.pmf(i) == double(count[i]) / AliasTable::kUnits);
    }
  }
  CHECK(AliasTable(std::vector<double>(5, 0.0)).empty());
}

TEST_CASE("light pmf: an environment map with one bright texel samples its pdf (χ²)") {
  Image image(16, 8);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      float* p = image.pixel(x, y);
      // The poles black: the χ² grid cannot integrate the pdf's 1/sin θ there.
      const float v = (y == 0 || y == image.height - 1) ? 0.f : 1.f;
      p[0] = p[1] = p[2] = v;
    }
  float* sun = image.pixel(5, 3);
  sun[0] = sun[1] = sun[2] =
      30.f;  // a fifth of the power: more and the χ² grid cannot integrate its edges
  const EnvironmentMap map(image, "test");
  const double p = dacrt::test::chi2_p_value(
      [&](Pcg32& rng) -> std::optional<glm::vec3> {
        const float a = rng.uniform(), b = rng.uniform(), c = rng.uniform();
        const auto s = map.sample({a, b, c, rng.uniform()});
        if (!(s.pdf > 0.f)) return std::nullopt;
        return s.direction;
      },
      [&](const glm::vec3& d) { return map.pdf(d); }, 11, 500000, /*sub=*/128);
  CHECK(p > 0.01);
}

TEST_CASE("light pmf: the power heuristic at infinite, huge and zero pdfs") {
  const float inf = std::numeric_limits<float>::infinity(), huge = 1e30f;
  const auto weight = [](float a, float b) {
    const float w = power_heuristic(a, b);
    CHECK(std::isfinite(w));
    CHECK(w >= 0.f);
    CHECK(w <= 1.f);
    return w;
  };
  CHECK(weight(1.f, inf) == 0.f);  // the limit b → ∞
  CHECK(weight(inf, 1.f) == 1.f);  // a → ∞
  CHECK(weight(0.f, 0.f) == 0.f);
  CHECK(weight(huge, huge) == doctest::Approx(0.5));
  CHECK(weight(huge, 2.f * huge) == doctest::Approx(0.2));
  CHECK(weight(3e38f, 1.5e38f) == doctest::Approx(0.8));
  CHECK(weight(inf, inf) == 0.5f);
  CHECK(weight(1e-30f, 0.f) == 1.f);
  // The two strategies' weights still add up to 1.
  for (auto [a, b] : {std::pair{huge, 3.f * huge}, {1.f, inf}, {2.f, 5.f}})
    CHECK(weight(a, b) + weight(b, a) == doctest::Approx(1.0));
}
