// Outputs by their names on the command line: `render -o` and `--preview` write the format the
// extension says (a PNG -o is byte for byte the PNG preview), an unknown extension or what only an
// EXR can hold is a usage error before anything is loaded, a render cut short into a PNG says
// once what it lost; the names of frames and backends, --stats and mpirun's rank 0 with them;
// `dacrt convert` gives the preview's bytes from the render's EXR, and refuses what it cannot
// do with one line.
#include <doctest/doctest.h>
#include <stb_image.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "cli.h"
#include "mpirun.h"
#include "cli_scene.h"
#include "dacrt/io/exr.h"
#include "dacrt/io/image_file.h"

using namespace dacrt;
using namespace dacrt::test;
namespace fs = std::filesystem;

namespace {

const std::string cornell = DACRT_SOURCE_DIR "/scenes/cornell-box.gltf";
const std::string small = " --width 16 --height 12 --spp 2 --threads 2 --quiet";
const std::string aces = " --view 'ACES 1.0 SDR-video (sRGB)' --exposure 1.5";

// The size stb_image decodes, or 0 × 0 when it cannot.
std::pair<int, int> decoded_size(const std::string& path) {
  int w = 0, h = 0, n = 0;
  if (stbi_is_hdr(path.c_str())) {
    std::unique_ptr<float, void (*)(void*)> p(stbi_loadf(path.c_str(), &w, &h, &n, 3),
                                              stbi_image_free);
    return p ? std::pair{w, h} : std::pair{0, 0};
  }
  std::unique_ptr<unsigned char, void (*)(void*)> p(stbi_load(path.c_str(), &w, &h, &n, 3),
                                                    stbi_image_free);
  return p ? std::pair{w, h} : std::pair{0, 0};
}

std::string magic(const std::string& path) {
  return slurp(path).substr(0, 4);
}

const std::string png_magic = "\x89PNG", jpeg_magic = "\xff\xd8\xff",
                  exr_magic = "\x76\x2f\x31\x01", hdr_magic = "#?RA";

size_t count(const std::string& text, const std::string& word) {
  size_t n = 0;
  for (size_t at = text.find(word); at != std::string::npos; at = text.find(word, at + 1)) ++n;
  return n;
}

// check_refused for words in a vector.
void refused(const Run& r, int code, const std::vector<std::string>& words) {
  INFO(r.err);
  CHECK(r.code == code);
  CHECK(lines(r.err) == 1);
  for (const std::string& w : words) CHECK_MESSAGE(r.err.find(w) != std::string::npos, w);
}

}  // namespace

TEST_CASE("image outputs: -o and --preview follow the extension, a PNG -o is the PNG preview") {
  TempDir dir("out-formats");
  const Run exr = run(dir, "render " + cornell + small + aces + " -o " + (dir / "ref.exr") +
                               " --preview " + (dir / "ref.png"));
  REQUIRE_MESSAGE(exr.code == 0, exr.err);
  CHECK(magic(dir / "ref.exr") == exr_magic);
  CHECK(magic(dir / "ref.png") == png_magic);
  // -o OUT.PNG (any case) with the same view: the preview's bytes; --preview x.jpg a JPEG.
  const Run png = run(dir, "render " + cornell + small + aces + " -o " + (dir / "out.PNG") +
                               " --preview " + (dir / "out.jpg"));
  REQUIRE_MESSAGE(png.code == 0, png.err);
  CHECK(png.err.empty());
  CHECK(slurp(dir / "out.PNG") == slurp(dir / "ref.png"));
  CHECK(magic(dir / "out.jpg").substr(0, 3) == jpeg_magic);
  CHECK(decoded_size(dir / "out.PNG") == std::pair{16, 12});
  CHECK(decoded_size(dir / "out.jpg") == std::pair{16, 12});
  // -o x.jpeg, -o x.hdr (linear: the EXR's values within RGBE's precision), --preview x.exr (the
  // image alone, the -o EXR's pixels).
  const Run jpeg = run(dir, "render " + cornell + small + " -o " + (dir / "j.jpeg"));
  REQUIRE_MESSAGE(jpeg.code == 0, jpeg.err);
  CHECK(magic(dir / "j.jpeg").substr(0, 3) == jpeg_magic);
  const Run hdr = run(dir, "render " + cornell + small + " -o " + (dir / "h.hdr") + " --preview " +
                               (dir / "p.exr"));
  REQUIRE_MESSAGE(hdr.code == 0, hdr.err);
  CHECK(magic(dir / "h.hdr") == hdr_magic);
  CHECK(decoded_size(dir / "h.hdr") == std::pair{16, 12});
  CHECK(magic(dir / "p.exr") == exr_magic);
  const Image ref = read_exr(dir / "ref.exr"), preview = read_exr(dir / "p.exr");
  CHECK(preview.rgb == ref.rgb);
  CHECK(read_exr_header(dir / "p.exr").channels.size() == 3);
  int w = 0, h = 0, n = 0;
  std::unique_ptr<float, void (*)(void*)> rgbe(stbi_loadf((dir / "h.hdr").c_str(), &w, &h, &n, 3),
                                               stbi_image_free);
  REQUIRE(rgbe);
  for (size_t i = 0; i < ref.rgb.size(); i += 3) {
    const float largest = std::max({ref.rgb[i], ref.rgb[i + 1], ref.rgb[i + 2]});
    for (int c = 0; c < 3; ++c)
      CHECK(std::abs(rgbe.get()[i + c] - ref.rgb[i + c]) <= largest / 128.f + 1e-30f);
  }
}

