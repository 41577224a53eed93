// `dacrt merge` and `render --resume`: parts of one render (--samples ranges) add up to the whole
// render bit for bit, colour and every AOV, in any split and any order; a render cut short and
// resumed is the uninterrupted render bit for bit. Parts that overlap, leave gaps, belong to
// another render or hold no exact sums are refused with one line naming the files.
#include <ImfChannelList.h>
#include <ImfDoubleAttribute.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>
#include <doctest/doctest.h>

#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "cli.h"
#include "dacrt/io/exr.h"
#include "same_image.h"

using namespace dacrt;
using namespace dacrt::test;

namespace {

const std::string cornell = DACRT_SOURCE_DIR "/scenes/cornell-box.gltf";
const std::string options = "--width 24 --height 16 --spp 8 --seed 5 " + every_aov;

void render(const TempDir& dir, const std::string& name, const std::string& args) {
  const Run r = run(dir, "render " + cornell + " " + options + " --quiet " + args + " -o " +
                             (dir / name));
  REQUIRE_MESSAGE(r.code == 0, r.err);
}

Run merge(const TempDir& dir, const std::string& args) {
  return run(dir, "merge --quiet " + args);
}

// A copy of `from` with one string attribute set: a forged part.
void forge(const std::string& from, const std::string& to, const std::string& name,
           const std::string& value) {
  Imf::InputFile in(from.c_str());
  Imf::Header header = in.header();
  // Of the attribute's own type (OpenEXR 3.1's Header::erase leaks the attribute it erases).
  if (header.findTypedAttribute<Imf::DoubleAttribute>(name))
    header.insert(name, Imf::DoubleAttribute(std::stod(value)));
  else
    header.insert(name, Imf::StringAttribute(value));
  const Imath::Box2i window = header.dataWindow();
  const size_t width = size_t(window.max.x - window.min.x + 1);
  const size_t pixels = width * size_t(window.max.y - window.min.y + 1);
  std::vector<std::vector<uint32_t>> data;  // 4 bytes a value: float or uint
  Imf::FrameBuffer frame;
  for (auto it = header.channels().begin(); it != header.channels().end(); ++it) {
    data.emplace_back(pixels);
    frame.insert(it.name(), Imf::Slice(it.channel().type, reinterpret_cast<char*>(data.back().data()),
                                       4, 4 * width));
  }
  in.setFrameBuffer(frame);
  in.readPixels(window.min.y, window.max.y);
  Imf::OutputFile out(to.c_str(), header);
  out.setFrameBuffer(frame);
  out.writePixels(window.max.y - window.min.y + 1);
}

}  // namespace

TEST_CASE("merge: parts of any split, in any order, are the whole render bit for bit") {
  TempDir dir("merge");
  render(dir, "whole.exr", "");
  CHECK(!has_sums(dir / "whole.exr"));  // a complete render keeps no sums unless asked
  const std::vector<std::vector<std::string>> splits = {
      {"3:8", "0:3"}, {"7:8", "0:1", "2:7", "1:2"}, {"0:8"}};
  for (const auto& split : splits) {
    std::string parts;
    for (const std::string& range : split) {
      const std::string name = "part-" + range.substr(0, range.find(':')) + ".exr";
      render(dir, name, "--samples " + range + (range == "2:7" ? " --backend dacrt-naive" : ""));
      CHECK(has_sums(dir / name));
      parts.append(" ").append(dir / name);
    }
    CAPTURE(parts);
    const Run r = merge(dir, parts + " -o " + (dir / "merged.exr"));
    REQUIRE_MESSAGE(r.code == 0, r.err);
    check_same_image(dir / "merged.exr", dir / "whole.exr");
    const ExrHeader h = read_exr_header(dir / "merged.exr");
    CHECK(h.attributes.at("sampleRange") == "0:8");
    CHECK(h.attributes.at("spp") == "8");
    CHECK(h.attributes.at("match.seed") == "5");
    CHECK(!has_sums(dir / "merged.exr"));
    for (const auto& e : fs::directory_iterator(dir.path()))
      if (e.path().filename().string().rfind("part-", 0) == 0) fs::remove(e.path());
  }
  // Parts of one range merge (allowing the gap, the rest of the render) into a part of that
  // range, sums kept, which merges on.
  render(dir, "a.exr", "--samples 0:2");
  render(dir, "b.exr", "--samples 2:5");
  render(dir, "c.exr", "--samples 5:8");
  render(dir, "ab-rendered.exr", "--samples 0:5");
  const Run ab =
      merge(dir, (dir / "a.exr") + " " + (dir / "b.exr") + " --allow-gaps -o " + (dir / "ab.exr"));
  REQUIRE(ab.code == 0);
  CHECK(ab.err.find("samples 5:8 of the 8-spp render are in no part") != std::string::npos);
  CHECK(read_exr_header(dir / "ab.exr").attributes.at("sampleRange") == "0:5");
  CHECK(has_sums(dir / "ab.exr"));
  check_same_image(dir / "ab.exr", dir / "ab-rendered.exr");
  // The parts' tallies of dropped and clamped samples add up: under a sky of 3e38, samples that
  // see it are clamped; a lamp of 3e38 a few decimetres away gives irradiance past float's range
  // (infinite samples, dropped).
  const std::string bright =
      " --environment 3e38,3e38,3e38 --point-light 0.278,0.5,0.279=3e38,3e38,3e38 --samples ";
  render(dir, "bright-a.exr", bright + "0:3");
  render(dir, "bright-b.exr", bright + "3:8");
  const Run tallied = merge(dir, (dir / "bright-a.exr") + " " + (dir / "bright-b.exr") + " -o " +
                                     (dir / "tallied.exr"));
  REQUIRE_MESSAGE(tallied.code == 0, tallied.err);
  auto tally = [](const std::string& file, const char* name) {
    return std::stoull(read_exr_header(file).attributes.at(name));
  };
  for (const std::string name : {"samplesDropped", "samplesClamped"}) {
    CAPTURE(name);
    const uint64_t a = tally(dir / "bright-a.exr", name.c_str()),
                   b = tally(dir / "bright-b.exr", name.c_str());
    CHECK(a > 0);
    CHECK(b > 0);
    CHECK(tally(dir / "tallied.exr", name.c_str()) == a + b);
  }
  const Run r = merge(dir, (dir / "c.exr") + " " + (dir / "ab.exr") + " --keep-sums -o " +
                               (dir / "abc.exr") + " --preview " + (dir / "abc.png"));
  REQUIRE_MESSAGE(r.code == 0, r.err);
  check_same_image(dir / "abc.exr", dir / "whole.exr");
  CHECK(has_sums(dir / "abc.exr"));
  CHECK(fs::file_size(dir / "abc.png") > 100);
}

