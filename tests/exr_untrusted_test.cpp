// EXR environment maps and references from untrusted files (issue 31, item 8): read_exr checks
// the header against the file before OpenEXR allocates anything. Each hostile file here is a few
// hundred bytes written byte by byte (the OpenEXR file layout: magic, version and flags,
// attributes as name\0 type\0 int32 size value, an empty name, the offset table, the chunks); it
// must be refused with one line naming the file and what is wrong, allocating almost nothing.
// The kept fuzzing inputs in tests/fuzz-exr/ go through fuzz/exr_input.h as the fuzzer runs them.
#include <doctest/doctest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "../fuzz/exr_input.h"
#include "address_space.h"
#include "allocations.h"
#include "corpus.h"
#include "dacrt/io/exr.h"
#include "dacrt/scene/environment.h"
#include "temp_dir.h"
#include "dacrt/util/error.h"

namespace {

using dacrt::test::AllocationWatch;
using dacrt::test::TempDir;

// A header written field by field.
struct Exr {
  std::string bytes;
  explicit Exr(uint32_t flags = 0) {
    u32(0x01312f76);
    u32(2 | flags);
  }
  Exr& u32(uint32_t v) {
    for (int i = 0; i < 4; ++i) bytes += char((v >> (8 * i)) & 0xff);
    return *this;
  }
  Exr& u8(uint8_t v) {
    bytes += char(v);
    return *this;
  }
  Exr& text(const std::string& s) {
    bytes += s;
    bytes += '\0';
    return *this;
  }
  // An attribute whose size field is `size`, followed by `value`.
  Exr& attr(const std::string& name, const std::string& type, int32_t size,
            const std::string& value) {
    text(name).text(type).u32(uint32_t(size));
    bytes += value;
    return *this;
  }
  Exr& attr(const std::string& name, const std::string& type, const std::string& value) {
    return attr(name, type, int32_t(value.size()), value);
  }
  static std::string ints(std::initializer_list<int32_t> values) {
    Exr e;
    e.bytes.clear();
    for (int32_t v : values) e.u32(uint32_t(v));
    return e.bytes;
  }
  static std::string channels(int n, const std::vector<std::string>& names = {"R", "G", "B"}) {
    Exr e;
    e.bytes.clear();
    for (int i = 0; i < n; ++i) {
      std::string name = std::to_string(i);  // c0, c1…: GCC 12 warns on "c" + to_string
      name.insert(name.begin(), 'c');
      e.text(i < int(names.size()) ? names[size_t(i)] : name);
      e.u32(2).u32(0).u32(1).u32(1);  // FLOAT, linear 0 + 3 reserved, sampling 1 x 1
    }
    e.u8(0);
    return e.bytes;
  }
  // The required attributes of a w x h image with n float channels.
  Exr& standard(int32_t w, int32_t h, int n = 3, uint8_t compression = 0) {
    attr("channels", "chlist", channels(n));
    attr("compression", "compression", std::string(1, char(compression)));
    attr("dataWindow", "box2i", ints({0, 0, w - 1, h - 1}));
    attr("displayWindow", "box2i", ints({0, 0, w - 1, h - 1}));
    attr("lineOrder", "lineOrder", std::string(1, '\0'));
    attr("pixelAspectRatio", "float", ints({0x3f800000}));
    attr("screenWindowCenter", "v2f", ints({0, 0}));
    attr("screenWindowWidth", "float", ints({0x3f800000}));
    return *this;
  }
  Exr& end() { return u8(0); }
  Exr& pad(size_t n) {
    bytes.append(n, '\0');
    return *this;
  }
};

// The error reading `bytes` as the file `name` gives, checking that it is one line naming the
// file and that reading allocated less than 1 MiB.
std::string refusal(const TempDir& dir, const std::string& name, const std::string& bytes) {
  const std::string path = dir / name;
  std::ofstream(path, std::ios::binary) << bytes;
  AllocationWatch watch;
  std::string error = "(read)";
  try {
    (void)dacrt::read_exr(path);
  } catch (const dacrt::Error& e) {
    error = e.what();
  }
  INFO(error);
  CHECK(watch.peak() < (1u << 20));
  CHECK(error.find(path) != std::string::npos);
  CHECK(error.find('\n') == std::string::npos);
  return error;
}

bool has(const std::string& s, const std::string& part) {
  if (s.find(part) != std::string::npos) return true;
  MESSAGE("the message was: " << s);
  return false;
}

}  // namespace