TEST_CASE("image outputs: an unknown extension and what only an EXR holds are usage errors") {
  TempDir dir("out-refused");
  const std::string missing = dir / "no-such-scene.gltf";  // refused before it is looked for
  struct Case {
    std::string args;
    std::vector<std::string> words;
  };
  const Case cases[] = {
      {" -o " + dir / "out.tif", {"-o", "out.tif", "'.tif'", ".exr, .png, .jpg, .jpeg or .hdr"}},
      {" -o " + dir / "out", {"-o", "no extension", ".hdr"}},
      {" --preview " + dir / "p.webp", {"--preview", "'.webp'"}},
      {" -o " + dir / "o.png --aov albedo", {"--aov", "EXR"}},
      {" -o " + dir / "o.jpg --samples 0:1", {"--samples", "EXR", "merge"}},
      {" -o " + dir / "o.hdr --keep-sums", {"--keep-sums", "EXR"}},
      {" -o " + dir / "o.png --resume", {"--resume", "EXR"}},
      {" -o " + dir / "o.exr --view sRGB", {"--view", "PNG or JPEG"}},
      {" -o " + dir / "o.hdr --exposure 1", {"--exposure", "PNG or JPEG"}},
      {" --preview " + dir / "p.exr --exposure 1", {"--exposure", "PNG or JPEG"}},
  };
  for (const Case& c : cases) {
    CAPTURE(c.args);
    const Run r = run(dir, "render " + missing + c.args);
    refused(r, 2, c.words);
    CHECK(r.err.find("see dacrt render --help") != std::string::npos);
  }
  CHECK(fs::is_empty(dir.path()));
  // The same outputs under two names are refused before the render, as for EXR.
  const Run same = run(dir, "render " + cornell + small + " -o " + (dir / "a.png") + " --preview " +
                                dir.path().string() + "/./a.png");
  check_refused(same, 1, {"a.png"});
  CHECK(fs::is_empty(dir.path()));
}

TEST_CASE("image outputs: frames, backends and --stats with a PNG -o, and with --view") {
  TempDir dir("out-names");
  const Run frames = run(dir, "render " + cornell + small + " --frames 0:1 -o " + (dir / "f.png") +
                                  " --stats " + (dir / "f.json"));
  REQUIRE_MESSAGE(frames.code == 0, frames.err);
  CHECK(magic(dir / "f.0000.png") == png_magic);
  CHECK(magic(dir / "f.0001.png") == png_magic);
  CHECK_FALSE(fs::exists(dir / "f.png"));
  CHECK(fs::file_size(dir / "f.json") > 0);
  const Run backends =
      run(dir, "render " + cornell + small + " --backend dacrt,brute -o " + (dir / "b.jpg") + aces);
  REQUIRE_MESSAGE(backends.code == 0, backends.err);
  CHECK(magic(dir / "b.dacrt.jpg").substr(0, 3) == jpeg_magic);
  CHECK(slurp(dir / "b.dacrt.jpg") == slurp(dir / "b.brute.jpg"));  // exact backends: one image
  CHECK_FALSE(fs::exists(dir / "b.jpg"));
}

TEST_CASE("image outputs: a render cut short into a PNG says once what the file does not keep") {
  TempDir dir("out-cut");
  const Run r = run(dir, "render " + cornell +
                             " --width 64 --height 64 --spp 100000 --threads 2 --quiet "
                             "--time-limit 2 --pass-spp 1 --checkpoint 0.2 -o " +
                             (dir / "cut.png"));
  REQUIRE_MESSAGE(r.code == 0, r.err);
  CHECK(magic(dir / "cut.png") == png_magic);
  CHECK(count(r.err, "warning:") == 1);
  CHECK(count(r.err, "cut.png holds only the image of a render cut short") == 1);
  CHECK(lines(r.err) == 1);
  // A whole render says nothing.
  const Run whole = run(dir, "render " + cornell + small + " -o " + (dir / "whole.png"));
  REQUIRE(whole.code == 0);
  CHECK(whole.err.empty());
}

