// `dacrt diff A.exr B.exr`: the per-channel metrics on a pair computed by hand (in the library and
// through the CLI's table and JSON, B the reference), the error map's EXR, the false-colour
// preview's colour scale and its colour bar, and the refusals: sizes that differ, a NaN or an
// infinite value, an output that is an input, usage mistakes.
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cli.h"
#include "dacrt/io/exr.h"
#include "dacrt/io/texture_decode.h"
#include "dacrt/render/convergence.h"

using namespace dacrt;
using namespace dacrt::test;
namespace fs = std::filesystem;

namespace {

// The hand-computed pair: a 2 × 1 image A against the reference B.
//   R: A 1, 3 against B 0, 1 (differences 1, 2)
//   G: A 2, 0 against B 1, 3 (differences 1, −3: the largest difference is negative)
//   B: A 0, 0.5 against B 0, 0.25 (differences 0, 0.25; the first pair both black)
Image pair_a() {
  Image i(2, 1);
  i.rgb = {1, 2, 0, 3, 0, 0.5f};
  return i;
}
Image pair_b() {
  Image i(2, 1);
  i.rgb = {0, 1, 0, 1, 3, 0.25f};
  return i;
}

// The pair written as a.exr and b.exr in a fresh directory, for the CLI.
struct PairFiles {
  TempDir dir;
  std::string a = dir / "a.exr", b = dir / "b.exr";
  explicit PairFiles(const std::string& name) : dir(name) {
    write_exr(a, pair_a(), {});
    write_exr(b, pair_b(), {});
  }
};

// What each metric must be, per channel then over all six values.
struct Expected {
  const char* name;
  double rmse, relmse, mae, smape, max_abs;
};
const Expected expected[] = {
    // relMSE (A − B)² / (B² + 0.01): 1/0.01 and 4/1.01; SMAPE 2|d| / (|A| + |B|): 2/1 and 4/4.
    {"R", std::sqrt(5.0 / 2), (100 + 4 / 1.01) / 2, 1.5, (2 + 1.0) / 2, 2},
    {"G", std::sqrt(10.0 / 2), (1 / 1.01 + 9 / 9.01) / 2, 2, (2.0 / 3 + 2) / 2, 3},
    // The black pair counts 0 in SMAPE; 0.0625 / 0.0725 in relMSE.
    {"B", 0.25 / std::sqrt(2.0), 0.0625 / 0.0725 / 2, 0.125, (2.0 / 3) / 2, 0.25},
    {"RGB", std::sqrt(15.0625 / 6), (100 + 4 / 1.01 + 1 / 1.01 + 9 / 9.01 + 0.0625 / 0.0725) / 6,
     7.25 / 6, (2 + 1 + 2.0 / 3 + 2 + 2.0 / 3) / 6, 3},
};

// Each metric of `e` within a relative `epsilon` of `x`'s (the table prints six digits).
void check_metrics(const ImageError& e, const Expected& x, double epsilon = 1e-9) {
  INFO(std::string(x.name));
  CHECK(e.rmse == doctest::Approx(x.rmse).epsilon(epsilon));
  CHECK(e.relmse == doctest::Approx(x.relmse).epsilon(epsilon));
  CHECK(e.mae == doctest::Approx(x.mae).epsilon(epsilon));
  CHECK(e.smape == doctest::Approx(x.smape).epsilon(epsilon));
  CHECK(e.max_abs == doctest::Approx(x.max_abs).epsilon(epsilon));
}

void check_refused(const Run& r, int code, const std::string& message) {
  INFO(r.err);
  CHECK(r.code == code);
  CHECK(lines(r.err) == 1);
  CHECK_MESSAGE(r.err.find(message) != std::string::npos, message);
  CHECK(r.out.empty());
}

using Rgb = std::array<int, 3>;
constexpr Rgb viridis_first = {68, 1, 84}, viridis_middle = {33, 144, 140},
              viridis_last = {253, 231, 37};

// A decoded PNG's pixel (x, y).
Rgb pixel(const TextureImage& png, int x, int y) {
  const size_t at = 4 * (size_t(y) * size_t(png.width) + size_t(x));
  return {png.rgba8[at], png.rgba8[at + 1], png.rgba8[at + 2]};
}

TextureImage read_png(const std::string& path) {
  const std::string bytes = slurp(path);
  return decode_image(reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size(), path);
}

// A 4 × 2 pair whose per-pixel error (the mean of |A − B| over R, G, B) is 0 at (0, 0), 2 (the
// largest) at (1, 0), 1 at (2, 0) and 0.5 at (3, 1).
void write_map_pair(const TempDir& dir) {
  Image a(4, 2), b(4, 2);
  for (float& v : a.rgb) v = 0.5f;
  b.rgb = a.rgb;
  float* p = a.pixel(1, 0);
  p[0] += 6;  // 6 / 3 = 2
  p = a.pixel(2, 0);
  p[0] += 1, p[1] -= 1.5f, p[2] += 0.5f;  // 3 / 3 = 1
  a.pixel(3, 1)[2] -= 1.5f;               // 1.5 / 3 = 0.5
  write_exr(dir / "a.exr", a, {});
  write_exr(dir / "b.exr", b, {});
}

}  // namespace