TEST_CASE("EXR: an attribute larger than the rest of the file is refused before it is read") {
  TempDir dir("exr-attr");
  const std::string tail = Exr().standard(2, 2).end().bytes.substr(8);  // what follows the version
  // A string, an opaque attribute of an unknown type, a float vector: 2^31 - 1 bytes declared.
  for (const std::string type : {"string", "someUnknownType", "floatvector", "chlist"}) {
    Exr e;
    e.attr("comments", type, 0x7fffffff, "abc");
    e.bytes += tail;
    CHECK(has(refusal(dir, "huge-" + type + ".exr", e.bytes),
              "attribute 'comments' declares 2147483647 bytes, more than the "));
  }
  Exr negative;
  negative.attr("owner", "string", -5, "");
  CHECK(has(refusal(dir, "negative.exr", negative.bytes + tail),
            "attribute 'owner' declares a negative size (-5)"));
  // A string vector whose size fits, but one of whose strings claims 1 GiB.
  Exr vector;
  vector.attr("multiView", "stringvector", Exr::ints({1 << 30}) + "left");
  CHECK(has(refusal(dir, "stringvector.exr", vector.bytes + tail),
            "a string in attribute 'multiView' declares 1073741824 bytes"));
  // A preview of 2^16 x 2^16 pixels in 8 bytes.
  Exr preview;
  preview.attr("preview", "preview", Exr::ints({1 << 16, 1 << 16}));
  CHECK(has(refusal(dir, "preview.exr", preview.bytes + tail), "declares a 65536 x 65536 preview"));
  // Names past 31 bytes (without the long-names flag), and a header cut short.
  Exr name;
  name.attr(std::string(40, 'n'), "string", "x");
  CHECK(has(refusal(dir, "name.exr", name.bytes + tail),
            "an attribute name is longer than 31 bytes"));
  const std::string cut = Exr().standard(2, 2).bytes;
  CHECK(has(refusal(dir, "cut.exr", cut.substr(0, cut.size() - 6)), "the file ends inside"));
  CHECK(has(refusal(dir, "magic.exr", "not an EXR at all"), "it is not an OpenEXR file"));
}

TEST_CASE("EXR: a data window of billions of pixels, or more than the file could decode to") {
  TempDir dir("exr-window");
  CHECK(has(refusal(dir, "billions.exr", Exr().standard(100000, 100000).end().bytes),
            "100000 x 100000 pixels is more than the 2^27 accepted"));
  CHECK(has(refusal(dir, "overflow.exr",
                    Exr()
                        .attr("channels", "chlist", Exr::channels(3))
                        .attr("compression", "compression", std::string(1, '\0'))
                        .attr("dataWindow", "box2i", Exr::ints({-2147483647 - 1, 0, 2147483647, 0}))
                        .end()
                        .bytes),
            "4294967296 x 1 pixels is more than the 2^27 accepted"));
  CHECK(
      has(refusal(dir, "empty.exr", Exr().standard(0, 4).end().bytes), "its data window is empty"));
  // 16384 x 8192 float RGB (1.5 GiB) from DWAB's 32 chunks in a file of under 1 KiB: this is
  // what allocated the whole image before OpenEXR found the pixels missing.
  Exr dwab;
  dwab.standard(16384, 8192, 3, 9).end().pad(32 * 8);
  CHECK(has(refusal(dir, "dwab.exr", dwab.bytes),
            "its 16384 x 8192 pixels in 3 channels would decode to 1.5 GiB, more than a "));
  // Large enough for the ratio, but more than any memory: 2^27 pixels in 1024 channels in a
  // 2 MiB file (the padding an attribute of an unknown type, skipped, never allocated).
  Exr memory;
  memory.attr("pad", "padding", std::string(size_t(2) << 20, '\0'));
  memory.attr("channels", "chlist", Exr::channels(1024));
  memory.attr("compression", "compression", std::string(1, '\0'));
  memory.attr("dataWindow", "box2i", Exr::ints({0, 0, 16383, 8191})).end();
  CHECK(has(refusal(dir, "memory.exr", memory.bytes),
            "its 16384 x 8192 pixels in 1024 channels need 512.0 GiB, more than the "));
  CHECK(has(refusal(dir, "channels.exr", Exr().standard(2, 2, 5000).end().bytes),
            "5000 channels are more than the 4096 accepted"));
  // One block of DWAB (256 lines) of a 2^20-pixel-wide image: 3 GiB decoded at once.
  CHECK(has(refusal(dir, "block.exr", Exr().standard(1 << 20, 1, 3, 9).end().pad(64).bytes),
            "its blocks of 268435456 pixels in 3 channels decode to more than 256.0 MiB each"));
}