TEST_CASE("image outputs: under mpirun rank 0 writes the PNG of one process") {
  if (!have_mpirun()) {
    MESSAGE("skipped: no mpirun");
    return;
  }
  TempDir dir("out-mpi");
  REQUIRE(run(dir, "render " + cornell + small + " -o " + (dir / "one.png")).code == 0);
  const Run r = run(dir, "render " + cornell + small + " -o " + (dir / "two.png"),
                    mpirun(2));
  REQUIRE_MESSAGE(r.code == 0, r.err);
  CHECK(slurp(dir / "two.png") == slurp(dir / "one.png"));
  size_t files = 0;
  for (auto it = fs::directory_iterator(dir.path()); it != fs::directory_iterator(); ++it) ++files;
  CHECK(files == 2);  // no temporary of another rank
}

TEST_CASE("convert: a render's EXR gives the preview's bytes, any layer, any format") {
  TempDir dir("convert");
  const Run render = run(dir, "render " + cornell + small + aces + " --aov albedo,depth -o " +
                                  (dir / "r.exr") + " --preview " + (dir / "r.png"));
  REQUIRE_MESSAGE(render.code == 0, render.err);
  const Run png = run(dir, "convert " + (dir / "r.exr") + " " + (dir / "c.png") + aces);
  REQUIRE_MESSAGE(png.code == 0, png.err);
  CHECK(slurp(dir / "c.png") == slurp(dir / "r.png"));
  CHECK(lines(png.err) == 1);  // the file written
  const Run jpg = run(dir, "convert --quiet " + (dir / "r.exr") + " " + (dir / "c.JPG") + aces);
  REQUIRE_MESSAGE(jpg.code == 0, jpg.err);
  CHECK(jpg.err.empty());
  const Run jpg_render = run(dir, "render " + cornell + small + aces + " -o " + (dir / "r.jpg"));
  REQUIRE(jpg_render.code == 0);
  CHECK(slurp(dir / "c.JPG") == slurp(dir / "r.jpg"));
  // Without --view the default view's bytes differ; EXR and HDR stay linear.
  REQUIRE(run(dir, "convert --quiet " + (dir / "r.exr") + " " + (dir / "d.png")).code == 0);
  CHECK(slurp(dir / "d.png") != slurp(dir / "r.png"));
  REQUIRE(run(dir, "convert --quiet " + (dir / "r.exr") + " " + (dir / "c.exr")).code == 0);
  CHECK(read_exr(dir / "c.exr").rgb == read_exr(dir / "r.exr").rgb);
  CHECK(read_exr_header(dir / "c.exr").channels.size() == 3);
  REQUIRE(run(dir, "convert --quiet " + (dir / "r.exr") + " " + (dir / "c.hdr")).code == 0);
  CHECK(magic(dir / "c.hdr") == hdr_magic);
  // A layer: albedo's channels, the depth as grey.
  REQUIRE(run(dir, "convert --quiet " + (dir / "r.exr") + " " + (dir / "a.exr") + " --layer albedo")
              .code == 0);
  const ExrFile r = read_exr_file(dir / "r.exr");
  const Image albedo = read_exr(dir / "a.exr");
  for (size_t p = 0; p < r.find("albedo.R")->values.size(); ++p) {
    CHECK(albedo.rgb[3 * p] == r.find("albedo.R")->values[p]);
    CHECK(albedo.rgb[3 * p + 2] == r.find("albedo.B")->values[p]);
  }
  REQUIRE(run(dir, "convert --quiet " + (dir / "r.exr") + " " + (dir / "z.exr") + " --layer depth")
              .code == 0);
  const Image depth = read_exr(dir / "z.exr");
  for (size_t p = 0; p < r.find("Z")->values.size(); ++p) {
    CHECK(depth.rgb[3 * p] == r.find("Z")->values[p]);
    CHECK(depth.rgb[3 * p + 1] == r.find("Z")->values[p]);
    CHECK(depth.rgb[3 * p + 2] == r.find("Z")->values[p]);
  }
}

