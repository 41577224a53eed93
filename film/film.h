// Film: per-pixel sums of a render's samples, in named channels. The colour (radiance) is always
// kept, with its sums of squares for error and variance estimates; the first-hit values (AOVs:
// albedo, normal, depth, position) only when asked. Samples that are not finite are dropped and
// counted, never averaged in; values beyond ±value_limit (albedo and normal: ±bounded_limit) are
// clamped and counted. The sums are fixed point (film/fixed.h), exact: films of the same size and
// channels merge by adding their sums, so samples [0, a) and [a, b) rendered apart (other
// processes, other machines, a resumed render) make the film of [0, b) bit for bit.
#pragma once

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <glm/glm.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "dacrt/film/fixed.h"
#include "dacrt/util/error.h"
#include "dacrt/util/image.h"
#include "dacrt/util/large_array.h"

namespace dacrt {

// The outputs a film can hold beyond the colour (`--aov`). Depth and position average the samples
// that hit something; albedo and normal average all samples (a miss adds zero).
enum class Aov : uint8_t { albedo, normal, depth, position, variance, samples };
inline constexpr int aov_count = 6;

class AovSet {
 public:
  AovSet() = default;
  bool has(Aov a) const { return bits_ >> unsigned(a) & 1u; }
  AovSet& add(Aov a) { return bits_ |= uint8_t(1u << unsigned(a)), *this; }
  bool empty() const { return bits_ == 0; }
  // Whether the integrator must capture first-hit values for these.
  bool first_hit() const {
    return has(Aov::albedo) || has(Aov::normal) || has(Aov::depth) || has(Aov::position);
  }
  // "albedo,normal,depth": throws Error naming an unknown entry and listing the names.
  static AovSet parse(std::string_view list);
  static const char* name(Aov a);

 private:
  uint8_t bits_ = 0;
};

// What a camera sample saw first: the material's base colour (× texture × vertex colour), the
// shading normal on the side facing the camera (world space, unit), the distance along the
// camera's view axis, and the world-space point. `hit` false: the ray left the scene.
struct FirstHit {
  glm::vec3 albedo{0.f}, normal{0.f}, position{0.f};
  float depth = 0.f;
  bool hit = false;
};

class Film {
 public:
  // The per-pixel sample count's channel: a layer and a one-letter channel, as Cycles writes its
  // own sample count ("Debug Sample Count.X"); a bare "samples" is dropped by Blender's reader.
  static constexpr const char* samples_channel = "samples.X";
  // Depth (Z) where no sample hit: Cycles' value for the background (its pass accessor writes
  // 1e10 where nothing was hit), finite so that a compositor's filters and arithmetic stay
  // finite, and above the 10^4 that Blender's Normalize node ignores.
  static constexpr float background_depth = 1e10f;

  Film(int width, int height, AovSet aovs = {});

  // The bytes a film of this size with these outputs holds.
  static uint64_t bytes(int width, int height, AovSet aovs = {});

  int width() const { return width_; }
  int height() const { return height_; }
  size_t pixels() const { return size_t(width_) * size_t(height_); }
  AovSet aovs() const { return aovs_; }

  // Adds a sample. Error when the pixel already took count_limit samples.
  void add(size_t pixel, const glm::vec3& radiance, const FirstHit* first = nullptr) {
    const Added a = stride_ > at_first ? accumulate<true>(record(pixel), radiance, first)
                                       : accumulate<false>(record(pixel), radiance, first);
    if (a == Added::full) throw Error(too_many(pixel));
    dropped_ += a == Added::dropped, clamped_ += a == Added::clamped;
    counted_ = false;
  }

