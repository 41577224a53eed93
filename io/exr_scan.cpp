// The check of an EXR file's header before OpenEXR reads it (see exr_scan.h).
#include "dacrt/io/exr_scan.h"

#include <cstdint>
#include <cstring>
#include <istream>
#include <map>
#include <string>
#include <vector>

#include "dacrt/util/error.h"
#include "dacrt/util/memory.h"

namespace dacrt {

namespace {

// Bounds, above what any real environment map or reference needs.
constexpr uint32_t kExrMagic = 0x01312f76;  // 76 2f 31 01, read little-endian
constexpr uint32_t kTiledFlag = 0x200, kLongNamesFlag = 0x400, kDeepFlag = 0x800,
                   kMultipartFlag = 0x1000;
// Float bytes a file may decode to per byte it holds. Real files compress far less (zlib at most
// ~1000:1; a constant image in DWAB a few times that), so only a forged header reaches this.
constexpr uint64_t kMaxDecodeRatio = uint64_t(1) << 18;
// OpenEXR decodes one block (a group of scanlines, or a tile) of every channel at a time.
constexpr uint64_t kMaxBlockBytes = uint64_t(256) << 20;
constexpr int64_t kMaxChannels = 4096;

// Lines per chunk, by the compression attribute's value (NO, RLE, ZIPS, ZIP, PIZ, PXR24, B44,
// B44A, DWAA, DWAB); 0 for a value OpenEXR does not know.
int lines_per_block(int compression) {
  static constexpr int lines[] = {1, 1, 1, 16, 32, 16, 32, 32, 32, 256};
  return compression >= 0 && compression < 10 ? lines[compression] : 0;
}

// Reads the header byte by byte, allocating nothing that the file's size does not bound.
class HeaderReader {
 public:
  HeaderReader(std::istream& in, const std::string& name, uint64_t size)
      : in_(in), name_(name), size_(size) {}
  uint64_t left() const { return size_ - pos_; }
  uint64_t pos() const { return pos_; }
  [[noreturn]] void fail(const std::string& what) const {
    throw Error("cannot read EXR '" + name_ + "': " + what);
  }
  void bytes(void* out, uint64_t n, const std::string& what) {
    if (n > left()) fail("the file ends inside " + what);
    in_.read(static_cast<char*>(out), std::streamsize(n));
    if (uint64_t(in_.gcount()) != n) fail("the file ends inside " + what);
    pos_ += n;
  }
  void skip(uint64_t n, const std::string& what) {
    if (n > left()) fail("the file ends inside " + what);
    in_.seekg(std::streamoff(n), std::ios::cur);
    if (!in_) fail("cannot seek past " + what);
    pos_ += n;
  }
  uint32_t u32(const std::string& what) {
    unsigned char b[4];
    bytes(b, 4, what);
    return uint32_t(b[0]) | uint32_t(b[1]) << 8 | uint32_t(b[2]) << 16 | uint32_t(b[3]) << 24;
  }
  int32_t i32(const std::string& what) { return int32_t(u32(what)); }
  uint8_t u8(const std::string& what) {
    uint8_t b;
    bytes(&b, 1, what);
    return b;
  }
  // A NUL-terminated string of at most `max` bytes.
  std::string text(size_t max, const std::string& what) {
    std::string s;
    for (;;) {
      const char c = char(u8(what));
      if (c == '\0') return s;
      if (s.size() == max) fail(what + " is longer than " + std::to_string(max) + " bytes");
      s += c;
    }
  }

