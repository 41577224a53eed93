#include "dacrt/io/film_exr.h"

#include <charconv>
#include <cstring>
#include <system_error>

#include "dacrt/util/error.h"

namespace dacrt {

namespace {

// How many of a pixel's sums are bounded (kept in 96 bits).
int bounded_count(const Film& film) {
  int n = 0;
  for (int c = 0; c < film.sums_per_pixel(); ++c) n += Film::bounded(c);
  return n;
}

}  // namespace

std::vector<WordChannel> film_words(const Film& film, std::vector<uint32_t>* high,
                                   std::vector<uint32_t>* counts) {
  // The channels only point into the film; reading into them is read_film_state's business.
  Film& f = const_cast<Film&>(film);
  std::vector<WordChannel> out;
  const int n = f.sums_per_pixel();
  const int bounded_sums = bounded_count(film);
  int bounded = 0;  // the bounded sums before sum c
  for (int c = 0; c < n; ++c) {
    const Film::SumPlace place = f.sum_place(c);
    for (int w = 0; w < 4; ++w) {
      WordChannel word{"exact.sums." + std::to_string(c) + ".w" + std::to_string(w),
                       place.base + 4 * w, place.stride};
      if (w >= place.words)
        word.base = high ? reinterpret_cast<char*>(high->data() + bounded) : nullptr,
        word.stride = sizeof(uint32_t) * bounded_sums;
      out.push_back(word);
    }
    bounded += place.words < 4;
  }
  // The counts, which the film keeps in one word a pixel, into `counts` (made here).
  const int per_pixel = film.counts_per_pixel();
  if (counts) {
    counts->resize(size_t(per_pixel) * film.pixels());
    for (size_t p = 0; p < film.pixels(); ++p)
      for (int i = 0; i < per_pixel; ++i)
        (*counts)[size_t(per_pixel) * p + i] = film.count_value(p, i);
  }
  for (int i = 0; i < per_pixel; ++i)
    out.push_back({"exact." + std::string(Film::count_name(i)),
                   counts ? reinterpret_cast<char*>(counts->data() + i) : nullptr,
                   sizeof(uint32_t) * per_pixel});
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
  // A band of rows at a time: the float channels of a whole film of every AOV would hold
  // 68 bytes a pixel beside the film's sums.
  film.release_scratch();  // the sorted samples of the last pass, no longer needed
  const bool counts = film.min_count() != film.max_count();
  const std::vector<WordChannel> words = exact ? film_words(film) : std::vector<WordChannel>{};
  ExrRows rows{film.channel_names(counts), {}, {}};
  for (const WordChannel& w : words) rows.words.push_back(w.name);
  const size_t width = size_t(film.width()), sums = size_t(film.sums_per_pixel());
  rows.fill = [&](int y0, int y1, const std::vector<float*>& floats,
                  const std::vector<uint32_t*>& out) {
    const size_t first = size_t(y0) * width, n = size_t(y1 - y0) * width;
    film.channel_values(counts, first, n, floats);
    if (!exact) return;
    // Each sum's four words, from its 96 or 128 bits (sign-extended).
    __extension__ using Word = unsigned __int128;
    Fixed pixel[32];
    for (size_t k = 0; k < n; ++k) {
      film.pixel_sums(first + k, pixel);
      for (size_t c = 0; c < sums; ++c)
        for (size_t w = 0; w < 4; ++w) out[4 * c + w][k] = uint32_t(Word(pixel[c]) >> (32 * w));
    }
    for (size_t c = 4 * sums; c < words.size(); ++c)
      for (size_t k = 0; k < n; ++k) out[c][k] = film.count_value(first + k, int(c - 4 * sums));
  };
  write_exr(path, film.width(), film.height(), rows, metadata);
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
  // The bounded sums' fourth words go beside the film, and must be the sign of the 96 bits
  // it keeps (as this version writes them), else the sum is more than samples can add up to.
  std::vector<uint32_t> high(size_t(bounded_count(film)) * film.pixels()), counts;
  read_exr_words(path, film.width(), film.height(), film_words(film, &high, &counts));
  // The counts into the film, each at most what it can count (check_sums then checks them
  // against the samples the file was to hold).
  const int per_pixel = film.counts_per_pixel();
  for (size_t p = 0; p < film.pixels(); ++p)
    if (!film.set_counts(p, &counts[size_t(per_pixel) * p]))
      throw Error(path + ": pixel (" + std::to_string(p % size_t(film.width())) + ", " +
                  std::to_string(p / size_t(film.width())) + ") counts more than " +
                  std::to_string(Film::count_limit) + " samples");
  for (size_t p = 0, j = 0; j < high.size(); ++p)
    for (int c = 0; c < film.sums_per_pixel(); ++c)
      if (Film::bounded(c)) {
        __extension__ using Word = unsigned __int128;
        if (uint32_t(Word(film.sum(p, c)) >> 96) != high[j++])
          throw Error(path + ": pixel (" + std::to_string(p % size_t(film.width())) + ", " +
                      std::to_string(p / size_t(film.width())) +
                      ") has sums its " + std::to_string(film.count(p)) +
                      " samples cannot add up to");
      }
  // The tallies as decimal counts, nothing else (strtoull would take "-1" for 2^64 - 1, "5x" for
  // 5, and wrap where parts are added).
  auto tally = [&](const char* name) {
    const auto it = header.attributes.find(name);
    if (it == header.attributes.end()) throw Error(path + ": its " + name + " attribute is missing");
    const std::string& text = it->second;
    uint64_t value = 0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || error != std::errc() || end != text.data() + text.size())
      throw Error(path + ": its " + name + " attribute \"" + one_line(text.substr(0, 40)) +
                  "\" is not a count");
    return value;
  };
  const uint64_t dropped = tally("samplesDropped"), clamped = tally("samplesClamped");
  const std::string bad = film.check_sums(least, most);
  if (!bad.empty()) throw Error(path + ": " + bad);
  // Every sample a pixel took and did not keep was dropped; every clamped one was kept. So the
  // tallies are bounded by the counts, and adding parts cannot wrap them.
  const uint64_t kept = film.total_count();
  uint64_t taken = 0;
  for (size_t p = 0; p < film.pixels(); ++p) taken += film.taken(p);
  if (dropped != taken - kept)
    throw Error(path + ": its samplesDropped " + std::to_string(dropped) + " is not the " +
                std::to_string(taken - kept) + " samples its pixels took and did not keep");
  if (clamped > kept)
    throw Error(path + ": its samplesClamped " + std::to_string(clamped) + " is more than the " +
                std::to_string(kept) + " samples its pixels kept");
  film.set_tallies(dropped, clamped);
}

}  // namespace dacrt