  // add(pixel_of(i), radiance_of(i), first_of(i)) for i in [0, n), in parallel: the samples are
  // sorted into ranges of pixels (a counting sort), one task per range, so no two tasks add to
  // one pixel (the sums are exact, so the order they add in never shows). first_of returns a
  // const FirstHit* (null when the film keeps no first-hit values). The sort gathers each
  // sample's pixel, radiance and first-hit values beside its place (reading the first hits in
  // the order the caller holds them, not the pixels'), so that the adding pass reads them in
  // order and can fetch the pixels' sums ahead of use (the pass waits on memory, not on
  // arithmetic).
  // Error (after adding the others) when a pixel already took count_limit samples.
  template <class PixelOf, class RadianceOf, class FirstOf>
  void add_in_order(size_t n, PixelOf pixel_of, RadianceOf radiance_of, FirstOf first_of) {
    constexpr size_t block = 8192;
    // Ranges of 2^shift pixels (at least 64), at most 1024 of them: a shift, not a division, a
    // sample.
    int shift = 6;
    while (pixels() > 0 && (pixels() - 1) >> shift >= 1024) ++shift;
    const size_t ranges = pixels() > 0 ? ((pixels() - 1) >> shift) + 1 : 1;
    const size_t blocks = (n + block - 1) / block;
    auto range_of = [&](size_t pixel) { return pixel >> shift; };
    // start[r * blocks + b]: where block b's samples of range r go.
    std::vector<uint32_t>& start = start_;
    start.assign(ranges * blocks + 1, 0);
    tbb::parallel_for(size_t(0), blocks, [&](size_t b) {
      for (size_t i = b * block, end = std::min(n, (b + 1) * block); i < end; ++i)
        ++start[range_of(pixel_of(i)) * blocks + b + 1];
    });
    for (size_t k = 1; k < start.size(); ++k) start[k] += start[k - 1];
    order_.resize(n);
    const bool firsts = stride_ > at_first;
    if (firsts) firsts_.resize(n);
    tbb::parallel_for(size_t(0), blocks, [&](size_t b) {
      std::vector<uint32_t> next(ranges);
      for (size_t r = 0; r < ranges; ++r) next[r] = start[r * blocks + b];
      for (size_t i = b * block, end = std::min(n, (b + 1) * block); i < end; ++i) {
        const size_t pixel = pixel_of(i), at = next[range_of(pixel)]++;
        const FirstHit* first = firsts ? first_of(i) : nullptr;
        order_[at] = {radiance_of(i), uint32_t(pixel), first != nullptr};
        if (first) firsts_[at] = *first;
      }
    });
    std::atomic<uint64_t> dropped_now{0}, clamped_now{0};
    std::atomic<size_t> full{pixels()};
    auto add_range = [&]<bool Firsts>(size_t r) {
      uint64_t own[4] = {};
      constexpr uint32_t ahead = 12;  // samples whose sums are fetched before they are added
      for (uint32_t k = start[r * blocks], end = start[(r + 1) * blocks]; k < end; ++k) {
        if (k + ahead < end) fetch(order_[k + ahead].pixel);
        const Sample& s = order_[k];
        const Added a = accumulate<Firsts>(record(s.pixel), s.radiance,
                                           Firsts && s.first ? &firsts_[k] : nullptr);
        ++own[int(a)];
        if (a == Added::full) full = s.pixel;
      }
      dropped_now += own[int(Added::dropped)], clamped_now += own[int(Added::clamped)];
    };
    tbb::parallel_for(size_t(0), ranges, [&](size_t r) {
      if (firsts)
        add_range.template operator()<true>(r);
      else
        add_range.template operator()<false>(r);
    });
    dropped_ += dropped_now, clamped_ += clamped_now;
    counted_ = false;
    if (full != pixels()) throw Error(too_many(full));
  }

  // Frees what add_in_order keeps between calls (the sorted samples; it makes them again when
  // called again): writing a film needs memory beside it, rendering into it no more.
  void release_scratch() const {
    std::vector<Sample>().swap(order_);
    std::vector<FirstHit>().swap(firsts_);
    std::vector<uint32_t>().swap(start_);
  }

  // Adds another film's samples (same size and outputs, else Error; Error too, with nothing
  // added, where a pixel would have more than count_limit samples or more albedo or normal than
  // max_samples samples can add up to).
  void merge(const Film& other);

