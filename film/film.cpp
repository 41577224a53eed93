#include "dacrt/film/film.h"

#include <tbb/parallel_reduce.h>

#include "dacrt/util/error.h"

namespace dacrt {

namespace {
constexpr const char* aov_names[aov_count] = {"albedo",   "normal",   "depth",
                                              "position", "variance", "samples"};

// "pixel (x, y)" of pixel p in a film `width` pixels wide, for errors.
std::string pixel_name(size_t p, int width) {
  return "pixel (" + std::to_string(p % size_t(width)) + ", " + std::to_string(p / size_t(width)) +
         ")";
}
}

const char* AovSet::name(Aov a) {
  return aov_names[size_t(a)];
}

AovSet AovSet::parse(std::string_view list) {
  AovSet set;
  while (!list.empty()) {
    const size_t comma = list.find(',');
    const std::string_view item = list.substr(0, comma);
    bool known = false;
    for (int a = 0; a < aov_count; ++a)
      if (item == aov_names[a]) set.add(Aov(a)), known = true;
    if (!known) {
      std::string names;
      for (int a = 0; a < aov_count; ++a) names += (a ? ", " : "") + std::string(aov_names[a]);
      throw Error("unknown AOV '" + std::string(item) + "' (known: " + names + ")");
    }
    list = comma == std::string_view::npos ? std::string_view() : list.substr(comma + 1);
  }
  return set;
}

Film::Film(int width, int height, AovSet aovs)
    : width_(width),
      height_(height),
      aovs_(aovs),
      stride_(at_first + (aovs.first_hit() ? first_count : 0)),
      record_(record_bytes(aovs.first_hit())),
      data_(record_ / 8 * size_t(width) * height) {
  // Records of whole 64-bit words: 120 bytes a pixel, 256 (4 cache lines) with the first-hit
  // sums; the counts fit in a word (three fields of count_field bits, each up to count_limit).
  static_assert(record_bytes(false) == 120 && record_bytes(true) == 256);
  static_assert(3 * count_field <= 64 && max_samples <= count_limit);
}

uint64_t Film::bytes(int width, int height, AovSet aovs) {
  return uint64_t(width) * uint64_t(height) * record_bytes(aovs.first_hit());
}

std::string Film::too_many(size_t pixel) const {
  return pixel_name(pixel, width_) + " took more than " + std::to_string(count_limit) +
         " samples, the most a film counts";
}

void Film::merge(const Film& other) {
  if (other.width_ != width_ || other.height_ != height_ || other.stride_ != stride_)
    throw Error("cannot merge a " + std::to_string(other.width_) + " x " +
                std::to_string(other.height_) + " film into a " + std::to_string(width_) + " x " +
                std::to_string(height_) + " one with other outputs");
  // The bounded sums of films of up to max_samples samples together stay within 96 bits; more
  // could wrap them, and the counts their fields, so each is checked first.
  std::atomic<size_t> wrapped{pixels()}, full{pixels()};
  tbb::parallel_for(size_t(0), pixels(), [&](size_t p) {
    for (int i = 0; i < counts_per_pixel(); ++i)
      if (uint64_t(count_value(p, i)) + other.count_value(p, i) > count_limit) full = p;
    for (int k = at_first; k < at_first + bounded_count && k < stride_; ++k)
      if (!fits96(sum(p, k) + other.sum(p, k))) wrapped = p;
  });
  auto where = [&](size_t p) { return pixel_name(p, width_); };
  if (full != pixels())
    throw Error("cannot merge the films: " + where(full) + " would count more than " +
                std::to_string(count_limit) + " samples");
  if (wrapped != pixels())
    throw Error("cannot merge the films: " + where(wrapped) +
                " would hold more albedo or normal than " + std::to_string(max_samples) +
                " samples can add up to");
  tbb::parallel_for(size_t(0), pixels(), [&](size_t p) {
    for (int k = 0; k < stride_; ++k) set_sum(p, k, sum(p, k) + other.sum(p, k));
    // Fields of at most count_limit each: the words add field by field.
    const uint64_t word = counts_word(p) + other.counts_word(p);
    std::memcpy(record(p) + record_ - 8, &word, 8);
  });
  counted_ = false;
  dropped_ += other.dropped_;
  clamped_ += other.clamped_;
}

bool Film::set_sum(size_t pixel, int k, Fixed value) {
  char* at = record(pixel) + offset(k);
  if (!bounded(k)) return store128(at, value), true;
  if (!fits96(value)) return false;
  store96(at, value);
  return true;
}

std::vector<Fixed> Film::sums() const {
  std::vector<Fixed> out(size_t(stride_) * pixels());
  for (size_t p = 0; p < pixels(); ++p) pixel_sums(p, &out[size_t(stride_) * p]);
  return out;
}

bool Film::set_counts(size_t pixel, const uint32_t* values) {
  uint64_t word = 0;
  for (int i = 0; i < counts_per_pixel(); ++i) {
    if (values[i] > count_limit) return false;
    word |= uint64_t(values[i]) << (count_field * i);
  }
  std::memcpy(record(pixel) + record_ - 8, &word, 8);
  counted_ = false;
  return true;
}

std::string Film::check_sums(uint32_t least, uint32_t most) const {
  most = std::min(most, max_samples);
  // The largest sum n samples can make, in each scale.
  const Fixed value_most = Fixed(1) << (64 + 30), square_most = Fixed(1) << (46 + 60),
              bounded_most = Fixed(1) << (64 + 10);
  for (size_t p = 0; p < pixels(); ++p) {
    const uint32_t n = count(p), took = taken(p);
    auto where = [&] { return pixel_name(p, width_); };
    if (took < least || took > most || n > took)
      return where() + " took " + std::to_string(took) + " samples and kept " +
             std::to_string(n) +
             (least == most ? " (" + std::to_string(most) + " were to be taken)"
              : least > 0   ? " (between " + std::to_string(least) + " and " +
                                  std::to_string(most) + " were to be)"
                            : " (at most " + std::to_string(most) + ")");
    if (hits(p) > n)
      return where() + " has more first hits than samples";
    auto within = [&](Fixed v, Fixed limit) { return v <= n * limit && v >= -(n * limit); };
    Fixed f[at_first + first_count] = {};
    pixel_sums(p, f);
    bool ok = true;
    for (int c = 0; c < 3; ++c)
      ok = ok && within(f[at_sum + c], value_most) && f[at_square + c] >= 0 &&
           within(f[at_square + c], square_most);
    ok = ok && f[at_mean_square] >= 0 && within(f[at_mean_square], square_most);
    for (int k = at_first; k < stride_; ++k)
      ok = ok && within(f[k], bounded(k) ? bounded_most : value_most);
    if (!ok) return where() + " has sums its " + std::to_string(n) + " samples cannot add up to";
  }
  return "";
}

void Film::count_all() const {
  if (counted_) return;
  struct Counts {
    uint32_t least, most;
    uint64_t total;
  };
  const Counts none{~uint32_t(0), 0, 0};
  const Counts all = tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, pixels()), none,
      [&](const tbb::blocked_range<size_t>& r, Counts c) {
        for (size_t p = r.begin(); p < r.end(); ++p) {
          const uint32_t n = count(p);
          c.least = std::min(c.least, n), c.most = std::max(c.most, n), c.total += n;
        }
        return c;
      },
      [](Counts a, const Counts& b) {
        return Counts{std::min(a.least, b.least), std::max(a.most, b.most), a.total + b.total};
      });
  least_ = pixels() ? all.least : 0, most_ = all.most, total_ = all.total;
  counted_ = true;
}

