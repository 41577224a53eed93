#include "apps/diff.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "apps/false_color.h"
#include "dacrt/render/header.h"
#include "dacrt/render/request.h"
#include "dacrt/io/color.h"
#include "dacrt/io/exr.h"
#include "dacrt/render/convergence.h"
#include "dacrt/render/render_job.h"
#include "dacrt/util/atomic_file.h"
#include "dacrt/util/error.h"
#include "dacrt/util/image.h"
#include "dacrt/util/memory.h"
#include "dacrt/util/paths.h"
#include "dacrt/util/help_text.h"
#include "dacrt/util/text.h"

namespace dacrt {

namespace {

constexpr const char* diff_help = R"help(Usage: dacrt diff A.exr B.exr [options]

Compares the R, G and B channels of two OpenEXR images of the same size, pixel by pixel, in
linear values, B being the reference, and prints for each channel and for all three together:
  RMSE        sqrt(mean (A-B)^2)
  relMSE      mean (A-B)^2 / (B^2 + 0.01): relative to B, the reference
  MAE         mean |A-B|
  SMAPE       mean |A-B| / ((|A|+|B|)/2), a term 0 where both are 0 (from 0 to 2)
  max |A-B|   the largest difference
Images of different sizes, or with a NaN or infinite value, are refused.

Options
  -o, --output MAP.exr       the per-pixel error as an EXR of one channel, Y: the mean over R, G
                             and B of |A-B|, in linear values
  --preview MAP.png          the same error in false colour (viridis, from 0 to the scale) with
                             a colour bar on the right labelled with its two ends
  --scale X                  the error at the top of the colour bar (default: the largest
                             per-pixel error of the map); larger errors take its top colour.
                             Needs --preview
  --json                     the metrics as JSON on stdout instead of the table
  -h, --help                 this text
)help";

struct DiffArgs {
  std::string a, b, map, preview;
  std::optional<double> scale;
  bool json = false, help = false;
};

DiffArgs parse_diff(const std::vector<std::string>& given) {
  DiffArgs d;
  std::vector<std::string> args = given;
  std::vector<std::string> images;
  for (size_t i = 0; i < args.size(); ++i) {
    split_option_value(args, i, help_flag_names(diff_help));
    const std::string& a = args[i];
    auto value = [&]() -> const std::string& {
      if (i + 1 >= args.size() || args[i + 1].empty()) throw UsageError(a + " needs a value");
      return args[++i];
    };
    if (a == "-h" || a == "--help")
      d.help = true;
    else if (a == "-o" || a == "--output")
      d.map = value();
    else if (a == "--preview")
      d.preview = value();
    else if (a == "--scale")
      d.scale = parse_seconds(a, value());
    else if (a == "--json")
      d.json = true;
    else if (a.size() > 1 && a[0] == '-')
      throw UsageError("diff: unknown option " + a + did_you_mean(a, help_option_names(diff_help)));
    else
      images.push_back(a);
  }
  if (d.help) return d;
  if (images.size() != 2)
    throw UsageError("diff needs two images, A.exr and B.exr (got " +
                     std::to_string(images.size()) + ")");
  d.a = images[0], d.b = images[1];
  if (d.scale && d.preview.empty()) throw UsageError("--scale needs --preview");
  return d;
}

std::string size_of(const Image& image) {
  return std::to_string(image.width) + "x" + std::to_string(image.height);
}

// The images compared: the same size, every value finite (a NaN would make every metric NaN).
void check_comparable(const DiffArgs& d, const Image& a, const Image& b) {
  if (a.width != b.width || a.height != b.height)
    throw Error(d.a + " is " + size_of(a) + ", " + d.b + " is " + size_of(b) +
                ": the images must be the same size");
  for (const auto& [path, image] : {std::pair{&d.a, &a}, std::pair{&d.b, &b}})
    if (const std::optional<std::string> where = first_non_finite(*image))
      throw Error(*path + ": " + *where + ": only finite values can be compared");
}

// The rows of the table and the keys of the JSON: each channel, then all three.
const char* const row_names[] = {"R", "G", "B", "RGB"};
const ImageError& row(const ChannelErrors& e, int r) {
  return r < 3 ? e.channel[r] : e.all;
}

void print_table(const DiffArgs& d, const Image& a, const ChannelErrors& e) {
  std::printf("A  %s\n", d.a.c_str());
  std::printf("B  %s (the reference: relMSE divides by B^2 + 0.01)\n", d.b.c_str());
  std::printf("%d x %d pixels, linear values\n\n", a.width, a.height);
  std::printf("%-8s%13s%13s%13s%13s%13s\n", "channel", "RMSE", "relMSE", "MAE", "SMAPE",
              "max |A-B|");
  for (int r = 0; r < 4; ++r) {
    const ImageError& m = row(e, r);
    std::printf("%-8s%13.6g%13.6g%13.6g%13.6g%13.6g\n", row_names[r], m.rmse, m.relmse, m.mae,
                m.smape, m.max_abs);
  }
}

void print_json(const DiffArgs& d, const Image& a, const ChannelErrors& e) {
  nlohmann::json j = {
      {"a", d.a}, {"b", d.b}, {"reference", "b"}, {"width", a.width}, {"height", a.height}};
  for (int r = 0; r < 4; ++r) {
    const ImageError& m = row(e, r);
    j["metrics"][row_names[r]] = {{"rmse", m.rmse},
                                  {"relmse", m.relmse},
                                  {"mae", m.mae},
                                  {"smape", m.smape},
                                  {"max_abs", m.max_abs}};
  }
  std::printf("%s\n", json_text(j).c_str());
}

// The per-pixel error: the mean over R, G and B of |A - B|, in float as the map's EXR holds it.
// Finite images can differ by more than a float holds (3e38 against -3e38): such a pixel is an
// Error naming it, never an infinite map or colour bar.
std::vector<float> error_map(const DiffArgs& d, const Image& a, const Image& b) {
  std::vector<float> map(a.rgb.size() / 3);
  for (size_t p = 0; p < map.size(); ++p) {
    double sum = 0;
    for (size_t c = 0; c < 3; ++c) sum += std::abs(double(a.rgb[3 * p + c]) - b.rgb[3 * p + c]);
    if (sum / 3 > double(std::numeric_limits<float>::max())) {
      char by[32];
      std::snprintf(by, sizeof by, "%.3g", sum / 3);
      throw Error(d.a + " and " + d.b + ": pixel (" + std::to_string(p % size_t(a.width)) + ", " +
                  std::to_string(p / size_t(a.width)) + ") differs by " + by +
                  ", more than the error map's 32-bit floats hold (no map is written)");
    }
    map[p] = float(sum / 3);
  }
  return map;
}

// A preview is at least 32 rows tall and a bar and labels wider than the map: a map of one row
// and 2^27 columns would take 12 GiB. Its size is checked before anything is written. The
// picture is held three times over (the pixels, stb_image_write's filtered rows, the PNG).
void check_preview_memory(const DiffArgs& d, const Image& a) {
  if (d.preview.empty()) return;
  const uint64_t need = 3 * uint64_t(a.width + 256) * uint64_t(std::max(a.height, 32)) * 3;
  const uint64_t available = available_memory();
  if (need > available)
    throw Error(d.preview + ": the preview of a " + size_of(a) + " image needs about " +
                format_bytes(need) + ", more than the " + format_bytes(available) +
                " of memory available");
}

}  // namespace

