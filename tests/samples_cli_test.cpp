// `dacrt render --samples FIRST:LAST`: a range of the --spp render's sample indices, the same
// numbers the whole render draws for them, said in the header; bad ranges are usage errors.
#include <doctest/doctest.h>

#include "cli.h"
#include "dacrt/io/exr.h"
#include "gltf_triangle.h"

using namespace dacrt;
using namespace dacrt::test;

namespace {

const std::string cornell = DACRT_SOURCE_DIR "/scenes/cornell-box.gltf";

ExrFile render_part(const TempDir& dir, const std::string& name, const std::string& args) {
  const Run r = run(dir, "render " + cornell + " --width 24 --height 16 --spp 8 --seed 5 --quiet " +
                             args + " -o " + (dir / name));
  REQUIRE_MESSAGE(r.code == 0, r.err);
  return read_exr_file(dir / name);
}

const Channel& channel(const ExrFile& f, const std::string& name) {
  for (const Channel& c : f.channels)
    if (c.name == name) return c;
  FAIL("no channel " << name);
  return f.channels.front();
}

}  // namespace

TEST_CASE("render --samples: a range of the whole render's samples, said in the header") {
  TempDir dir("samples");
  const ExrFile whole = render_part(dir, "whole.exr", "");
  const ExrFile all = render_part(dir, "all.exr", "--samples 0:8");
  const ExrFile head = render_part(dir, "head.exr", "--samples 0:5");
  const ExrFile tail = render_part(dir, "tail.exr", "--samples 3:8");
  CHECK(whole.attributes.at("sampleRange") == "0:8");
  CHECK(tail.attributes.at("sampleRange") == "3:8");
  CHECK(tail.attributes.at("sppRequested") == "8");
  CHECK(tail.attributes.at("spp") == "5");
  // 0:8 is the whole render, bit for bit.
  for (const char* c : {"R", "G", "B"}) CHECK(channel(all, c).values == channel(whole, c).values);
  // 3:8 draws samples 3 to 7, not 0 to 4: the same count as 0:5, other numbers, another image;
  // with 0:3 (weighed by the counts) it makes the whole image.
  const ExrFile first = render_part(dir, "first.exr", "--samples 0:3");
  size_t differ = 0, off = 0;
  for (const char* c : {"R", "G", "B"}) {
    const std::vector<float>&t = channel(tail, c).values, &h = channel(head, c).values,
                          &f = channel(first, c).values, &w = channel(whole, c).values;
    for (size_t p = 0; p < t.size(); ++p) {
      differ += t[p] != h[p];
      const double merged = (3.0 * f[p] + 5.0 * t[p]) / 8.0;
      off += std::abs(merged - w[p]) > 1e-5 * std::max(1.0, std::abs(double(w[p])));
    }
  }
  CHECK(differ > 100);
  CHECK(off == 0);
}

TEST_CASE("render --samples: ranges that are not part of the render are usage errors") {
  TempDir dir("samples-usage");
  for (const char* bad : {"--samples 3", "--samples 3:3", "--samples 5:2", "--samples 0:9",
                          "--samples -1:4", "--samples a:4", "--samples 0:4 --adaptive 0.1"}) {
    INFO(bad);
    const Run r = run(dir, "render " + cornell + " --spp 8 -o " + (dir / "x.exr") + " " + bad);
    CHECK(r.code == 2);
    CHECK(r.err.find("--samples") != std::string::npos);
    CHECK(lines(r.err) == 1);
  }
  check_no_outputs(dir);
}