uint32_t Film::min_count() const {
  return count_all(), least_;
}

uint32_t Film::max_count() const {
  return count_all(), most_;
}

uint64_t Film::total_count() const {
  return count_all(), total_;
}

Image Film::resolve() const {
  Image img(width_, height_);
  tbb::parallel_for(size_t(0), pixels(), [&](size_t p) {
    for (int c = 0; c < 3; ++c)
      img.rgb[3 * p + c] =
          count(p) ? float(from_fixed<value_bits>(sum(p, at_sum + c)) / count(p))
                    : 0.f;
  });
  return img;
}

glm::dvec2 Film::mean_and_error(size_t pixel) const {
  const double n = count(pixel);
  if (n < 1) return {0.0, 0.0};
  const double mean =
      from_fixed<value_bits>(sum(pixel, at_sum) + sum(pixel, at_sum + 1) + sum(pixel, at_sum + 2)) /
      (3.0 * n);
  const double var =
      n > 1 ? std::max(0.0,
                       (from_fixed<square_bits>(sum(pixel, at_mean_square)) - n * mean * mean) /
                           (n - 1))
            : 0.0;
  return {mean, std::sqrt(var / n)};
}

double Film::variance_of_mean(size_t pixel, int c) const {
  const double n = count(pixel);
  if (n < 2) return 0.0;
  const double total = from_fixed<value_bits>(sum(pixel, at_sum + c));
  const double s2 =
      std::max(0.0, (from_fixed<square_bits>(sum(pixel, at_square + c)) - total * total / n) /
                        (n - 1));
  return s2 / n;
}