TEST_CASE("EXR: an offset table that cannot fit in the file") {
  TempDir dir("exr-offsets");
  // 1 x 100000 pixels uncompressed: 100000 chunks, 800 000 bytes of offsets, in a 300-byte file.
  CHECK(has(refusal(dir, "lines.exr", Exr().standard(1, 100000).end().pad(16).bytes),
            "its offset table of 100000 chunks needs 800000 bytes, more than the 16 left"));
  // Tiled, 1 x 1 tiles over 4096 x 4 pixels: 16384 tiles.
  Exr tiled(0x200);
  tiled.standard(4096, 4).attr("tiles", "tiledesc", Exr::ints({1, 1}) + std::string(1, '\0'));
  CHECK(has(refusal(dir, "tiles.exr", tiled.end().pad(8).bytes),
            "its offset table of 16384 chunks needs 131072 bytes"));
  // Tiles of 65536 x 65536 pixels over a 4 x 4 image: OpenEXR would allocate a tile's buffer.
  Exr big(0x200);
  big.standard(4, 4).attr("tiles", "tiledesc", Exr::ints({65536, 65536}) + std::string(1, '\0'));
  CHECK(has(refusal(dir, "bigtile.exr", big.end().pad(8).bytes),
            "its blocks of 4294967296 pixels in 3 channels decode to more than 256.0 MiB each"));
  Exr notiles(0x200);
  CHECK(has(refusal(dir, "notiles.exr", notiles.standard(4, 4).end().pad(8).bytes),
            "the tiled file has no tiles attribute"));
}

TEST_CASE("EXR: multipart, deep and unknown files are refused as not supported") {
  TempDir dir("exr-kinds");
  CHECK(has(refusal(dir, "multi.exr", Exr(0x1000).standard(2, 2).end().end().pad(16).bytes),
            "multipart EXR files are not supported"));
  CHECK(has(refusal(dir, "deep.exr", Exr(0x800).standard(2, 2).end().pad(16).bytes),
            "deep EXR files are not supported"));
  Exr deep_type;
  deep_type.attr("type", "string", "deepscanline").standard(2, 2).end().pad(16);
  CHECK(has(refusal(dir, "deeptype.exr", deep_type.bytes),
            "EXR parts of type 'deepscanline' are not supported"));
  Exr version;
  version.bytes[4] = 3;
  CHECK(has(refusal(dir, "version.exr", version.standard(2, 2).end().bytes),
            "OpenEXR file format version 3 is not supported"));
  CHECK(has(refusal(dir, "flags.exr", Exr(0x10000).standard(2, 2).end().bytes),
            "unknown version flags 0x10000"));
  CHECK(has(refusal(dir, "compression.exr", Exr().standard(2, 2, 3, 42).end().bytes),
            "unknown compression 42"));
  CHECK(has(refusal(dir, "nochannels.exr", Exr().standard(2, 2, 0).end().bytes),
            "it has no channels"));
}

