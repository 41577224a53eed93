// The film's fixed-point sums (film/fixed.h): each value is rounded once, on its own, so sums
// are the same in any order; values beyond the limit are clamped and counted, never silently.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "dacrt/film/film.h"
#include "dacrt/film/fixed.h"
#include "dacrt/util/error.h"

using namespace dacrt;

TEST_CASE("fixed point: values convert toward zero to the step, whole and fraction apart") {
  CHECK(to_fixed<value_bits>(1.0) == Fixed(1) << 64);
  CHECK(to_fixed<value_bits>(-1.0) == -(Fixed(1) << 64));
  CHECK(to_fixed<value_bits>(0.75) == Fixed(3) << 62);
  CHECK(to_fixed<value_bits>(-0.75) == -(Fixed(3) << 62));
  CHECK(to_fixed<value_bits>(0x1p-64) == 1);
  CHECK(to_fixed<value_bits>(0x1p-66) == 0);   // below the step: toward zero
  CHECK(to_fixed<value_bits>(-0x1p-66) == 0);
  CHECK(to_fixed<value_bits>(-(1 + 0x1p-50)) == -((Fixed(1) << 64) + (Fixed(1) << 14)));
  CHECK(to_fixed<value_bits>(0x1p-30 + 0x1p-66) == Fixed(1) << 34);  // the fraction's bits cut
  CHECK(to_fixed<square_bits>(0x1p60 - 0x1p8) == (Fixed(1) << 106) - (Fixed(1) << 54));
  CHECK(to_fixed<square_bits>(0x1p60) == Fixed(1) << 106);
  CHECK(to_fixed<value_bits>(-value_limit) == -(Fixed(1) << 94));
  // Every float in the range converts exactly when it is a multiple of the step, and back.
  std::mt19937 rng(3);
  for (int i = 0; i < 10000; ++i) {
    const int shift = int(rng() % 48) - 40;
    const float v = std::ldexp(float(rng() % (1u << 24)) - float(1 << 23), shift);
    CAPTURE(v);
    REQUIRE(from_fixed<value_bits>(to_fixed<value_bits>(v)) == double(v));
    if (shift >= -square_bits / 2)  // the square's lowest bit is a step or more
      REQUIRE(from_fixed<square_bits>(to_fixed<square_bits>(double(v) * v)) == double(v) * v);
  }
}

TEST_CASE("film: sums are the same bit for bit in any order, values past the limit are clamped") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-2.f, 8.f);
  std::vector<glm::vec3> samples;
  for (int i = 0; i < 500; ++i)
    samples.push_back(glm::vec3(std::exp2(u(rng) * 3), u(rng) * 1e-6f, u(rng)));
  Film forward(1, 1), backward(1, 1), shuffled(1, 1);
  for (const glm::vec3& s : samples) forward.add(0, s);
  for (size_t i = samples.size(); i-- > 0;) backward.add(0, samples[i]);
  std::shuffle(samples.begin(), samples.end(), rng);
  for (const glm::vec3& s : samples) shuffled.add(0, s);
  for (int c = 0; c < 3; ++c) {
    CHECK(forward.variance_of_mean(0, c) == backward.variance_of_mean(0, c));
    CHECK(forward.variance_of_mean(0, c) == shuffled.variance_of_mean(0, c));
  }
  CHECK(forward.resolve().rgb == backward.resolve().rgb);
  CHECK(forward.resolve().rgb == shuffled.resolve().rgb);
  CHECK(forward.mean_and_error(0) == shuffled.mean_and_error(0));
  CHECK(forward.clamped() == 0);

  Film bright(2, 1);
  bright.add(0, glm::vec3(1e12f, 1.f, 1.f));
  bright.add(0, glm::vec3(1.f, -1e10f, 1.f));
  bright.add(1, glm::vec3(float(value_limit), 1.f, 1.f));  // at the limit: kept as it is
  bright.add(1, glm::vec3(NAN, 1.f, 1.f));
  CHECK(bright.clamped() == 2);
  CHECK(bright.dropped() == 1);
  const Image img = bright.resolve();
  CHECK(img.rgb[0] == doctest::Approx((value_limit + 1) / 2));
  CHECK(img.rgb[1] == doctest::Approx((1 - value_limit) / 2));
  CHECK(img.rgb[3] == float(value_limit));
  Film other(2, 1);
  other.add(0, glm::vec3(2e9f, 0.f, 0.f));
  bright.merge(other);
  CHECK(bright.clamped() == 3);
}

