// EXR writer and reader: bit-exact float round trip, header metadata, atomic replacement and
// errors that name the file.
#include "dacrt/io/exr.h"

#include <ImfChannelList.h>
#include <ImfChromaticitiesAttribute.h>
#include <ImfCompressionAttribute.h>
#include <ImfDoubleAttribute.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfIntAttribute.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>
#include <doctest/doctest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include "temp_dir.h"
#include "dacrt/util/error.h"

namespace fs = std::filesystem;
using dacrt::test::TempDir;

namespace {

dacrt::Image distinctive_image() {
  dacrt::Image image(5, 3);
  const float values[] = {0.f,
                          -0.f,
                          std::numeric_limits<float>::denorm_min(),
                          std::numeric_limits<float>::min(),
                          1e-30f,
                          0.18f,
                          1.f,
                          3.14159265f,
                          65504.f,
                          1e20f,
                          std::numeric_limits<float>::max(),
                          -1.f,
                          -1e-7f,
                          -12345.678f,
                          0.1f};
  for (size_t i = 0; i < image.rgb.size(); ++i)
    image.rgb[i] = values[i % std::size(values)] * (i < std::size(values) ? 1.f : 0.5f);
  return image;
}

bool bits_equal(float a, float b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

size_t files_in(const fs::path& dir) {
  size_t n = 0;
  for (auto it = fs::directory_iterator(dir); it != fs::directory_iterator(); ++it) ++n;
  return n;
}

}  // namespace

TEST_CASE("EXR round trip is bit-exact and keeps the metadata") {
  TempDir dir;
  const std::string path = (dir.path() / "out.exr").string();
  const dacrt::Image image = distinctive_image();
  dacrt::ExrMetadata metadata;
  metadata.spp = 64;
  metadata.backend = "dacrt";
  metadata.integrator = "path";
  metadata.render_seconds = 12.5;
  metadata.extra = {{"scene", "cornell-box.gltf"}, {"dacrtVersion", "0.1.0"}};
  dacrt::write_exr(path, image, metadata);
  CHECK(files_in(dir.path()) == 1);  // no temporary left behind

  const dacrt::Image back = dacrt::read_exr(path);
  REQUIRE(back.width == image.width);
  REQUIRE(back.height == image.height);
  REQUIRE(back.rgb.size() == image.rgb.size());
  for (size_t i = 0; i < image.rgb.size(); ++i) {
    INFO("value " << i << ": wrote " << image.rgb[i] << ", read " << back.rgb[i]);
    CHECK(bits_equal(back.rgb[i], image.rgb[i]));
  }

  Imf::InputFile file(path.c_str());
  const Imf::Header& header = file.header();
  const auto* spp = header.findTypedAttribute<Imf::IntAttribute>("spp");
  REQUIRE(spp);
  CHECK(spp->value() == 64);
  const auto* backend = header.findTypedAttribute<Imf::StringAttribute>("backend");
  REQUIRE(backend);
  CHECK(backend->value() == "dacrt");
  const auto* integrator = header.findTypedAttribute<Imf::StringAttribute>("integrator");
  REQUIRE(integrator);
  CHECK(integrator->value() == "path");
  const auto* seconds = header.findTypedAttribute<Imf::DoubleAttribute>("renderSeconds");
  REQUIRE(seconds);
  CHECK(seconds->value() == 12.5);
  const auto* scene = header.findTypedAttribute<Imf::StringAttribute>("scene");
  REQUIRE(scene);
  CHECK(scene->value() == "cornell-box.gltf");
  const auto* version = header.findTypedAttribute<Imf::StringAttribute>("dacrtVersion");
  REQUIRE(version);
  CHECK(version->value() == "0.1.0");

  CHECK(header.compression() == Imf::ZIP_COMPRESSION);
  for (const char* name : {"R", "G", "B"}) {
    const Imf::Channel* channel = header.channels().findChannel(name);
    REQUIRE(channel);
    CHECK(channel->type == Imf::FLOAT);
  }
  const auto* chroma = header.findTypedAttribute<Imf::ChromaticitiesAttribute>("chromaticities");
  REQUIRE(chroma);
  CHECK(chroma->value().red.x == doctest::Approx(0.64));
  CHECK(chroma->value().red.y == doctest::Approx(0.33));
  CHECK(chroma->value().green.x == doctest::Approx(0.30));
  CHECK(chroma->value().green.y == doctest::Approx(0.60));
  CHECK(chroma->value().blue.x == doctest::Approx(0.15));
  CHECK(chroma->value().blue.y == doctest::Approx(0.06));
  CHECK(chroma->value().white.x == doctest::Approx(0.3127));
  CHECK(chroma->value().white.y == doctest::Approx(0.3290));
}

TEST_CASE("EXR writing into a missing directory throws, naming the path, and leaves nothing") {
  TempDir dir;
  const std::string path = (dir.path() / "no-such-dir" / "out.exr").string();
  bool threw = false;
  try {
    dacrt::write_exr(path, dacrt::Image(2, 2), {});
  } catch (const dacrt::Error& e) {
    threw = true;
    const std::string message = e.what();
    CHECK(message.find(path) != std::string::npos);
    CHECK(message.find("does not exist") != std::string::npos);
    CHECK(message.find('\n') == std::string::npos);
  }
  CHECK(threw);
  CHECK(!fs::exists(dir.path() / "no-such-dir"));
  CHECK(files_in(dir.path()) == 0);
}

TEST_CASE("EXR writing into a read-only directory throws and leaves no temporary") {
  TempDir dir;
  const fs::path locked = dir.path() / "locked";
  fs::create_directory(locked);
  fs::permissions(locked, fs::perms::owner_read | fs::perms::owner_exec);
  const std::string path = (locked / "out.exr").string();
  if (access(locked.c_str(), W_OK) == 0) {
    MESSAGE("running as root: a read-only directory is still writable, skipped");
  } else {
    CHECK_THROWS_AS(dacrt::write_exr(path, dacrt::Image(2, 2), {}), dacrt::Error);
    CHECK(files_in(locked) == 0);
  }
  fs::permissions(locked, fs::perms::owner_all);
}

TEST_CASE("EXR writing over an existing file replaces it") {
  TempDir dir;
  const std::string path = (dir.path() / "out.exr").string();
  { std::ofstream(path) << "not an exr, to be replaced"; }
  dacrt::Image image(3, 2);
  for (size_t i = 0; i < image.rgb.size(); ++i) image.rgb[i] = float(i) * 0.25f;
  dacrt::write_exr(path, image, {});
  dacrt::Image back = dacrt::read_exr(path);
  CHECK(back.rgb == image.rgb);

  image.rgb.assign(image.rgb.size(), 7.f);
  dacrt::write_exr(path, image, {});
  back = dacrt::read_exr(path);
  CHECK(back.rgb == image.rgb);
  CHECK(files_in(dir.path()) == 1);
}

TEST_CASE("EXR extra metadata may not replace a standard attribute") {
  TempDir dir;
  const std::string path = (dir.path() / "out.exr").string();
  dacrt::ExrMetadata metadata;
  metadata.extra = {{"compression", "none"}};
  CHECK_THROWS_AS(dacrt::write_exr(path, dacrt::Image(1, 1), metadata), dacrt::Error);
  CHECK(files_in(dir.path()) == 0);
}

TEST_CASE("EXR reading a missing or broken file throws, naming the path") {
  TempDir dir;
  const std::string missing = (dir.path() / "missing.exr").string();
  const std::string text = (dir.path() / "text.exr").string();
  { std::ofstream(text) << "this is not an OpenEXR file\n"; }
  for (const std::string& path : {missing, text}) {
    bool threw = false;
    try {
      dacrt::read_exr(path);
    } catch (const dacrt::Error& e) {
      threw = true;
      const std::string message = e.what();
      CHECK(message.find(path) != std::string::npos);
      CHECK(message.find('\n') == std::string::npos);
    }
    CHECK(threw);
  }
}

TEST_CASE("EXR reading a file without R, G and B names the missing channel") {
  TempDir dir;
  const std::string path = (dir.path() / "luminance.exr").string();
  {
    Imf::Header header(2, 2);
    header.channels().insert("Y", Imf::Channel(Imf::FLOAT));
    float y[4] = {1, 2, 3, 4};
    Imf::OutputFile file(path.c_str(), header);
    Imf::FrameBuffer frame;
    frame.insert(
        "Y", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(y), sizeof(float), 2 * sizeof(float)));
    file.setFrameBuffer(frame);
    file.writePixels(2);
  }
  bool threw = false;
  try {
    dacrt::read_exr(path);
  } catch (const dacrt::Error& e) {
    threw = true;
    const std::string message = e.what();
    CHECK(message.find(path) != std::string::npos);
    CHECK(message.find("R channel") != std::string::npos);
  }
  CHECK(threw);
}
