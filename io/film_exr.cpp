#include "dacrt/io/film_exr.h"

#include <cstdlib>

#include "dacrt/util/error.h"

namespace dacrt {

std::vector<WordChannel> film_words(const Film& film) {
  // The channels only point into the film; reading into them is read_film_words' business.
  Film& f = const_cast<Film&>(film);
  std::vector<WordChannel> out;
  const int n = f.sums_per_pixel();
  for (int c = 0; c < n; ++c)
    for (int w = 0; w < 4; ++w)
      out.push_back({"exact.sums." + std::to_string(c) + ".w" + std::to_string(w),
                     reinterpret_cast<char*>(f.sums().data() + c) + 4 * w, sizeof(Fixed) * size_t(n)});
  for (const Film::CountArray& a : f.count_arrays())
    out.push_back({"exact." + std::string(a.name), reinterpret_cast<char*>(a.values->data()),
                   sizeof(uint32_t)});
  return out;
}

std::string samples_per_pixel_text(uint32_t least, uint32_t most) {
  return least == most ? "every pixel " + std::to_string(least)
                       : "from " + std::to_string(least) + " to " + std::to_string(most) +
                             " (the " + Film::samples_channel + " channel)";
}

void write_film_exr(const std::string& path, const Film& film, ExrMetadata metadata, bool exact) {
  metadata.extra.push_back({"samplesDropped", std::to_string(film.dropped())});
  metadata.extra.push_back({"samplesClamped", std::to_string(film.clamped())});
  if (exact) metadata.extra.push_back({"exactSums", exact_sums_format});
  write_exr(path, film.width(), film.height(), film.channels(film.min_count() != film.max_count()),
            metadata, exact ? film_words(film) : std::vector<WordChannel>{});
}

ExrHeader read_sums_header(const std::string& path, const std::string& purpose) {
  ExrHeader header = read_exr_header(path);
  const auto format = header.attributes.find("exactSums");
  if (format == header.attributes.end())
    throw Error(path + " holds no exact sums " + purpose +
                " (a render keeps them with --samples, --keep-sums, or when it is cut short)");
  if (format->second != exact_sums_format)
    throw Error(path + ": its exact sums are of another format (" + format->second + ")");
  return header;
}

void read_film_state(const std::string& path, const ExrHeader& header, Film& film, uint32_t least,
                     uint32_t most) {
  read_exr_words(path, film.width(), film.height(), film_words(film));
  auto tally = [&](const char* name) {
    const auto it = header.attributes.find(name);
    return it == header.attributes.end() ? uint64_t(0)
                                         : uint64_t(std::strtoull(it->second.c_str(), nullptr, 10));
  };
  film.set_tallies(tally("samplesDropped"), tally("samplesClamped"));
  const std::string bad = film.check_sums(least, most);
  if (!bad.empty()) throw Error(path + ": " + bad);
}

}  // namespace dacrt