int Film::channel_count(AovSet a) {
  return 3 + 3 * a.has(Aov::albedo) + 3 * a.has(Aov::normal) + a.has(Aov::depth) +
         3 * a.has(Aov::position) + 3 * a.has(Aov::variance) + 1;
}

std::vector<Channel> Film::channels(bool counts) const {
  return channels(counts, nullptr);
}

std::vector<Film::Output> Film::outputs(bool counts) const {
  std::vector<std::string> owners;
  std::vector<Output> out;
  std::vector<Channel> all = channels(counts, &owners);
  for (size_t c = 0; c < all.size(); ++c) {
    if (out.empty() || out.back().name != owners[c]) out.push_back({owners[c], {}});
    out.back().channels.push_back(std::move(all[c]));
  }
  return out;
}

std::vector<Channel> Film::channels(bool counts, std::vector<std::string>* owners) const {
  std::vector<Channel> out;
  const size_t n = pixels();
  for (const Source& source : sources(counts)) {
    Channel ch{source.name, std::vector<float>(n)};
    tbb::parallel_for(size_t(0), n, [&](size_t p) { ch.values[p] = float(source.value(p)); });
    out.push_back(std::move(ch));
    if (owners) owners->push_back(source.owner);
  }
  return out;
}

std::vector<std::string> Film::channel_names(bool counts) const {
  std::vector<std::string> out;
  for (const Source& source : sources(counts)) out.push_back(source.name);
  return out;
}

void Film::channel_values(bool counts, size_t first, size_t n,
                          const std::vector<float*>& values) const {
  const std::vector<Source> all = sources(counts);
  if (values.size() != all.size())
    throw Error("channel_values: " + std::to_string(values.size()) + " arrays for " +
                std::to_string(all.size()) + " channels");
  tbb::parallel_for(size_t(0), n, [&](size_t k) {
    for (size_t c = 0; c < all.size(); ++c) values[c][k] = float(all[c].value(first + k));
  });
}

std::vector<Film::Source> Film::sources(bool counts) const {
  std::vector<Source> out;
  // The output the channels made next belong to ("" for the colour).
  std::string owner;
  auto channel = [&](std::string name, std::function<double(size_t)> value) {
    out.push_back({std::move(name), owner, std::move(value)});
  };
  auto mean = [this](size_t p, Fixed sum) {
    const uint32_t n = count(p);
    return n ? from_fixed<value_bits>(sum) / n : 0.0;
  };
  const char* rgb[3] = {"R", "G", "B"};
  const char* xyz[3] = {"X", "Y", "Z"};
  for (int c = 0; c < 3; ++c)
    channel(rgb[c],
            [this, mean, c](size_t p) { return mean(p, sum(p, at_sum + c)); });
  auto first = [this](size_t p, int k) { return sum(p, at_first + k); };
  auto over_hits = [this, first](size_t p, int k, double none) {
    const uint32_t n = hits(p);
    return n ? from_fixed<value_bits>(first(p, k)) / n : none;
  };
  if (aovs_.has(Aov::albedo)) {
    owner = AovSet::name(Aov::albedo);
    for (int c = 0; c < 3; ++c)
      channel(std::string("albedo.") + rgb[c],
              [mean, first, c](size_t p) { return mean(p, first(p, c)); });
  }
  if (aovs_.has(Aov::normal)) {
    owner = AovSet::name(Aov::normal);
    for (int c = 0; c < 3; ++c)
      channel(std::string("N.") + xyz[c],
              [mean, first, c](size_t p) { return mean(p, first(p, 3 + c)); });
  }
  if (aovs_.has(Aov::depth)) {
    owner = AovSet::name(Aov::depth);
    channel("Z", [over_hits](size_t p) { return over_hits(p, 6, double(background_depth)); });
  }
  if (aovs_.has(Aov::position)) {
    owner = AovSet::name(Aov::position);
    for (int c = 0; c < 3; ++c)
      channel(std::string("P.") + xyz[c],
              [over_hits, c](size_t p) { return over_hits(p, 7 + c, 0.0); });
  }
  if (aovs_.has(Aov::variance)) {
    owner = AovSet::name(Aov::variance);
    for (int c = 0; c < 3; ++c)
      channel(std::string("variance.") + rgb[c],
              [this, c](size_t p) { return variance_of_mean(p, c); });
  }
  if (counts || aovs_.has(Aov::samples)) {
    owner = AovSet::name(Aov::samples);
    channel(samples_channel, [this](size_t p) { return double(count(p)); });
  }
  return out;
}

}  // namespace dacrt
