#include "io/film_exr.h"

#include "util/error.h"

namespace dacrt {

std::vector<WordChannel> film_words(const Film& film) {
  // The channels only point into the film; reading into them is read_film_words' business.
  Film& f = const_cast<Film&>(film);
  std::vector<WordChannel> out;
  for (const Film::FixedArray& a : f.fixed_arrays())
    for (int c = 0; c < a.per_pixel; ++c)
      for (int w = 0; w < 4; ++w)
        out.push_back({"exact." + std::string(a.name) + "." + std::to_string(c) + ".w" +
                           std::to_string(w),
                       reinterpret_cast<char*>(a.values->data() + c) + 4 * w,
                       sizeof(Fixed) * size_t(a.per_pixel)});
  for (const Film::CountArray& a : f.count_arrays())
    out.push_back({"exact." + std::string(a.name), reinterpret_cast<char*>(a.values->data()),
                   sizeof(uint32_t)});
  return out;
}

void write_film_exr(const std::string& path, const Film& film, ExrMetadata metadata, bool exact) {
  metadata.extra.push_back({"samplesDropped", std::to_string(film.dropped())});
  metadata.extra.push_back({"samplesClamped", std::to_string(film.clamped())});
  if (exact) metadata.extra.push_back({"exactSums", exact_sums_format});
  write_exr(path, film.width(), film.height(), film.channels(film.min_count() != film.max_count()),
            metadata, exact ? film_words(film) : std::vector<WordChannel>{});
}

void read_film_words(const std::string& path, Film& film, uint32_t most) {
  read_exr_words(path, film.width(), film.height(), film_words(film));
  const std::string bad = film.check_sums(most);
  if (!bad.empty()) throw Error(path + ": " + bad);
}

}  // namespace dacrt