 private:
  std::istream& in_;
  const std::string& name_;
  uint64_t size_, pos_ = 0;
};

int64_t tiles(int64_t pixels, int64_t tile) {
  return (pixels + tile - 1) / tile;
}

// Levels of a mipmap over n pixels, and the size of level l (OpenEXR's ImfTiledMisc rules).
int64_t level_count(int64_t n, bool round_up) {
  int64_t levels = 1;
  if (round_up)
    while ((int64_t(1) << (levels - 1)) < n) ++levels;
  else
    while ((n >> levels) > 0) ++levels;
  return levels;
}
int64_t level_size(int64_t n, int64_t l, bool round_up) {
  const int64_t s = round_up ? (n + (int64_t(1) << l) - 1) >> l : n >> l;
  return std::max<int64_t>(s, 1);
}

// The tiles of every level of a tiled file: the entries of its offset table.
int64_t tile_count(int64_t w, int64_t h, int64_t tx, int64_t ty, int mode, bool round_up) {
  if (mode == 0) return tiles(w, tx) * tiles(h, ty);
  if (mode == 1) {
    int64_t n = 0;
    for (int64_t l = 0, levels = level_count(std::max(w, h), round_up); l < levels; ++l)
      n += tiles(level_size(w, l, round_up), tx) * tiles(level_size(h, l, round_up), ty);
    return n;
  }
  int64_t nx = 0, ny = 0;
  for (int64_t l = 0, levels = level_count(w, round_up); l < levels; ++l)
    nx += tiles(level_size(w, l, round_up), tx);
  for (int64_t l = 0, levels = level_count(h, round_up); l < levels; ++l)
    ny += tiles(level_size(h, l, round_up), ty);
  return nx * ny;
}

// The attributes of a header whose version says names of at most `max_name` bytes, each checked
// against its declared size, up to the empty name that ends them: what scan_header checks next.
struct HeaderAttributes {
  int64_t channel_count = -1, compression = -1, tile_x = 0, tile_y = 0;
  int tile_mode = -1;
  bool have_window = false, tiled_type = false;
  int32_t window[4] = {0, 0, 0, 0};
};
HeaderAttributes read_attributes(HeaderReader& r, size_t max_name) {
  HeaderAttributes found;
  for (;;) {
    const std::string attr = r.text(max_name, "an attribute name");
    if (attr.empty()) break;
    const std::string what = "attribute '" + attr + "'";
    const std::string type = r.text(max_name, what + "'s type name");
    const int32_t size = r.i32(what + "'s size");
    if (size < 0) r.fail(what + " declares a negative size (" + std::to_string(size) + ")");
    if (uint64_t(size) > r.left())
      r.fail(what + " declares " + std::to_string(size) + " bytes, more than the " +
             std::to_string(r.left()) + " left in the file");
    const uint64_t value_end = r.pos() + uint64_t(size);
    const auto fixed = [&](int32_t n) {
      if (size != n)
        r.fail(what + " of type " + type + " has " + std::to_string(size) + " bytes, not " +
               std::to_string(n));
    };
    // OpenEXR reads the types of a fixed size at that size whatever size the file declares: a
    // box2i declaring 0 bytes is read as 16, and from there OpenEXR sees other attributes than
    // this scan did (a fuzzed file made it read a string of 1.9 GB). Every such type's declared
    // size must be its own.
    static const std::map<std::string, int32_t> fixed_sizes = {
        {"compression", 1}, {"lineOrder", 1}, {"envmap", 1},     {"deepImageState", 1},
        {"int", 4},         {"float", 4},     {"v2i", 8},        {"v2f", 8},
        {"double", 8},      {"rational", 8},  {"timecode", 8},   {"tiledesc", 9},
        {"v3i", 12},        {"v3f", 12},      {"box2i", 16},     {"box2f", 16},
        {"v2d", 16},        {"v3d", 24},      {"keycode", 28},   {"chromaticities", 32},
        {"m33f", 36},       {"m44f", 64},     {"m33d", 72},      {"m44d", 128}};
    if (const auto known = fixed_sizes.find(type); known != fixed_sizes.end()) fixed(known->second);
    if (type == "chlist") {
      int64_t n = 0;
      for (;;) {
        if (r.pos() >= value_end) r.fail(what + " is not terminated");
        const std::string channel = r.text(max_name, "a channel name in " + what);
        if (channel.empty()) break;
        r.skip(16, "channel '" + channel + "' in " + what);
        ++n;
      }
      if (r.pos() != value_end) r.fail(what + " does not fill its declared size");
      if (attr == "channels") found.channel_count = n;
    } else if (type == "compression") {
      const int c = r.u8(what);
      if (attr == "compression") {
        if (!lines_per_block(c)) r.fail("unknown compression " + std::to_string(c));
        found.compression = c;
      }
    } else if (type == "box2i" && attr == "dataWindow") {
      for (int32_t& v : found.window) v = r.i32(what);
      found.have_window = true;
    } else if (type == "tiledesc" && attr == "tiles") {
      found.tile_x = r.u32(what), found.tile_y = r.u32(what);
      found.tile_mode = r.u8(what);
    } else if (type == "string" && attr == "type") {
      std::string value(size_t(size), '\0');
      r.bytes(value.data(), uint64_t(size), what);
      found.tiled_type = value == "tiledimage";
      if (value != "scanlineimage" && value != "tiledimage")
        r.fail("EXR parts of type '" + one_line(value) + "' are not supported");
    } else if (type == "stringvector") {
      while (r.pos() < value_end) {
        const int32_t n = r.i32("a string in " + what);
        if (n < 0 || uint64_t(n) > value_end - r.pos())
          r.fail("a string in " + what + " declares " + std::to_string(n) +
                 " bytes, more than the " + std::to_string(value_end - r.pos()) +
                 " left in the attribute");
        r.skip(uint64_t(n), what);
      }
    } else if (type == "preview") {
      if (size < 8) r.fail(what + " is shorter than its preview size");
      const uint64_t w = r.u32(what), h = r.u32(what);  // each below 2^32: no overflow
      if (w * h != (uint64_t(size) - 8) / 4 || (uint64_t(size) - 8) % 4 != 0)
        r.fail(what + " declares a " + std::to_string(w) + " x " + std::to_string(h) +
               " preview in " + std::to_string(size - 8) + " bytes");
    }
    if (r.pos() > value_end) r.fail(what + " is longer than its declared size");
    r.skip(value_end - r.pos(), what);
  }
  return found;
}

}  // namespace

// Checks, before OpenEXR allocates anything, that every size the header of the file in `in`
// declares fits in the file and in memory, and that the file is one we decode (a single part of
// flat scanlines or tiles). Follows the OpenEXR file layout: magic, version and flags, then
// attributes (name\0 type\0 int32 size, value) up to an empty name, then the offset table.
HeaderScan scan_header(std::istream& in, const std::string& name) {
  in.seekg(0, std::ios::end);
  const std::streamoff end = in.tellg();
  in.seekg(0);
  if (!in || end < 0) throw Error("cannot read EXR '" + name + "': cannot find its size");
  HeaderReader r(in, name, uint64_t(end));
  if (r.left() < 8 || r.u32("the magic number") != kExrMagic)
    r.fail("it is not an OpenEXR file (no 76 2f 31 01 magic number)");
  const uint32_t version = r.u32("the version");
  if ((version & 0xff) != 2)
    r.fail("OpenEXR file format version " + std::to_string(version & 0xff) + " is not supported");
  if (version & kMultipartFlag) r.fail("multipart EXR files are not supported");
  if (version & kDeepFlag) r.fail("deep EXR files are not supported");
  if (version & ~uint32_t(0xff | kTiledFlag | kLongNamesFlag))
    r.fail("unknown version flags 0x" + [&] {
      char hex[16];
      std::snprintf(hex, sizeof hex, "%x", version & ~0xffu);
      return std::string(hex);
    }());
  const bool tiled = version & kTiledFlag;
  const size_t max_name = version & kLongNamesFlag ? 255 : 31;

  const HeaderAttributes found = read_attributes(r, max_name);
  const int64_t channel_count = found.channel_count, compression = found.compression,
                tile_x = found.tile_x, tile_y = found.tile_y;
  const int tile_mode = found.tile_mode;
  const bool have_window = found.have_window, tiled_type = found.tiled_type;
  const int32_t(&window)[4] = found.window;

  if (channel_count < 0) r.fail("the header has no channels attribute");
  if (channel_count == 0) r.fail("it has no channels");
  if (channel_count > kMaxChannels)
    r.fail(std::to_string(channel_count) + " channels are more than the " +
           std::to_string(kMaxChannels) + " accepted");
  if (compression < 0) r.fail("the header has no compression attribute");
  if (!have_window) r.fail("the header has no dataWindow attribute");
  const int64_t width = int64_t(window[2]) - window[0] + 1,
                height = int64_t(window[3]) - window[1] + 1;
  if (width < 1 || height < 1) r.fail("its data window is empty");
  const std::string pixels_text = std::to_string(width) + " x " + std::to_string(height) +
                                  " pixels in " + std::to_string(channel_count) + " channels";
  // Each side first: a window's sides reach 2^32, whose product overflows 64 bits.
  if (width > kMaxExrPixels || height > kMaxExrPixels || width * height > kMaxExrPixels)
    r.fail(std::to_string(width) + " x " + std::to_string(height) +
           " pixels is more than the 2^27 accepted");
  // At most 2^27 pixels, and channels bounded by the file's size: no overflow.
  const uint64_t decoded = uint64_t(width * height) * uint64_t(channel_count) * 4;
  if (decoded / kMaxDecodeRatio > uint64_t(end))
    r.fail("its " + pixels_text + " would decode to " + format_bytes(decoded) + ", more than a " +
           std::to_string(end) + "-byte file can hold");
  if (decoded > available_memory())
    r.fail("its " + pixels_text + " need " + format_bytes(decoded) + ", more than the " +
           format_bytes(available_memory()) + " of memory available");

  // The scanline blocks, and the tiles when the header describes any (whichever way OpenEXR
  // takes the file, its buffers stay bounded).
  const auto check_block = [&](int64_t block) {
    if (uint64_t(block) > kMaxBlockBytes / 4 / uint64_t(channel_count))
      r.fail("its blocks of " + std::to_string(block) + " pixels in " +
             std::to_string(channel_count) + " channels decode to more than " +
             format_bytes(kMaxBlockBytes) + " each");
  };
  check_block(width * lines_per_block(int(compression)));
  int64_t chunks = tiles(height, lines_per_block(int(compression)));
  if (tiled && tile_mode < 0) r.fail("the tiled file has no tiles attribute");
  if (tile_mode >= 0) {
    const int level_mode = tile_mode & 0xf, rounding = tile_mode >> 4;
    if (level_mode > 2 || rounding > 1)
      r.fail("unknown tile level mode " + std::to_string(tile_mode));
    if (tile_x < 1 || tile_y < 1 || tile_x > (int64_t(1) << 30) || tile_y > (int64_t(1) << 30))
      r.fail("tiles of " + std::to_string(tile_x) + " x " + std::to_string(tile_y) +
             " pixels are not supported");
    check_block(tile_x * tile_y);
    if (tiled || tiled_type)
      chunks = tile_count(width, height, tile_x, tile_y, level_mode, rounding == 1);
  }
  if (uint64_t(chunks) > r.left() / 8)
    r.fail("its offset table of " + std::to_string(chunks) + " chunks needs " +
           std::to_string(uint64_t(chunks) * 8) + " bytes, more than the " +
           std::to_string(r.left()) + " left in the file");
  return {width, height};
}


}  // namespace dacrt