TEST_CASE("diff: RMSE, relMSE, MAE, SMAPE and max |A-B| per channel of a hand-computed pair") {
  const ChannelErrors e = channel_errors(pair_a(), pair_b());
  for (int c = 0; c < 3; ++c) check_metrics(e.channel[c], expected[c]);
  check_metrics(e.all, expected[3]);
  // The overall metrics are image_error's, as `dacrt converge` measures them.
  const ImageError whole = image_error(pair_a(), pair_b());
  CHECK(whole.rmse == e.all.rmse);
  CHECK(whole.smape == e.all.smape);
}

TEST_CASE("diff: the CLI prints the metrics of A against the reference B, as a table and as JSON") {
  const PairFiles files("diff-cli");
  const std::string ab = "diff " + files.a + " " + files.b;
  const Run json = run(files.dir, ab + " --json");
  INFO(json.err);
  REQUIRE(json.code == 0);
  const nlohmann::json j = nlohmann::json::parse(json.out);
  CHECK(j["reference"] == "b");
  CHECK(j["width"] == 2);
  CHECK(j["height"] == 1);
  for (const Expected& x : expected) {
    const nlohmann::json& m = j["metrics"][x.name];
    ImageError e;
    e.rmse = m["rmse"], e.relmse = m["relmse"], e.mae = m["mae"], e.smape = m["smape"],
    e.max_abs = m["max_abs"];
    check_metrics(e, x);
  }

  const Run table = run(files.dir, ab);
  REQUIRE(table.code == 0);
  CHECK(table.err.empty());
  CHECK(table.out.find("the reference: relMSE divides by B^2 + 0.01") != std::string::npos);
  // The rows under the header line, one per channel and one for all three.
  const size_t header = table.out.find("\nchannel ");
  REQUIRE(header != std::string::npos);
  std::istringstream in(table.out.substr(header + 1));
  std::string line;
  std::getline(in, line);
  for (const Expected& x : expected) {
    REQUIRE(std::getline(in, line));
    std::istringstream cells(line);
    std::string name;
    ImageError e;
    cells >> name >> e.rmse >> e.relmse >> e.mae >> e.smape >> e.max_abs;
    CHECK(cells);
    CHECK(name == x.name);
    check_metrics(e, x, 1e-5);
  }
  CHECK(!std::getline(in, line));  // and nothing after them
}

TEST_CASE("diff: -o writes the per-pixel mean of |A-B| as the one channel Y of an EXR") {
  TempDir dir("diff-map");
  write_map_pair(dir);
  const Run r = run(dir, "diff " + dir / "a.exr" + " " + dir / "b.exr" + " -o " + dir / "map.exr");
  INFO(r.err);
  REQUIRE(r.code == 0);
  const ExrFile map = read_exr_file(dir / "map.exr");
  CHECK(map.width == 4);
  CHECK(map.height == 2);
  REQUIRE(map.channels.size() == 1);
  REQUIRE(map.find("Y"));
  const std::vector<float> want = {0, 2, 1, 0, 0, 0, 0, 0.5f};
  for (size_t p = 0; p < want.size(); ++p)
    CHECK(map.find("Y")->values[p] == doctest::Approx(want[p]));
  CHECK(map.attributes.at("imageA") == dir / "a.exr");
}