TEST_CASE("convert: its help, and one line for every refusal") {
  TempDir dir("convert-refused");
  const Run help = run(dir, "convert --help");
  CHECK(help.code == 0);
  CHECK(help.out.find("Usage: dacrt convert IN.exr OUT") == 0);
  const std::string scene = small_scene(dir);
  REQUIRE(run(dir, "render " + scene + small + " -o " + (dir / "in.exr")).code == 0);
  const std::string in = dir / "in.exr";
  struct Case {
    std::string args;
    int code;
    std::vector<std::string> words;
  };
  std::ofstream(dir / "bad.exr") << "not an EXR at all";
  const Case cases[] = {
      {in, 2, {"convert needs IN.exr and OUT", "see dacrt convert --help"}},
      {in + " " + dir / "o.tif", 2, {"OUT", "'.tif'", ".png"}},
      {in + " " + dir / "o.hdr --view sRGB", 2, {"--view", "HDR"}},
      {in + " " + dir / "o.exr --exposure 2", 2, {"--exposure", "EXR"}},
      {in + " " + dir / "o.png --exposure nan", 2, {"--exposure"}},
      {in + " " + dir / "o.png --view Nope", 2, {"Nope", "sRGB"}},
      {in + " " + dir / "o.png --layer albedo", 2, {"no layer 'albedo'"}},
      {in + " " + dir / "o.png --bogus", 2, {"--bogus", "see dacrt convert --help"}},
      {in + " " + dir / "o.png extra", 2, {"extra"}},
      {dir / "none.exr " + dir / "o.png", 1, {"none.exr"}},
      {dir / "bad.exr " + dir / "o.png", 1, {"bad.exr"}},
      {dir / "s.gltf " + dir / "o.png", 1, {"s.gltf"}},
      {in + " " + in, 1, {"in.exr"}},
      {in + " " + dir / "no/dir/o.png", 1, {"no/dir"}},
  };
  for (const Case& c : cases) {
    CAPTURE(c.args);
    refused(run(dir, "convert " + c.args), c.code, c.words);
    CHECK_FALSE(fs::exists(dir / "o.png"));
  }
  CHECK(slurp(in).substr(0, 4) == exr_magic);  // IN as it was
}

TEST_CASE("image outputs: merge writes an EXR, and its preview by the preview's name") {
  TempDir dir("out-merge");
  REQUIRE(run(dir, "render " + cornell + small + aces + " --samples 0:2 -o " + (dir / "part.exr") +
                       " --preview " + (dir / "part.png"))
              .code == 0);
  refused(run(dir, "merge --quiet " + (dir / "part.exr") + " -o " + (dir / "m.png")), 2,
          {"-o", "m.png", "EXR", "see dacrt merge --help"});
  refused(run(dir, "merge --quiet " + (dir / "part.exr") + " -o " + (dir / "m.exr") +
                       " --preview " + (dir / "m.hdr") + " --view sRGB"),
          2, {"--view", "PNG or JPEG"});
  CHECK_FALSE(fs::exists(dir / "m.exr"));
  const Run r = run(dir, "merge --quiet " + (dir / "part.exr") + " -o " + (dir / "m.exr") +
                             " --preview " + (dir / "m.png") + aces);
  REQUIRE_MESSAGE(r.code == 0, r.err);
  CHECK(magic(dir / "m.exr") == exr_magic);
  CHECK(slurp(dir / "m.png") == slurp(dir / "part.png"));  // the whole render: the same image
  REQUIRE(run(dir, "merge --quiet " + (dir / "part.exr") + " -o " + (dir / "n.exr") +
                       " --preview " + (dir / "n.jpg"))
              .code == 0);
  CHECK(magic(dir / "n.jpg").substr(0, 3) == jpeg_magic);
}

TEST_CASE("convert: an RGBA EXR keeps its alpha in a PNG, and a JPEG says it has none") {
  TempDir dir("convert-alpha");
  Image image(4, 2);
  for (size_t i = 0; i < image.rgb.size(); ++i) image.rgb[i] = 0.1f * float(i % 7);
  const std::vector<float> alpha = {0.f, 0.25f, 0.5f, 1.f, 1.f, 0.5f, 0.25f, 0.f};
  write_image(dir / "in.exr", image, {}, {}, alpha);
  const Run png = run(dir, "convert --quiet " + (dir / "in.exr") + " " + (dir / "out.png"));
  REQUIRE_MESSAGE(png.code == 0, png.err);
  write_image(dir / "direct.png", image, {}, {}, alpha);
  CHECK(slurp(dir / "out.png") == slurp(dir / "direct.png"));
  CHECK(slurp(dir / "out.png")[25] == 6);  // colour type RGBA
  const Run jpg = run(dir, "convert --quiet " + (dir / "in.exr") + " " + (dir / "out.jpg"));
  REQUIRE(jpg.code == 0);
  CHECK(lines(jpg.err) == 1);
  CHECK(jpg.err.find("warning: " + (dir / "out.jpg") + " is JPEG, which holds no alpha") == 0);
  write_image(dir / "direct.jpg", image);
  CHECK(slurp(dir / "out.jpg") == slurp(dir / "direct.jpg"));
}