int diff_main(const std::vector<std::string>& args) {
  const DiffArgs d = parse_diff(args);
  if (d.help) return std::fputs(diff_help, stdout), 0;
  // Everything checked before an image is read: the inputs exist, the outputs can be written and
  // are neither an input nor each other.
  check_input_file(d.a, "EXR image");
  check_input_file(d.b, "EXR image");
  const std::vector<NamedFile> outputs = {{"-o", d.map}, {"--preview", d.preview}};
  for (const NamedFile& out : outputs)
    if (!out.path.empty()) check_writable(out.path);
  check_outputs(outputs, {{"image A", d.a}, {"image B", d.b}});

  const Image a = read_exr(d.a), b = read_exr(d.b);
  check_comparable(d, a, b);
  check_preview_memory(d, a);
  const ChannelErrors e = channel_errors(a, b);
  // The map first: a pixel it cannot hold fails the command before anything is printed.
  const std::vector<float> map =
      d.map.empty() && d.preview.empty() ? std::vector<float>() : error_map(d, a, b);
  if (d.json)
    print_json(d, a, e);
  else
    print_table(d, a, e);

  if (d.map.empty() && d.preview.empty()) return 0;
  if (!d.map.empty()) {
    ExrMetadata meta;
    meta.extra = {{"errorMap", "Y: the mean over R, G and B of |A - B|"},
                  {"imageA", d.a},
                  {"imageB", d.b},
                  software_attribute()};
    write_exr(d.map, a.width, a.height, {{"Y", map}}, meta);
  }
  if (!d.preview.empty()) {
    double scale = 0;
    for (const float v : map) scale = std::max(scale, double(v));
    const Picture p = false_color(map, a.width, a.height, d.scale.value_or(scale));
    write_png(d.preview, p.width, p.height, p.rgb);
  }
  return 0;
}

}  // namespace dacrt