TEST_CASE("render: the header's match.* keys, what parts of one render share") {
  TempDir dir("samples-match");
  const ExrFile a = render_part(dir, "a.exr", "--samples 0:3");
  const ExrFile b = render_part(dir, "b.exr", "--samples 3:8 --backend dacrt-naive --threads 1");
  const ExrFile e = render_part(dir, "e.exr", "--samples 3:8 --backend embree");
  const ExrFile seed = render_part(dir, "seed.exr", "--samples 3:8 --seed 6");
  auto keys = [](const ExrFile& f) {
    std::map<std::string, std::string> m;
    for (const auto& [k, v] : f.attributes)
      if (k.rfind("match.", 0) == 0) m[k] = v;
    return m;
  };
  CHECK(keys(a).size() >= 15);
  CHECK(keys(a) == keys(b));  // the backend and the threads never change a pixel
  CHECK(keys(a).at("match.intersection") == "dacrt");
  // ... but for Embree's intersection test, whose hits differ in the last bits.
  std::map<std::string, std::string> embree = keys(e);
  CHECK(embree.at("match.intersection") == "embree");
  embree["match.intersection"] = "dacrt";
  CHECK(embree == keys(a));
  std::map<std::string, std::string> other = keys(seed);
  CHECK(other.at("match.seed") == "6");
  other["match.seed"] = "5";
  CHECK(other == keys(a));
  CHECK(a.attributes.at("match.inputs").rfind("fnv1a64w:", 0) == 0);
  CHECK(a.attributes.at("match.size") == "24x16");
  // Another scene file, the same size (the JSON with a space of its layout made a tab): another
  // fingerprint.
  std::string text = slurp(cornell);
  const size_t space = text.find("\n ");
  REQUIRE(space != std::string::npos);
  text[space + 1] = '\t';
  std::ofstream(dir / "cb.gltf") << text;
  const Run r = run(dir, "render " + (dir / "cb.gltf") +
                             " --width 24 --height 16 --spp 8 --seed 5 --quiet -o " + (dir / "c.exr"));
  REQUIRE_MESSAGE(r.code == 0, r.err);
  const ExrFile c = read_exr_file(dir / "c.exr");
  CHECK(c.attributes.at("match.inputs") != a.attributes.at("match.inputs"));
  CHECK(c.attributes.at("match.camera") == a.attributes.at("match.camera"));
}

TEST_CASE("render --samples: a render stopped by its time limit says the range it has") {
  TempDir dir("samples-time-limit");
  const Run r = run(dir, "render " + cornell + " --width 128 --height 128 --spp 4096 --samples 2:4096 "
                             "--pass-spp 1 --time-limit 0.3 --quiet -o " + (dir / "t.exr"));
  REQUIRE_MESSAGE(r.code == 0, r.err);
  const ExrFile t = read_exr_file(dir / "t.exr");
  const std::string range = t.attributes.at("sampleRange");
  REQUIRE(range.rfind("2:", 0) == 0);
  const int last = std::stoi(range.substr(2));
  CHECK(last > 2);
  CHECK(last < 4096);
  CHECK(t.attributes.at("spp") == std::to_string(last - 2));
}

TEST_CASE("render: match.inputs covers the bytes the render read, and only those") {
  // A triangle whose buffer is an external file: bytes past its byteLength are not the scene's
  // (the spec allows them; the loader never reads them), nor is an image no material uses.
  TempDir dir("samples-fingerprint");
  GltfWriter w;
  w.add_triangles(kTriangle);
  w.doc["images"] = nlohmann::json::array({{{"uri", "unused.png"}}});
  const std::string scene = w.write_gltf(dir / "t.gltf", /*embed=*/false);
  write_text(dir / "unused.png", "not even a PNG");
  auto fingerprint = [&](const std::string& name) {
    const Run r = run(dir, "render " + scene + " --width 8 --height 8 --spp 1 --quiet -o " +
                               (dir / name));
    REQUIRE_MESSAGE(r.code == 0, r.err);
    return read_exr_header(dir / name).attributes.at("match.inputs");
  };
  const std::string before = fingerprint("a.exr");
  // Longer than its byteLength (another program's data after it), another unused image: the same.
  std::string bin = slurp(dir / "t.bin");
  write_text(dir / "t.bin", bin + std::string(100000, 'x'));
  write_text(dir / "unused.png", "another text");
  CHECK(fingerprint("b.exr") == before);
  // A byte the render reads: another fingerprint.
  bin[bin.size() - 1] ^= 1;
  write_text(dir / "t.bin", bin);
  CHECK(fingerprint("c.exr") != before);
}