TEST_CASE("merge: parts that overlap, leave gaps, are of another render or hold no sums are refused") {
  TempDir dir("merge-refused");
  render(dir, "a.exr", "--samples 0:3");
  render(dir, "b.exr", "--samples 2:8");
  render(dir, "c.exr", "--samples 4:8");
  render(dir, "seed.exr", "--samples 3:8 --seed 6");
  render(dir, "embree.exr", "--samples 3:8 --backend embree");
  render(dir, "whole.exr", "");
  render(dir, "small.exr", "--samples 3:8 --width 12");
  render(dir, "head.exr", "--samples 0:4");
  forge(dir / "c.exr", dir / "cut.exr", "sampleRangeMost", "4:9");
  forge(dir / "a.exr", dir / "lying.exr", "sampleRange", "0:4");
  forge(dir / "a.exr", dir / "format.exr", "exactSums", "fixed64 v0");
  // Tallies that are not counts, or not the counts of the part's pixels: 2^64 - 1 and 5 would
  // wrap to 4 if they were added.
  forge(dir / "c.exr", dir / "wrap.exr", "samplesDropped", "18446744073709551615");
  forge(dir / "c.exr", dir / "minus.exr", "samplesDropped", "-1");
  forge(dir / "c.exr", dir / "letters.exr", "samplesClamped", "5x");
  forge(dir / "c.exr", dir / "huge.exr", "samplesClamped", "99999999999999999999999");
  forge(dir / "c.exr", dir / "dropped.exr", "samplesDropped", "5");
  forge(dir / "c.exr", dir / "clamped.exr", "samplesClamped", "1537");  // 24 x 16 x 4 = 1536 kept
  forge(dir / "c.exr", dir / "seconds.exr", "renderSeconds", "inf");
  const std::string out = dir / "out.exr";
  struct Case {
    std::string parts, message;
  };
  const std::vector<Case> cases = {
      {"a b", "overlap: samples 2:3 are in both"},
      {"a c", "samples 3:4 of the 8-spp render are in no part"},
      {"seed a", "match.seed is 5 in " + (dir / "a.exr") + ", 6 in " + (dir / "seed.exr")},
      {"embree a", "match.intersection is dacrt in " + (dir / "a.exr") + ", embree in"},
      {"small a", "match.size is 24x16 in " + (dir / "a.exr") + ", 12x16 in"},
      {"a whole", "whole.exr holds no exact sums"},
      {"a cut", "cut.exr was cut short"},
      {"lying c", "took 3 samples and kept 3 (4 were to be taken)"},
      {"format c", "format.exr: its exact sums are of another format"},
      {"a missing", "missing.exr"},
      {"head wrap", "wrap.exr: its samplesDropped 18446744073709551615 is not the 0 samples"},
      {"head minus", "minus.exr: its samplesDropped attribute \"-1\" is not a count"},
      {"head letters", "letters.exr: its samplesClamped attribute \"5x\" is not a count"},
      {"head huge", "huge.exr: its samplesClamped attribute \"99999999999999999999999\" is not a count"},
      {"head dropped", "dropped.exr: its samplesDropped 5 is not the 0 samples its pixels took and did not keep"},
      {"head seconds", "seconds.exr: its renderSeconds attribute \"inf\" is not a number of seconds"},
      {"head clamped", "clamped.exr: its samplesClamped 1537 is more than the 1536 samples its pixels kept"},
  };
  for (const Case& c : cases) {
    std::string parts;
    for (size_t at = 0; at < c.parts.size();) {
      const size_t space = std::min(c.parts.find(' ', at), c.parts.size());
      parts.append(" ").append(dir / (c.parts.substr(at, space - at) + ".exr"));
      at = space + 1;
    }
    CAPTURE(parts);
    const Run r = merge(dir, parts + " -o " + out);
    CHECK(r.code == 1);
    CHECK(lines(r.err) == 1);
    CHECK_MESSAGE(r.err.find(c.message) != std::string::npos, r.err);
    CHECK(!fs::exists(out));
  }
  // --allow-gaps merges what there is and says what is missing.
  const Run gaps = merge(dir, (dir / "a.exr") + " " + (dir / "c.exr") + " --allow-gaps -o " + out);
  REQUIRE_MESSAGE(gaps.code == 0, gaps.err);
  CHECK(gaps.err.find("samples 3:4 of the 8-spp render are in no part") != std::string::npos);
  const ExrHeader h = read_exr_header(out);
  CHECK(h.attributes.at("samplesMissing") == "3:4");
  CHECK(h.attributes.at("sampleRanges") == "0:3, 4:8");
  CHECK(h.attributes.count("sampleRange") == 0);  // not one range: not a part of anything
  CHECK(h.attributes.at("spp") == "7");
  // Usage errors: exit 2, one line.
  for (const std::string& bad : {std::string("-o ") + out, (dir / "a.exr"),
                                 (dir / "a.exr") + " -o " + out + " --nope",
                                 (dir / "a.exr") + " -o " + out + " --view sRGB"}) {
    CAPTURE(bad);
    const Run r = merge(dir, bad);
    CHECK(r.code == 2);
    CHECK(lines(r.err) == 1);
  }
}