TEST_CASE("diff: finite images whose difference a float cannot hold: refused, naming the pixel") {
  TempDir dir("diff-overflow");
  Image a(3, 2), b(3, 2);
  a.pixel(2, 1)[0] = a.pixel(2, 1)[1] = a.pixel(2, 1)[2] = 3e38f;
  b.pixel(2, 1)[0] = b.pixel(2, 1)[1] = b.pixel(2, 1)[2] = -3e38f;
  write_exr(dir / "a.exr", a, {});
  write_exr(dir / "b.exr", b, {});
  const std::string pair = "diff " + dir / "a.exr" + " " + dir / "b.exr";
  for (const std::string& out : {" -o " + dir / "map.exr", " --preview " + dir / "map.png"}) {
    CAPTURE(out);
    const Run r = run(dir, pair + out);
    CHECK(r.code == 1);
    CHECK(lines(r.err) == 1);
    CHECK_MESSAGE(r.err.find("pixel (2, 1) differs by 6e+38, more than the error map's") !=
                      std::string::npos,
                  r.err);
    CHECK(r.out.empty());  // nothing printed before the refusal
    CHECK(!fs::exists(dir / "map.exr"));
    CHECK(!fs::exists(dir / "map.png"));
  }
  // Without a map, the measures (in double) are printed.
  const Run measures = run(dir, pair + " --json");
  REQUIRE_MESSAGE(measures.code == 0, measures.err);
  CHECK(nlohmann::json::parse(measures.out)["metrics"]["RGB"]["max_abs"].get<double>() ==
        doctest::Approx(6e38));
}

TEST_CASE("diff: the preview's colours run from viridis's first at 0 to its last at the scale") {
  TempDir dir("diff-preview");
  write_map_pair(dir);
  const std::string args = "diff " + dir / "a.exr" + " " + dir / "b.exr" + " --preview ";
  const Run r = run(dir, args + dir / "map.png");
  INFO(r.err);
  REQUIRE(r.code == 0);
  const TextureImage png = read_png(dir / "map.png");
  // The map at 1:1 in the top-left corner, the picture at least 32 rows tall for the bar.
  REQUIRE(png.width > 4);
  REQUIRE(png.height == 32);
  CHECK(pixel(png, 0, 0) == viridis_first);   // no error
  CHECK(pixel(png, 1, 0) == viridis_last);    // the largest: the default scale
  CHECK(pixel(png, 2, 0) == viridis_middle);  // half of it: the scale is linear
  CHECK(pixel(png, 0, 1) == viridis_first);

  // The bar: a column right of the map from the last colour at the top to the first at the
  // bottom, its colours in between falling from one end to the other; black label pixels right
  // of it at its top and its bottom.
  int bar = -1;
  for (int x = 4; x < png.width && bar < 0; ++x)
    if (pixel(png, x, 0) == viridis_last && pixel(png, x, png.height - 1) == viridis_first) bar = x;
  REQUIRE(bar > 4);
  CHECK(pixel(png, bar, png.height / 2)[1] < pixel(png, bar, 1)[1]);
  CHECK(pixel(png, bar, png.height / 2)[1] > pixel(png, bar, png.height - 2)[1]);
  auto black_in_rows = [&](const TextureImage& p, int y0, int y1) {
    int n = 0;
    for (int y = y0; y < y1; ++y)
      for (int x = bar + 1; x < p.width; ++x) n += pixel(p, x, y) == Rgb{0, 0, 0};
    return n;
  };
  CHECK(black_in_rows(png, 0, 5) > 0);                        // "2"
  CHECK(black_in_rows(png, png.height - 5, png.height) > 0);  // "0"
  CHECK(black_in_rows(png, 6, png.height - 6) == 0);

  // --scale 4: the largest error is half-way, the labels at the top change.
  const Run scaled = run(dir, args + dir / "scaled.png --scale 4");
  REQUIRE(scaled.code == 0);
  const TextureImage four = read_png(dir / "scaled.png");
  REQUIRE(four.width == png.width);
  CHECK(pixel(four, 1, 0) == viridis_middle);
  CHECK(pixel(four, 0, 0) == viridis_first);
  bool label_differs = false;
  for (int y = 0; y < 5; ++y)
    for (int x = bar + 1; x < png.width; ++x)
      label_differs |= pixel(png, x, y) != pixel(four, x, y);
  CHECK(label_differs);
}

TEST_CASE(
    "diff: images of different sizes, NaN or infinite values, and missing files are refused") {
  TempDir dir("diff-refused");
  const std::string a = dir / "a.exr", b = dir / "b.exr", small = dir / "small.exr";
  Image image(4, 4);
  write_exr(a, image, {});
  write_exr(small, Image(2, 3), {});
  const std::string outputs = " -o " + dir / "map.exr" + " --preview " + dir / "map.png";

  check_refused(
      run(dir, "diff " + a + " " + small + outputs), 1,
      "dacrt: error: " + a + " is 4x4, " + small + " is 2x3: the images must be the same size");

  image.pixel(1, 2)[1] = NAN;
  write_exr(b, image, {});
  check_refused(
      run(dir, "diff " + a + " " + b + outputs), 1,
      "dacrt: error: " + b + ": pixel (1, 2) channel G is NaN: only finite values can be compared");
  image.pixel(1, 2)[1] = 0;
  image.pixel(3, 0)[2] = -INFINITY;
  write_exr(b, image, {});
  check_refused(run(dir, "diff " + b + " " + a + outputs), 1,
                "dacrt: error: " + b + ": pixel (3, 0) channel B is infinite");

  check_refused(run(dir, "diff " + a + " " + dir / "none.exr" + outputs), 1,
                dir / "none.exr" + ": EXR image does not exist");
  std::ofstream(dir / "junk.exr") << "not an EXR";
  check_refused(run(dir, "diff " + dir / "junk.exr" + " " + a + outputs), 1,
                "cannot read EXR '" + dir / "junk.exr" + "'");
  CHECK(!fs::exists(dir / "map.exr"));
  CHECK(!fs::exists(dir / "map.png"));
}