TEST_CASE("EXR: OpenEXR's own errors on a header that passes the checks are one line") {
  TempDir dir("exr-openexr");
  // A valid header whose offsets and pixels are garbage, and a real file cut short.
  CHECK(has(refusal(dir, "garbage.exr", Exr().standard(2, 2).end().pad(2 * 8 + 64).bytes),
            "cannot read EXR"));
  dacrt::Image image(8, 4);
  for (size_t i = 0; i < image.rgb.size(); ++i) image.rgb[i] = float(i % 5) * 0.25f;
  const std::string good = dir / "good.exr";
  dacrt::write_exr(good, image, {});
  std::ifstream in(good, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  CHECK(dacrt::read_exr(good).rgb == image.rgb);
  CHECK(has(refusal(dir, "short.exr", bytes.substr(0, bytes.size() - 20)), "cannot read EXR"));
  // The same through the stream entry point the fuzzer uses.
  std::istringstream stream(bytes);
  CHECK(dacrt::read_exr(stream, "memory.exr").rgb == image.rgb);
}

TEST_CASE("EXR: every kept fuzzing input and seed map loads or is refused in one line") {
  const std::filesystem::path dir = DACRT_SOURCE_DIR "/tests/fuzz-exr";
  size_t inputs = 0, loaded = 0;
  dacrt::test::for_each_corpus_file(dir, [&](const std::filesystem::path& path,
                                             const std::vector<unsigned char>& bytes) {
    const std::string name = path.filename().string();
    INFO(name);
    ++inputs;
    // Each within what its header allows: the fuzzer's out-of-memory finding (a box2i declaring
    // 0 bytes, after which OpenEXR read a string of 1.9 GB) must stay refused before it allocates.
    AllocationWatch watch;
    const dacrt::ExrFuzzOutcome outcome = dacrt::fuzz_exr_input(bytes.data(), bytes.size(), name);
    CHECK(watch.peak() < (uint64_t(64) << 20));
    if (outcome.loaded) {
      ++loaded;
    } else {
      INFO(outcome.error);
      CHECK(outcome.error.find(name) != std::string::npos);
      CHECK(outcome.error.find('\n') == std::string::npos);
    }
    // Seeds (scanline in every compression, half and float, tiled and mipmapped) must load.
    if (name.rfind("seed-", 0) == 0) CHECK(outcome.loaded);
    if (name.rfind("hostile-", 0) == 0) CHECK(!outcome.loaded);
  });
  MESSAGE(inputs << " inputs, " << loaded << " loaded");
  CHECK(loaded >= 10);
}

TEST_CASE("EXR: an environment map whose sampling tables do not fit in memory is refused") {
#if defined(__SANITIZE_ADDRESS__)
  MESSAGE("skipped under AddressSanitizer: its shadow memory needs an unlimited address space");
#else
  // 4096 x 2048 pixels: 160 MiB of weights and alias tables, in a child process whose address
  // space is limited to 64 MiB more than it has (available_memory() reads RLIMIT_AS).
  dacrt::Image image(4096, 2048);
  std::fill(image.rgb.begin(), image.rgb.end(), 1.f);
  int fds[2];
  REQUIRE(pipe(fds) == 0);
  const pid_t pid = fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    close(fds[0]);
    const dacrt::test::AddressSpaceRoom room(64u << 20);
    std::string message = "the limit could not be set";
    if (room.ok()) {
      try {
        const dacrt::EnvironmentMap map(std::move(image), "sky.exr");
        message = "the map was built";
      } catch (const dacrt::Error& e) {
        message = e.what();
      } catch (const std::bad_alloc&) {
        message = "std::bad_alloc";
      }
    }
    const ssize_t written = write(fds[1], message.data(), message.size());
    _exit(written == ssize_t(message.size()) ? 0 : 1);
  }
  close(fds[1]);
  std::string message;
  char buffer[512];
  for (ssize_t n; (n = read(fds[0], buffer, sizeof buffer)) > 0;) message.append(buffer, size_t(n));
  close(fds[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  CHECK(WIFEXITED(status));
  CHECK(has(message, "sky.exr: the environment map's sampling tables need 160.0 MiB, more than "));
#endif
}