TEST_CASE("film: check_sums refuses counts and sums no samples can make (films read from files)") {
  Film film(3, 2, AovSet().add(Aov::albedo));
  film.add(4, glm::vec3(1.f), nullptr);
  film.add(4, glm::vec3(2.f), nullptr);
  CHECK(film.check_sums(0, 2) == "");
  CHECK(film.check_sums(0, 1).find("pixel (1, 1) took 2 samples") != std::string::npos);
  // Exactly n samples a pixel (a merge's parts): pixel (0, 0) took none.
  CHECK(film.check_sums(2, 2).find("pixel (0, 0) took 0 samples and kept 0 (2 were to be taken)") !=
        std::string::npos);
  // The film with sum k of a pixel set (its sums: colour 0-2, squares 3-5, mean square 6, first
  // hits 7-16).
  auto forged = [&](size_t pixel, size_t k, Fixed value) {
    Film f = film;
    REQUIRE(f.sums_per_pixel() == 17);
    REQUIRE(f.set_sum(pixel, int(k), value));
    return f.check_sums(0, 8);
  };
  const Fixed one = Fixed(1) << 64;
  CHECK(forged(4, 0, 2 * (one << 30)) == "");  // two samples at the limit
  CHECK(forged(4, 0, 2 * (one << 30) + 1).find("pixel (1, 1) has sums") != std::string::npos);
  CHECK(forged(0, 0, 1).find("pixel (0, 0) has sums") != std::string::npos);  // no samples
  CHECK(forged(4, 4, -1).find("pixel (1, 1)") != std::string::npos);
  CHECK(forged(4, 6, -1).find("pixel (1, 1)") != std::string::npos);
  CHECK(forged(4, 13, 2 * (one << 30)) == "");
  CHECK(forged(4, 13, 3 * (one << 30)).find("pixel (1, 1)") != std::string::npos);
  // Albedo and normal: two samples of at most 2^10 each.
  CHECK(forged(4, 7, 2 * (one << 10)) == "");
  CHECK(forged(4, 12, -2 * (one << 10)) == "");
  CHECK(forged(4, 7, 2 * (one << 10) + 1).find("pixel (1, 1) has sums") != std::string::npos);
  CHECK(forged(4, 12, -2 * (one << 10) - 1).find("pixel (1, 1) has sums") != std::string::npos);
  Film more = film;
  const uint32_t kept_one[3] = {1, 0, 0};  // kept one of none taken
  REQUIRE(more.set_counts(2, kept_one));
  CHECK(more.check_sums(0, 8).find("pixel (2, 0) took 0 samples and kept 1") != std::string::npos);
}