TEST_CASE("diff: an output that names an input is refused, and the input is left as it was") {
  const PairFiles files("diff-overwrite");
  const TempDir& dir = files.dir;
  const std::string &a = files.a, &b = files.b;
  const std::string a_bytes = slurp(a), b_bytes = slurp(b);
  check_refused(run(dir, "diff " + a + " " + b + " -o " + a), 1,
                "dacrt: error: -o " + a + " would overwrite image A");
  check_refused(run(dir, "diff " + a + " " + b + " --preview " + dir / "." + "/b.exr"), 1,
                "would overwrite image B " + b);
  check_refused(run(dir, "diff " + a + " " + b + " -o " + dir / "m" + " --preview " + dir / "m"), 1,
                "is the same file as -o");
  CHECK(slurp(a) == a_bytes);
  CHECK(slurp(b) == b_bytes);
  CHECK(!fs::exists(dir / "m"));
}

TEST_CASE("diff: usage mistakes are one line and exit 2") {
  const PairFiles files("diff-usage");
  const TempDir& dir = files.dir;
  const std::string a = files.a, ab = " " + files.a + " " + files.b;
  check_refused(run(dir, "diff"), 2, "diff needs two images");
  check_refused(run(dir, "diff " + a), 2, "diff needs two images");
  check_refused(run(dir, "diff" + ab + " " + a), 2, "diff needs two images");
  check_refused(run(dir, "diff" + ab + " --bogus"), 2, "unknown option --bogus");
  check_refused(run(dir, "diff" + ab + " -o"), 2, "-o needs a value");
  check_refused(run(dir, "diff" + ab + " --preview ''"), 2, "--preview needs a value");
  check_refused(run(dir, "diff" + ab + " --scale 2"), 2, "--scale needs --preview");
  for (const char* bad : {"0", "-1", "nan", "inf", "x"})
    check_refused(run(dir, "diff" + ab + " --preview " + dir / "p.png" + " --scale " + bad), 2,
                  "--scale wants a positive number");
  CHECK(!fs::exists(dir / "p.png"));
  const Run help = run(dir, "diff --help");
  CHECK(help.code == 0);
  CHECK(help.out.find("Usage: dacrt diff A.exr B.exr") == 0);
}

TEST_CASE(
    "diff: a preview larger than the memory available is refused before anything is written") {
  // One black row of 2^22 pixels, uncompressed (one scanline a block: dacrt's own ZIP blocks of
  // 16 lines this wide exceed what the reader accepts): its preview, 32 rows tall, would take
  // over 1 GB, the address space the command gets (ulimit -v counts KiB).
#if defined(__SANITIZE_ADDRESS__)
  MESSAGE("skipped: AddressSanitizer cannot run under an address-space limit");
#else
  TempDir dir("diff-memory");
  const std::string a = dir / "a.exr";
  {
    const int width = 1 << 22;
    Imf::Header header(width, 1, 1.f, Imath::V2f(0, 0), 1.f, Imf::INCREASING_Y,
                       Imf::NO_COMPRESSION);
    std::vector<float> black(size_t(width), 0.f);
    Imf::FrameBuffer frame;
    for (const char* c : {"R", "G", "B"}) {
      header.channels().insert(c, Imf::Channel(Imf::FLOAT));
      frame.insert(c,
                   Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(black.data()), sizeof(float), 0));
    }
    Imf::OutputFile file(a.c_str(), header);
    file.setFrameBuffer(frame);
    file.writePixels(1);
  }
  const std::string args =
      "diff " + a + " " + a + " -o " + dir / "map.exr" + " --preview " + dir / "map.png";
  check_refused(run(dir, args, "ulimit -v 1000000;"), 1,
                dir / "map.png" + ": the preview of a 4194304x1 image needs about");
  CHECK(!fs::exists(dir / "map.exr"));
  CHECK(!fs::exists(dir / "map.png"));
#endif
}
