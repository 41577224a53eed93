// A film written as renders write it (io/film_exr.h): the channels are made and written a band
// of rows at a time, so a film taller than one band must come back as channels() makes it, and
// its exact state must read back into a film with the same sums bit for bit.
#include <doctest/doctest.h>

#include <cstdint>
#include <vector>

#include "dacrt/film/film.h"
#include "dacrt/io/film_exr.h"
#include "dacrt/util/error.h"
#include "temp_dir.h"

using namespace dacrt;

TEST_CASE("film exr: a film of several bands of rows reads back channel for channel, sum for sum") {
  // 150 rows: two whole bands of 64 and a last one of 22.
  const int width = 5, height = 150;
  const AovSet aovs = AovSet::parse("albedo,normal,depth,position,variance,samples");
  Film film(width, height, aovs);
  // Every pixel its own values, and pixels with different counts (so the samples channel is
  // written too).
  for (size_t p = 0; p < film.pixels(); ++p)
    for (size_t s = 0; s < 1 + p % 3; ++s) {
      const float v = float(p) * 0.37f + float(s);
      FirstHit first;
      // Albedo and normal sums of both signs, some near their 2^10 limit (kept in 96 bits, written
      // in four words).
      first.albedo = glm::vec3(v * 0.001f, 0.5f, p % 5 == 0 ? 1000.f : 0.25f);
      first.normal = glm::vec3(-0.6f, p % 2 ? 0.8f : -0.8f, -v);
      first.position = glm::vec3(v, -v, 2.f * v);
      first.depth = v + 1.f;
      first.hit = p % 7 != 0;
      film.add(p, glm::vec3(v, 2.f * v, 0.5f), &first);
    }
  REQUIRE(film.min_count() != film.max_count());

  test::TempDir dir("film-exr");
  const std::string path = dir / "film.exr";
  write_film_exr(path, film, ExrMetadata{}, /*exact=*/true);

  const ExrFile file = read_exr_file(path);
  const std::vector<Channel> expected = film.channels(true);
  REQUIRE(expected.size() == 17);
  for (const Channel& c : expected) {
    INFO(c.name);
    const Channel* read = file.find(c.name);
    REQUIRE(read);
    CHECK(read->values == c.values);
  }

  Film back(width, height, aovs);
  read_film_state(path, read_sums_header(path, "to read back"), back, 1, 3);
  CHECK(back.sums() == film.sums());
  for (size_t p = 0; p < film.pixels(); ++p) {
    INFO(p);
    REQUIRE(back.count(p) == film.count(p));
    REQUIRE(back.taken(p) == film.taken(p));
  }
}

TEST_CASE("film exr: a 96-bit sum of the film whose fourth word is not its sign is refused") {
  const AovSet aovs = AovSet::parse("albedo,normal");
  Film film(3, 2, aovs);
  FirstHit first;
  first.albedo = glm::vec3(0.5f);
  first.normal = glm::vec3(0.f, -1.f, 0.f);
  first.hit = true;
  for (size_t p = 0; p < film.pixels(); ++p) film.add(p, glm::vec3(1.f), &first);
  ExrMetadata metadata;
  metadata.extra = {
      {"exactSums", exact_sums_format}, {"samplesDropped", "0"}, {"samplesClamped", "0"}};
  test::TempDir dir("film-exr-high");
  // The fourth words of the 6 bounded sums a pixel: the signs, then one forged (pixel (2, 1)'s
  // normal.Y, negative, whose fourth word is all ones).
  const size_t forged = 6 * 5 + 4;
  for (const uint32_t word : {0xffffffffu, 0u, 1u}) {
    CAPTURE(word);
    std::vector<uint32_t> high(6 * film.pixels());
    for (size_t p = 0; p < film.pixels(); ++p)
      for (int j = 0; j < 6; ++j) high[6 * p + j] = film.sum(p, 7 + j) < 0 ? 0xffffffffu : 0u;
    high[forged] = word;
    const std::string path = dir / "forged.exr";
    std::vector<uint32_t> counts;
    write_exr(path, film.width(), film.height(), film.channels(), metadata,
              film_words(film, &high, &counts));
    Film back(3, 2, aovs);
    if (word == 0xffffffffu) {
      read_film_state(path, read_sums_header(path, "to read"), back, 1, 1);
      CHECK(back.sums() == film.sums());
    } else {
      CHECK_THROWS_WITH_AS(read_film_state(path, read_sums_header(path, "to read"), back, 1, 1),
                           doctest::Contains("pixel (2, 1) has sums its 1 samples cannot"), Error);
    }
  }
}

TEST_CASE("film exr: counts the film cannot hold are refused, naming the pixel") {
  // The film keeps each count in 21 bits: a file's count above Film::count_limit would not fit.
  Film film(2, 2);
  for (size_t p = 0; p < film.pixels(); ++p) film.add(p, glm::vec3(1.f));
  ExrMetadata metadata;
  metadata.extra = {
      {"exactSums", exact_sums_format}, {"samplesDropped", "0"}, {"samplesClamped", "0"}};
  test::TempDir dir("film-exr-counts");
  const std::string path = dir / "counts.exr";
  for (const uint32_t taken : {1u, Film::count_limit + 1, 0xffffffffu}) {
    CAPTURE(taken);
    std::vector<uint32_t> counts;
    const std::vector<WordChannel> words = film_words(film, nullptr, &counts);
    REQUIRE(counts.size() == 2 * film.pixels());
    counts[2 * 3 + 1] = taken;  // pixel (1, 1)'s taken
    write_exr(path, film.width(), film.height(), film.channels(), metadata, words);
    Film back(2, 2);
    if (taken == 1) {
      read_film_state(path, read_sums_header(path, "to read"), back, 1, 1);
      CHECK(back.sums() == film.sums());
      CHECK(back.taken(3) == 1);
    } else {
      CHECK_THROWS_WITH_AS(read_film_state(path, read_sums_header(path, "to read"), back, 1, 1),
                           doctest::Contains("pixel (1, 1) counts more than 2097151"), Error);
    }
  }
}