TEST_CASE("film: albedo and normal sums in 96 bits carry, borrow and clamp as 128-bit sums would") {
  // Pixel 0 takes values of both signs around whole numbers (each 0.75 + 0.75 carries into the
  // sum's upper word, a negative one borrows from it), pixel 1 negative ones only, both past the
  // ±2^10 limit now and then.
  Film film(2, 1, AovSet::parse("albedo,normal"));
  Fixed expected[2][6] = {};
  uint64_t clamped = 0;
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-1.5f, 1.5f);
  const float special[] = {0.75f, 0.75f, 1.f, -1.f, -0.75f, 1024.f, -1024.f, 5000.f, -3000.f,
                           1e-30f, -0x1p-64f, 0.999999f};
  for (int s = 0; s < 400; ++s)
    for (size_t p = 0; p < 2; ++p) {
      FirstHit first;
      bool cut = false;
      for (int c = 0; c < 6; ++c) {
        float v = s < 12 ? special[(s + c) % 12] : u(rng) * (s % 50 == 0 ? 2000.f : 1.f);
        if (p == 1) v = -std::abs(v);
        (c < 3 ? first.albedo[c] : first.normal[c - 3]) = v;
        const double kept = std::clamp(double(v), -bounded_limit, bounded_limit);
        cut |= kept != double(v);
        expected[p][c] += to_fixed<value_bits>(kept);
      }
      first.hit = s % 3 != 0;
      clamped += cut;
      film.add(p, glm::vec3(1.f), &first);
    }
  REQUIRE(clamped > 2);
  CHECK(film.clamped() == clamped);
  for (size_t p = 0; p < 2; ++p)
    for (int c = 0; c < 6; ++c) {
      CAPTURE(p);
      CAPTURE(c);
      CHECK(film.sum(p, 7 + c) == expected[p][c]);
    }
  // Pixel 1's sums went below -2^64, so their upper words were borrowed from.
  CHECK(expected[1][0] < -(Fixed(1) << 64));

  // A 96-bit sum holds [-2^95, 2^95): the ends set and read back, past them nothing is set.
  const Fixed top = (Fixed(1) << 95) - 1, bottom = -(Fixed(1) << 95);
  Film ends(1, 1, AovSet::parse("normal"));
  CHECK(ends.set_sum(0, 7, top));
  CHECK(ends.set_sum(0, 8, bottom));
  CHECK_FALSE(ends.set_sum(0, 9, top + 1));
  CHECK_FALSE(ends.set_sum(0, 10, bottom - 1));
  CHECK(ends.sum(0, 7) == top);
  CHECK(ends.sum(0, 8) == bottom);
  CHECK(ends.sum(0, 9) == 0);
  CHECK(ends.sum(0, 10) == 0);
  CHECK(ends.set_sum(0, 13, top + 1));  // depth: 128 bits
  CHECK(ends.sum(0, 13) == top + 1);
}

TEST_CASE("film: a merge adds 96-bit sums across their words, and refuses sums that would wrap") {
  const Fixed top = (Fixed(1) << 95) - 1;
  Film a(2, 1, AovSet::parse("albedo")), b(2, 1, AovSet::parse("albedo"));
  REQUIRE(a.set_sum(0, 7, (Fixed(1) << 64) - 1));
  REQUIRE(b.set_sum(0, 7, 1));  // carries into the upper word
  REQUIRE(a.set_sum(0, 8, -(Fixed(1) << 64)));
  REQUIRE(b.set_sum(0, 8, -1));  // borrows from it
  REQUIRE(a.set_sum(1, 12, top - 1));
  REQUIRE(b.set_sum(1, 12, 1));  // just fits
  a.merge(b);
  CHECK(a.sum(0, 7) == Fixed(1) << 64);
  CHECK(a.sum(0, 8) == -(Fixed(1) << 64) - 1);
  CHECK(a.sum(1, 12) == top);
  Film over = a;
  CHECK_THROWS_WITH_AS(over.merge(b), doctest::Contains("pixel (1, 0)"), Error);
  Film under(2, 1, AovSet::parse("albedo"));
  REQUIRE(under.set_sum(0, 9, -(Fixed(1) << 95)));
  REQUIRE(b.set_sum(0, 9, -1));
  CHECK_THROWS_WITH_AS(under.merge(b), doctest::Contains("pixel (0, 0)"), Error);
}