  // The film's state, to send or store it exactly and add it back (merge, MPI, parts in EXR
  // files): sums_per_pixel() fixed-point sums a pixel, numbered k as the files number them
  // (colour 0-2, squares 3-5, square of the channel average 6, with first-hit outputs albedo
  // 7-9, normal 10-12, depth 13, position 14-16), then counts_per_pixel() counts, each with a
  // name (count_name). Albedo and normal sums are kept in 96 bits (bounded(k)), the others in
  // 128.
  int sums_per_pixel() const { return stride_; }
  static constexpr bool bounded(int k) { return k >= at_first && k < at_first + bounded_count; }
  Fixed sum(size_t pixel, int k) const {
    const char* at = record(pixel) + offset(k);
    return bounded(k) ? load96(at) : load128(at);
  }
  // Sets sum k of the pixel; false (nothing set) when it is bounded and the value does not fit
  // in 96 bits.
  bool set_sum(size_t pixel, int k, Fixed value);
  // The pixel's sums_per_pixel() sums into out.
  void pixel_sums(size_t pixel, Fixed* out) const {
    for (int k = 0; k < stride_; ++k) out[k] = sum(pixel, k);
  }
  // Every pixel's sums, sums_per_pixel() side by side for each (a copy).
  std::vector<Fixed> sums() const;
  // Where sum k of every pixel lies, to read files straight into the film: the address of pixel
  // 0's, the bytes from one pixel's to the next's, and the 32-bit words kept there, lowest first
  // (4; 3 for a bounded sum: its fourth word is the third's sign).
  struct SumPlace {
    char* base;
    size_t stride;
    int words;
  };
  SumPlace sum_place(int k) {
    return {reinterpret_cast<char*>(data_.data()) + offset(k), record_, bounded(k) ? 3 : 4};
  }
  // The counts a pixel: 0 "count" (samples added), 1 "taken" (samples taken, dropped ones too),
  // and with first-hit outputs 2 "hits" (samples whose camera ray hit something). Each is at
  // most count_limit.
  int counts_per_pixel() const { return stride_ > at_first ? 3 : 2; }
  static const char* count_name(int i) {
    constexpr const char* names[3] = {"count", "taken", "hits"};
    return names[i];
  }
  uint32_t count_value(size_t pixel, int i) const {
    return uint32_t(counts_word(pixel) >> (count_field * i) & count_mask);
  }
  // Sets the pixel's counts_per_pixel() counts; false (nothing set) when one is above
  // count_limit.
  bool set_counts(size_t pixel, const uint32_t* values);
  // "" when every pixel took between `least` and `most` samples, added no more than it took, has
  // no more hits than samples, and sums its samples can add up to (so that adding films cannot
  // overflow); else what is wrong, naming the pixel. For films read from files.
  std::string check_sums(uint32_t least, uint32_t most) const;
  // The samples dropped (not finite) and clamped, set when a film is read back.
  void set_tallies(uint64_t dropped, uint64_t clamped) { dropped_ = dropped, clamped_ = clamped; }

  uint64_t dropped() const { return dropped_; }
  uint64_t clamped() const { return clamped_; }
  // The most samples (taken) a pixel can count: its counts are fields of 21 bits. A render takes
  // at most max_samples.
  static constexpr uint32_t count_limit = (1u << 21) - 1;
  uint32_t count(size_t pixel) const { return count_value(pixel, 0); }
  // The samples the pixel took, dropped ones included: it has the render's samples
  // [first, first + taken) of whatever range the film holds.
  uint32_t taken(size_t pixel) const { return count_value(pixel, 1); }
  // The samples whose camera ray hit something (0 without first-hit outputs).
  uint32_t hits(size_t pixel) const { return stride_ > at_first ? count_value(pixel, 2) : 0; }
  // The fewest and most samples any pixel has, and all pixels' samples (one pass over the
  // film, kept until samples are added).
  uint32_t min_count() const;
  uint32_t max_count() const;
  uint64_t total_count() const;

  // The per-pixel mean colour.
  Image resolve() const;

  // Mean and standard error of the mean of a pixel's channel average (R+G+B)/3.
  glm::dvec2 mean_and_error(size_t pixel) const;

  // The unbiased estimate of the variance of the pixel's mean colour, channel c:
  // s² / n with s² = (Σx² − (Σx)²/n) / (n − 1). Zero with fewer than two samples.
  double variance_of_mean(size_t pixel, int c) const;