TEST_CASE("render --resume: a render cut short and resumed is the uninterrupted render bit for bit") {
  TempDir dir("resume");
  render(dir, "whole.exr", "");
  const std::string out = dir / "r.exr";
  // Cut short by its time limit after a pass (sums kept), twice, then resumed to the end.
  render(dir, "r.exr", "--pass-spp 3 --time-limit 1e-9");
  CHECK(read_exr_header(out).attributes.at("sampleRange") == "0:3");
  CHECK(has_sums(out));
  render(dir, "r.exr", "--pass-spp 2 --time-limit 1e-9 --resume");
  CHECK(read_exr_header(out).attributes.at("sampleRange") == "0:5");
  render(dir, "r.exr", "--resume --threads 1");
  check_same_image(out, dir / "whole.exr");
  CHECK(read_exr_header(out).attributes.at("sampleRange") == "0:8");
  // A part resumed: --samples 3:8 cut short, then finished.
  render(dir, "part.exr", "--samples 3:8 --pass-spp 1 --time-limit 1e-9");
  CHECK(read_exr_header(dir / "part.exr").attributes.at("sampleRange") == "3:4");
  render(dir, "part.exr", "--samples 3:8 --resume");
  render(dir, "head.exr", "--samples 0:3");
  REQUIRE(merge(dir, (dir / "head.exr") + " " + (dir / "part.exr") + " -o " + (dir / "m.exr")).code == 0);
  check_same_image(dir / "m.exr", dir / "whole.exr");
  // No file yet: from the start, said once.
  const Run fresh = run(dir, "render " + cornell + " " + options + " --resume -o " +
                                 (dir / "fresh.exr") + " --quiet");
  REQUIRE(fresh.code == 0);
  CHECK(fresh.err.empty());
  check_same_image(dir / "fresh.exr", dir / "whole.exr");

  // Another render's file, or one without sums, is refused and left as it was.
  render(dir, "stopped.exr", "--pass-spp 3 --time-limit 1e-9");
  const std::string before = slurp(dir / "stopped.exr");
  for (const std::string& bad : {std::string("--seed 6 -o ") + (dir / "stopped.exr"),
                                 std::string("--spp 9 -o ") + (dir / "stopped.exr"),
                                 std::string("--samples 1:8 -o ") + (dir / "stopped.exr"),
                                 std::string("-o ") + (dir / "whole.exr")}) {
    CAPTURE(bad);
    const Run r = run(dir, "render " + cornell + " " + options + " --quiet --resume " + bad);
    CHECK(r.code == 1);
    CHECK(lines(r.err) == 1);
    CHECK(r.err.find("is not an earlier run of this render") + r.err.find("holds no exact sums") +
              r.err.find("holds samples from 0") !=
          3 * std::string::npos);
  }
  CHECK(slurp(dir / "stopped.exr") == before);
  for (const char* bad : {"--adaptive 0.1", "--frames 0:1", "--backend dacrt,brute"}) {
    CAPTURE(bad);
    const Run r = run(dir, "render " + cornell + " --quiet --resume " + std::string(bad) + " -o " + out);
    CHECK(r.code == 2);
    CHECK(lines(r.err) == 1);
  }
}