TEST_CASE("film: a pixel's counts share a word, and stop at count_limit samples") {
  // Each count a field of its own: dropped samples count as taken only, hits only with first
  // hits, and none carries into the next.
  Film film(3, 1, AovSet::parse("depth"));
  FirstHit hit, miss;
  hit.hit = true;
  for (int i = 0; i < 5; ++i) film.add(1, glm::vec3(1.f), i % 2 ? &hit : &miss);
  film.add(1, glm::vec3(NAN, 0.f, 0.f), &hit);
  CHECK(film.count(1) == 5);
  CHECK(film.taken(1) == 6);
  CHECK(film.hits(1) == 2);
  CHECK(film.counts_per_pixel() == 3);
  CHECK(Film(3, 1).counts_per_pixel() == 2);
  // A pixel one sample short of the limit takes one more, then refuses the next, with its
  // counts and sums as they were; the others still take theirs (add_in_order adds them all).
  const uint32_t almost[3] = {Film::count_limit - 1, Film::count_limit - 1, 0};
  REQUIRE(film.set_counts(2, almost));
  film.add(2, glm::vec3(1.f), &hit);
  CHECK(film.taken(2) == Film::count_limit);
  CHECK(film.hits(2) == 1);
  const Fixed red = film.sum(2, 0);
  CHECK_THROWS_WITH_AS(film.add(2, glm::vec3(1.f), &hit),
                       doctest::Contains("pixel (2, 0) took more than 2097151 samples"), Error);
  const size_t pixels[3] = {0, 2, 1};
  CHECK_THROWS_WITH_AS(
      film.add_in_order(
          3, [&](size_t i) { return pixels[i]; }, [](size_t) { return glm::vec3(1.f); },
          [&](size_t) { return &hit; }),
      doctest::Contains("pixel (2, 0)"), Error);
  CHECK(film.taken(2) == Film::count_limit);
  CHECK(film.count(2) == Film::count_limit);
  CHECK(film.hits(2) == 1);
  CHECK(film.sum(2, 0) == red);
  CHECK(film.count(0) == 1);
  CHECK(film.count(1) == 6);
}

TEST_CASE("film: counts past count_limit are refused when set, merged or read") {
  Film a(2, 1), b(2, 1);
  const uint32_t over[2] = {0, Film::count_limit + 1};
  const uint32_t most[2] = {Film::count_limit, Film::count_limit};
  CHECK_FALSE(a.set_counts(0, over));
  CHECK(a.taken(0) == 0);
  REQUIRE(a.set_counts(1, most));
  a.add(0, glm::vec3(2.f));
  b.add(0, glm::vec3(3.f));
  b.add(1, glm::vec3(3.f));
  // Pixel 1 would count one more than the limit: nothing is added, not even pixel 0's.
  const std::vector<Fixed> sums = a.sums();
  CHECK_THROWS_WITH_AS(a.merge(b), doctest::Contains("pixel (1, 0) would count more than"),
                       Error);
  CHECK(a.sums() == sums);
  CHECK(a.count(0) == 1);
  CHECK(a.taken(1) == Film::count_limit);
  // Below the limit the counts add field by field.
  Film c(2, 1);
  c.add(0, glm::vec3(1.f));
  c.add(0, glm::vec3(INFINITY));
  c.merge(b);
  CHECK(c.count(0) == 2);
  CHECK(c.taken(0) == 3);
  CHECK(c.count(1) == 1);
}

TEST_CASE("film: the fewest, most and all samples follow adds, merges and counts set") {
  Film film(2, 2);
  CHECK(film.min_count() == 0);
  CHECK(film.max_count() == 0);
  film.add(3, glm::vec3(1.f));
  CHECK(film.max_count() == 1);
  CHECK(film.total_count() == 1);
  const size_t pixels[4] = {0, 1, 2, 3};
  film.add_in_order(
      4, [&](size_t i) { return pixels[i]; }, [](size_t) { return glm::vec3(1.f); },
      [](size_t) { return static_cast<const FirstHit*>(nullptr); });
  CHECK(film.min_count() == 1);
  CHECK(film.max_count() == 2);
  CHECK(film.total_count() == 5);
  Film more(2, 2);
  more.add(0, glm::vec3(1.f));
  film.merge(more);
  CHECK(film.total_count() == 6);
  const uint32_t seven[2] = {7, 7};
  REQUIRE(film.set_counts(1, seven));
  CHECK(film.max_count() == 7);
  CHECK(film.total_count() == 12);
}