  // Every output as named channels: R, G, B, then the AOVs asked (albedo.R/G/B, N.X/Y/Z, Z,
  // P.X/Y/Z, variance.R/G/B, samples.X), named as Blender's and Nuke's EXR readers split them
  // into layers (docs/usage.md#aovs). Z is background_depth and P zero where no sample hit
  // anything. `counts`: the samples channel even when the AOVs do not ask for it (for a film
  // whose pixels have different counts).
  std::vector<Channel> channels(bool counts = false) const;
  // The same channels by the output they belong to, in order: "" (R, G, B), then each AOV by
  // its name ("albedo": albedo.R/G/B, "normal": N.X/Y/Z, "depth": Z, ...).
  struct Output {
    std::string name;
    std::vector<Channel> channels;
  };
  std::vector<Output> outputs(bool counts = false) const;
  // The names of channels(counts), and their values at pixels [first, first + n): values[c]
  // has room for n values of channel c (for writing a band of rows at a time).
  std::vector<std::string> channel_names(bool counts = false) const;
  void channel_values(bool counts, size_t first, size_t n, const std::vector<float*>& values) const;
  // How many channels channels() returns, at most (the samples channel counted).
  static int channel_count(AovSet aovs);

 private:
  // A channel: its name, the output it belongs to and its value at a pixel.
  struct Source {
    std::string name, owner;
    std::function<double(size_t)> value;
  };
  std::vector<Source> sources(bool counts) const;
  // channels(), and the output each belongs to in `owners` (when given).
  std::vector<Channel> channels(bool counts, std::vector<std::string>* owners) const;
  // Adds a sample to the pixel whose record is f: added, clamped (added with values clamped),
  // dropped (not finite, nothing added but the sample taken) or full (nothing added: the pixel
  // already counts count_limit samples in a count). Firsts: the film keeps first-hit sums.
  enum class Added { dropped, added, clamped, full };
  template <bool Firsts>
  [[gnu::noinline]] static Added accumulate(char* f, const glm::vec3& radiance,
                                            const FirstHit* first) {
    const bool finite =
        std::isfinite(radiance.x) && std::isfinite(radiance.y) && std::isfinite(radiance.z);
    const uint64_t more = !finite                           ? one_taken
                          : Firsts && first && first->hit ? one_taken + one_count + one_hit
                                                          : one_taken + one_count;
    char* const counts = f + (Firsts ? counts_at(true) : counts_at(false));
    uint64_t word;
    std::memcpy(&word, counts, 8);
    // A field at the limit would carry into the next (each is at most count_limit, but a count
    // set from elsewhere need not be below its taken).
    for (int i = 0; i < 3; ++i)
      if ((word >> (count_field * i) & count_mask) == count_limit) return Added::full;
    word += more;
    std::memcpy(counts, &word, 8);
    if (!finite) return Added::dropped;
    bool cut = false;
    auto value = [&](float v) {
      const double c = std::clamp(double(v), -value_limit, value_limit);
      cut |= c != double(v);
      return c;
    };
    const glm::dvec3 r(value(radiance.x), value(radiance.y), value(radiance.z));
    for (int c = 0; c < 3; ++c) {
      add128(f + offset(at_sum + c), to_fixed<value_bits>(r[c]));
      add128(f + offset(at_square + c), to_fixed<square_bits>(r[c] * r[c]));
    }
    const double m = (r.x + r.y + r.z) / 3.0;
    add128(f + offset(at_mean_square), to_fixed<square_bits>(m * m));
    if (Firsts && first) {
      auto bounded_value = [&](float v) {
        const double c = std::clamp(double(v), -bounded_limit, bounded_limit);
        cut |= c != double(v);
        return c;
      };
      for (int c = 0; c < 3; ++c)
        add96(f + offset(at_first + c), to_fixed<value_bits>(bounded_value(first->albedo[c]))),
            add96(f + offset(at_first + 3 + c),
                  to_fixed<value_bits>(bounded_value(first->normal[c])));
      if (first->hit) {
        add128(f + offset(at_first + 6), to_fixed<value_bits>(value(first->depth)));
        for (int c = 0; c < 3; ++c)
          add128(f + offset(at_first + 7 + c), to_fixed<value_bits>(value(first->position[c])));
      }
    }
    return cut ? Added::clamped : Added::added;
  }
  // "pixel (x, y) took more than count_limit samples".
  std::string too_many(size_t pixel) const;

  // A pixel's record of record_ bytes: its sums side by side (a sample touches one run of
  // memory, not one array each), in the order of k, then its counts. The sums are 16 bytes
  // each, but 12 for the bounded ones (albedo and normal, 7-12), whose sums of up to
  // max_samples values of at most bounded_limit are at most 2^94 in size. A 96-bit sum is its
  // low 64 bits, then the next 32 (two's complement). The counts are one 64-bit word of three
  // fields of count_field bits, lowest first: count, taken, hits; adding a sample adds to them
  // at once (a field cannot carry into the next: each stays at most count_limit).
  static constexpr int at_sum = 0, at_square = 3, at_mean_square = 6, at_first = 7,
                       first_count = 10, bounded_count = 6;
  static constexpr size_t offset(int k) {
    return k < at_first                   ? 16 * size_t(k)
           : k < at_first + bounded_count ? 16 * at_first + 12 * size_t(k - at_first)
                                          : 16 * size_t(k) - 4 * bounded_count;
  }
  static constexpr size_t counts_at(bool first_hits) {
    return first_hits ? offset(at_first + first_count) : offset(at_first);
  }
  static constexpr size_t record_bytes(bool first_hits) { return counts_at(first_hits) + 8; }
  static constexpr int count_field = 21;
  static constexpr uint64_t count_mask = count_limit;
  static constexpr uint64_t one_count = 1, one_taken = uint64_t(1) << count_field,
                            one_hit = uint64_t(1) << (2 * count_field);
  uint64_t counts_word(size_t pixel) const {
    uint64_t word;
    std::memcpy(&word, record(pixel) + record_ - 8, 8);
    return word;
  }
  __extension__ using Word = unsigned __int128;
  static Fixed load128(const char* at) {
    uint64_t w[2];
    std::memcpy(w, at, 16);
    return Fixed(Word(w[1]) << 64 | w[0]);
  }
  static void store128(char* at, Fixed v) {
    const uint64_t w[2] = {uint64_t(Word(v)), uint64_t(Word(v) >> 64)};
    std::memcpy(at, w, 16);
  }
  static Fixed load96(const char* at) {
    uint64_t low;
    int32_t high;
    std::memcpy(&low, at, 8);
    std::memcpy(&high, at + 8, 4);
    return Fixed(Word(Fixed(high)) << 64 | low);
  }
  static void store96(char* at, Fixed v) {
    const uint64_t low = uint64_t(Word(v));
    const uint32_t high = uint32_t(uint64_t(Word(v) >> 64));
    std::memcpy(at, &low, 8);
    std::memcpy(at + 8, &high, 4);
  }
  static bool fits96(Fixed v) { return v >= -(Fixed(1) << 95) && v < Fixed(1) << 95; }
  static void add128(char* at, Fixed v) { store128(at, load128(at) + v); }
  static void add96(char* at, Fixed v) { store96(at, load96(at) + v); }
  char* record(size_t pixel) { return reinterpret_cast<char*>(data_.data()) + record_ * pixel; }
  const char* record(size_t pixel) const {
    return reinterpret_cast<const char*>(data_.data()) + record_ * pixel;
  }

  // A sample as add_in_order sorted it.
  struct Sample {
    glm::vec3 radiance;
    uint32_t pixel;
    uint32_t first;  // whether it has first-hit values (in firsts_, at the same place)
  };
  // Asks for the memory adding a sample to the pixel will touch: its record (4 cache lines with
  // first-hit sums: records of 256 bytes, from a page boundary).
  void fetch(size_t pixel) const {
    const uintptr_t sums = uintptr_t(record(pixel));
    const uintptr_t end = sums + record_;
    for (uintptr_t line = sums & ~uintptr_t(63); line < end; line += 64)
      __builtin_prefetch(reinterpret_cast<const void*>(line), 1);
  }
  // The fewest, most and all samples of the pixels (counted_: up to date).
  void count_all() const;

  int width_, height_;
  AovSet aovs_;
  // add_in_order's scratch (mutable: release_scratch).
  mutable std::vector<Sample> order_;
  mutable std::vector<FirstHit> firsts_;
  mutable std::vector<uint32_t> start_;
  int stride_;    // sums per pixel: at_first, or more with first hits
  size_t record_;  // bytes of a pixel's record: record_bytes()
  // record_ bytes per pixel: zero pages from the system, page-aligned.
  std::vector<uint64_t, ZeroPageAllocator<uint64_t>> data_;
  uint64_t dropped_ = 0, clamped_ = 0;
  mutable bool counted_ = false;
  mutable uint32_t least_ = 0, most_ = 0;
  mutable uint64_t total_ = 0;
};

}  // namespace dacrt
