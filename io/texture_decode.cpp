// Decoding of glTF images: PNG through libpng, JPEG through libjpeg-turbo, WebP (EXT_texture_webp)
// through libwebp, chosen by the bytes' signature (never by the mimeType, which files get wrong).
// Everything else is refused, naming the format when its signature is known (Radiance HDR, BMP,
// GIF, PSD, PNM, TIFF, KTX2, ...).
//
// - Bounds: the size is read from the header and refused above 2^27 texels before any row or
//   output buffer exists (libpng's user limits, 2^27 a side, back this up; WebP's own limit is
//   16384 a side). libpng refuses any chunk but IDAT longer than 8 MiB and drops an ancillary
//   chunk inflating past 8 MiB; the text, ICC profile, suggested-palette and Exif chunks (zTXt,
//   iTXt, tEXt, iCCP, sPLT, eXIf) are skipped unread. libpng allocates through operator new, so
//   the test suite's allocation counter sees it. A progressive JPEG may have at most 500 scans
//   (libjpeg-turbo's own fuzzing limit): each scan passes over the whole image, so a small file of
//   many scans would otherwise take minutes. libwebp decodes into our buffer; a lossless WebP
//   holds a second copy of its texels (ARGB, libwebp's malloc) while it decodes.
// - Strictness: data that ends early is an error (PNG: the reader refuses to read past the end;
//   JPEG: libjpeg's "premature end" warning, after which it would pad with grey, is an error;
//   WebP: libwebp's simple API says so), and so are CRC errors in critical PNG chunks and a bad
//   zlib checksum (the PNG is read through IEND). Other warnings (e.g. a bad CRC in an ancillary
//   chunk, which is dropped) are ignored: no library prints anything. Lossy WebP and JPEG data
//   have no checksum: damage inside them decodes to damaged texels.
// - Output: always RGBA, 16 bits per channel for 16-bit PNGs (host order), 8 otherwise; palette,
//   grey, grey + alpha, tRNS and 1-, 2- and 4-bit samples expanded. No gamma or ICC correction
//   (glTF colour textures are sRGB by definition). JPEG: greyscale, YCbCr, RGB, progressive and
//   arithmetic-coded files; CMYK and YCCK are converted to RGB without a profile, taken as
//   inverted (Adobe's convention) when the file has an Adobe marker. WebP: lossy (YUV 4:2:0,
//   upsampled by libwebp) and lossless, alpha kept unpremultiplied.
// - Apple CgBI PNGs (iOS-optimised, not standard PNG) are refused. An APNG decodes to its default
//   image (IDAT), what viewers that do not know APNG show; the animation chunks are skipped. An
//   animated WebP has no such default image (libwebp's still-image API refuses it): refused.
//
// Thread-safe: every call has its own decoder state; errors come back by longjmp from libpng's
// and libjpeg's error handlers into the one function per step that armed it (libwebp returns a
// status instead). Those functions keep only trivially destructible locals, and the output
// buffers are allocated outside them.
#include "dacrt/io/texture_decode.h"

// clang-format off
#include <cstdio>  // before jpeglib.h, which uses size_t and FILE without including them
#include <jpeglib.h>
#include <jerror.h>
// clang-format on
#include <png.h>
#include <webp/decode.h>

#include <bit>
#include <csetjmp>
#include <cstring>
#include <new>
#include <string_view>

#include "dacrt/util/error.h"

namespace dacrt {

namespace {

constexpr uint64_t kMaxTexels = uint64_t(1) << 27;

[[noreturn]] void fail(const std::string& what, const std::string& why) {
  throw Error(what + " cannot be decoded: " + why);
}

using namespace std::string_view_literals;

bool has_at(const unsigned char* bytes, size_t size, std::string_view signature, size_t at = 0) {
  return size >= at + signature.size() &&
         std::memcmp(bytes + at, signature.data(), signature.size()) == 0;
}

enum class Format { png, jpeg, webp };

constexpr const char* kSupported = "(only PNG, JPEG and WebP are supported)";

// The format of the bytes, from their signature; anything but PNG, JPEG and WebP is an error
// naming the format the bytes look like, or their first bytes.
Format sniff(const unsigned char* bytes, size_t size, const std::string& what) {
  if (size == 0) fail(what, "it has no data");
  if (has_at(bytes, size, "\x89PNG\r\n\x1a\n"sv)) {
    if (has_at(bytes, size, "CgBI"sv, 12))
      fail(what, "it is an Apple CgBI PNG (iOS-optimised, not a standard PNG)");
    return Format::png;
  }
  if (has_at(bytes, size, "\xff\xd8\xff"sv)) return Format::jpeg;
  if (has_at(bytes, size, "RIFF"sv) && has_at(bytes, size, "WEBP"sv, 8)) return Format::webp;
  struct Signature {
    std::string_view bytes;
    size_t at;
    const char* name;
  };
  static const Signature known[] = {
      {"#?RADIANCE"sv, 0, "a Radiance HDR"},
      {"#?RGBE"sv, 0, "a Radiance HDR"},
      {"BM"sv, 0, "a BMP"},
      {"GIF8"sv, 0, "a GIF"},
      {"8BPS"sv, 0, "a Photoshop (PSD)"},
      {"\x53\x80\xf6\x34"sv, 0, "a Softimage PIC"},
      {"II*\0"sv, 0, "a TIFF"},
      {"MM\0*"sv, 0, "a TIFF"},
      {"WEBP"sv, 8, "a damaged WebP (its RIFF signature is altered)"},
      {"qoif"sv, 0, "a QOI"},
      {"DDS "sv, 0, "a DDS"},
      {"\xabKTX 20\xbb"sv, 0, "a KTX2 (KHR_texture_basisu)"},
      {"\xabKTX"sv, 0, "a KTX"},
      {"\x76\x2f\x31\x01"sv, 0, "an OpenEXR"},
      {"ftypavif"sv, 4, "an AVIF"},
      {"ftypheic"sv, 4, "a HEIF"},
      {"\0\0\0\x0cjP  "sv, 0, "a JPEG 2000"},
      {"\x89PNG"sv, 0, "a damaged PNG (its signature is altered)"},
      {"\xff\xd8"sv, 0, "a damaged JPEG (its signature is altered)"},
  };
  for (const Signature& s : known)
    if (has_at(bytes, size, s.bytes, s.at))
      fail(what, std::string("it is ") + s.name + " image, not PNG, JPEG or WebP " + kSupported);
  // Netpbm: P1 to P7, then white space.
  if (size >= 3 && bytes[0] == 'P' && bytes[1] >= '1' && bytes[1] <= '7' &&
      (bytes[2] == ' ' || bytes[2] == '\t' || bytes[2] == '\r' || bytes[2] == '\n'))
    fail(what, std::string("it is a Netpbm (PBM/PGM/PPM/PAM) image, not PNG, JPEG or WebP ") +
                   kSupported);
  std::string first;
  for (size_t i = 0; i < size && i < 8; ++i) {
    char hex[4];
    std::snprintf(hex, sizeof hex, "%s%02x", i ? " " : "", bytes[i]);
    first += hex;
  }
  fail(what, "its first bytes (" + first + ") are not a PNG, JPEG or WebP signature " + kSupported);
}

struct Header {
  uint32_t width = 0, height = 0;
  bool wide = false;  // 16 bits per channel
};

void check_size(const Header& h, const std::string& what) {
  if (h.width == 0 || h.height == 0 || uint64_t(h.width) * h.height > kMaxTexels)
    fail(what,
         std::to_string(h.width) + " x " + std::to_string(h.height) + " texels is more than 2^27");
}

// ---- PNG ---------------------------------------------------------------------------------------

// libpng's state for one image: C data only, so that libpng's longjmp may leave it.
struct PngRead {
  png_structp png = nullptr;
  png_infop info = nullptr;
  const unsigned char* data = nullptr;
  size_t size = 0, at = 0;
  char message[256] = "";
};

void png_failed(png_structp png, png_const_charp message) {
  auto* r = static_cast<PngRead*>(png_get_error_ptr(png));
  std::snprintf(r->message, sizeof r->message, "%s", message ? message : "unknown error");
  png_longjmp(png, 1);
}

void png_warned(png_structp, png_const_charp) {}

void png_read_bytes(png_structp png, png_bytep out, size_t n) {
  auto* r = static_cast<PngRead*>(png_get_io_ptr(png));
  if (n > r->size - r->at) png_error(png, "the data ends before the image does (truncated file)");
  std::memcpy(out, r->data + r->at, n);
  r->at += n;
}

png_voidp png_allocate(png_structp, png_alloc_size_t n) {
  return ::operator new(n, std::nothrow);
}

void png_release(png_structp, png_voidp p) {
  ::operator delete(p);
}

// Reads the chunks up to the image data and sets the transforms to RGBA; false with r.message on
// error.
bool png_start(PngRead& r, Header& h) {
  if (setjmp(png_jmpbuf(r.png))) return false;
  png_set_read_fn(r.png, &r, png_read_bytes);
  png_set_user_limits(r.png, uint32_t(kMaxTexels), uint32_t(kMaxTexels));
  png_set_chunk_malloc_max(r.png, 8 << 20);
  static const png_byte skipped[] = "zTXt\0iTXt\0tEXt\0iCCP\0sPLT\0eXIf";
  png_set_keep_unknown_chunks(r.png, PNG_HANDLE_CHUNK_NEVER, skipped, int(sizeof skipped / 5));
  png_read_info(r.png, r.info);
  h.width = png_get_image_width(r.png, r.info);
  h.height = png_get_image_height(r.png, r.info);
  const int depth = png_get_bit_depth(r.png, r.info);
  const int type = png_get_color_type(r.png, r.info);
  h.wide = depth == 16;
  if (type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(r.png);
  if (png_get_valid(r.png, r.info, PNG_INFO_tRNS)) png_set_tRNS_to_alpha(r.png);
  // Expands 1-, 2- and 4-bit grey to 8 bits as well.
  if (type == PNG_COLOR_TYPE_GRAY || type == PNG_COLOR_TYPE_GRAY_ALPHA) png_set_gray_to_rgb(r.png);
  if (!(type & PNG_COLOR_MASK_ALPHA) && !png_get_valid(r.png, r.info, PNG_INFO_tRNS))
    png_set_add_alpha(r.png, 0xffff, PNG_FILLER_AFTER);
  if (h.wide && std::endian::native == std::endian::little) png_set_swap(r.png);
  return true;
}

// Decodes the rows into `out` (row_bytes each, width × 4 samples) and reads on to IEND.
bool png_finish(PngRead& r, unsigned char* out, size_t row_bytes) {
  if (setjmp(png_jmpbuf(r.png))) return false;
  const int passes = png_set_interlace_handling(r.png);
  png_read_update_info(r.png, r.info);
  if (png_get_rowbytes(r.png, r.info) != row_bytes)
    png_error(r.png, "the rows do not come out as RGBA");
  const uint32_t height = png_get_image_height(r.png, r.info);
  for (int pass = 0; pass < passes; ++pass)
    for (uint32_t y = 0; y < height; ++y) png_read_row(r.png, out + y * row_bytes, nullptr);
  png_read_end(r.png, nullptr);
  return true;
}

class PngDecoder {
 public:
  PngDecoder(const unsigned char* bytes, size_t size, const std::string& what) : what_(what) {
    // The size from IHDR (the first chunk) first, for this message rather than libpng's
    // "Invalid IHDR data" after the user limits (which are 2^27 per side).
    if (has_at(bytes, size, "IHDR"sv, 12) && size >= 24) {
      auto be32 = [&](size_t at) {
        return uint32_t(bytes[at]) << 24 | uint32_t(bytes[at + 1]) << 16 |
               uint32_t(bytes[at + 2]) << 8 | bytes[at + 3];
      };
      const Header claimed = {be32(16), be32(20), false};
      if (claimed.width && claimed.height) check_size(claimed, what_);
    }
    r_.data = bytes;
    r_.size = size;
    r_.png = png_create_read_struct_2(PNG_LIBPNG_VER_STRING, &r_, png_failed, png_warned, nullptr,
                                      png_allocate, png_release);
    if (r_.png) r_.info = png_create_info_struct(r_.png);
    if (!r_.info) fail(what_, "out of memory for libpng");
    if (!png_start(r_, header_)) failed();
    check_size(header_, what_);
  }
  PngDecoder(const PngDecoder&) = delete;
  PngDecoder& operator=(const PngDecoder&) = delete;

  const Header& header() const { return header_; }

  TextureImage decode() {
    TextureImage image;
    image.width = int(header_.width);
    image.height = int(header_.height);
    const size_t samples = 4 * size_t(header_.width) * header_.height;
    unsigned char* out;
    // Zeroed (Array's resize would not): rows a decoder might leave are black, never stale memory.
    if (header_.wide) {
      image.rgba16.assign(samples, 0);
      out = reinterpret_cast<unsigned char*>(image.rgba16.data());
    } else {
      image.rgba8.assign(samples, 0);
      out = image.rgba8.data();
    }
    if (!png_finish(r_, out, 4 * size_t(header_.width) * (header_.wide ? 2 : 1))) failed();
    return image;
  }

 private:
  [[noreturn]] void failed() { fail(what_, std::string("invalid PNG data: ") + r_.message); }

  // libpng's structures, freed also when the constructor throws.
  struct State : PngRead {
    State() = default;
    State(const State&) = delete;
    State& operator=(const State&) = delete;
    ~State() { png_destroy_read_struct(&png, info ? &info : nullptr, nullptr); }
  };

  std::string what_;
  State r_;
  Header header_;
};

// ---- JPEG --------------------------------------------------------------------------------------

constexpr int kMaxJpegScans = 500;

// libjpeg's state for one image: C data only, so that the error handler's longjmp may leave it.
struct JpegRead {
  jpeg_decompress_struct cinfo;
  jpeg_error_mgr errors;
  jpeg_progress_mgr progress;
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX + 64];
};

void jpeg_failed(j_common_ptr cinfo) {
  auto* r = reinterpret_cast<JpegRead*>(cinfo);  // cinfo is JpegRead's first member
  (*cinfo->err->format_message)(cinfo, r->message);
  std::longjmp(r->jump, 1);
}

// Warnings (level −1) are dropped, but for the data ending early, after which libjpeg would pad
// the image with grey: that is an error. Trace messages (level ≥ 0) are dropped too.
void jpeg_message(j_common_ptr cinfo, int level) {
  if (level == -1 && cinfo->err->msg_code == JWRN_JPEG_EOF) jpeg_failed(cinfo);
}

void jpeg_scan_limit(j_common_ptr cinfo) {
  auto* r = reinterpret_cast<JpegRead*>(cinfo);
  if (r->cinfo.input_scan_number > kMaxJpegScans) {
    std::snprintf(r->message, sizeof r->message, "more than %d scans", kMaxJpegScans);
    std::longjmp(r->jump, 1);
  }
}

// Fails only when out of memory.
bool jpeg_create(JpegRead& r) {
  r.cinfo.err = jpeg_std_error(&r.errors);
  r.errors.error_exit = jpeg_failed;
  r.errors.emit_message = jpeg_message;
  r.progress.progress_monitor = jpeg_scan_limit;
  if (setjmp(r.jump)) return false;
  jpeg_create_decompress(&r.cinfo);
  r.cinfo.progress = &r.progress;
  return true;
}

bool jpeg_start(JpegRead& r, const unsigned char* bytes, size_t size, Header& h) {
  if (setjmp(r.jump)) return false;
  jpeg_mem_src(&r.cinfo, bytes, static_cast<unsigned long>(size));
  jpeg_read_header(&r.cinfo, TRUE);
  h.width = r.cinfo.image_width;
  h.height = r.cinfo.image_height;
  switch (r.cinfo.jpeg_color_space) {
    case JCS_GRAYSCALE:
    case JCS_YCbCr:
    case JCS_RGB:
      r.cinfo.out_color_space = JCS_EXT_RGBA;
      break;
    case JCS_CMYK:
    case JCS_YCCK:
      r.cinfo.out_color_space = JCS_CMYK;
      break;
    default:
      std::snprintf(r.message, sizeof r.message, "%d colour components in an unknown colour space",
                    r.cinfo.num_components);
      return false;
  }
  return true;
}

bool jpeg_finish(JpegRead& r, unsigned char* out) {
  if (setjmp(r.jump)) return false;
  jpeg_start_decompress(&r.cinfo);
  if (r.cinfo.output_components != 4) {
    std::snprintf(r.message, sizeof r.message, "%d components per texel after conversion",
                  r.cinfo.output_components);
    return false;
  }
  const size_t row_bytes = 4 * size_t(r.cinfo.output_width);
  while (r.cinfo.output_scanline < r.cinfo.output_height) {
    JSAMPROW row = out + r.cinfo.output_scanline * row_bytes;
    jpeg_read_scanlines(&r.cinfo, &row, 1);
  }
  jpeg_finish_decompress(&r.cinfo);
  return true;
}

class JpegDecoder {
 public:
  JpegDecoder(const unsigned char* bytes, size_t size, const std::string& what) : what_(what) {
    if (!jpeg_create(r_) || !jpeg_start(r_, bytes, size, header_)) failed();
    check_size(header_, what_);
  }
  JpegDecoder(const JpegDecoder&) = delete;
  JpegDecoder& operator=(const JpegDecoder&) = delete;

  const Header& header() const { return header_; }

  TextureImage decode() {
    TextureImage image;
    image.width = int(header_.width);
    image.height = int(header_.height);
    image.rgba8.assign(4 * size_t(header_.width) * header_.height, 0);
    if (!jpeg_finish(r_, image.rgba8.data())) failed();
    if (r_.cinfo.out_color_space == JCS_CMYK) cmyk_to_rgba(image.rgba8, r_.cinfo.saw_Adobe_marker);
    return image;
  }

 private:
  // Without a colour profile: R = (1 − C)(1 − K) and so on. Adobe's files store 1 − C (255 is no
  // ink), others C.
  static void cmyk_to_rgba(Array<uint8_t>& texels, bool inverted) {
    for (size_t i = 0; i < texels.size(); i += 4) {
      const unsigned k = inverted ? texels[i + 3] : 255u - texels[i + 3];
      for (size_t c = 0; c < 3; ++c) {
        const unsigned v = inverted ? texels[i + c] : 255u - texels[i + c];
        texels[i + c] = uint8_t((v * k + 127) / 255);
      }
      texels[i + 3] = 255;
    }
  }

  [[noreturn]] void failed() { fail(what_, std::string("invalid JPEG data: ") + r_.message); }

  // libjpeg's structures, freed also when the constructor throws; zeroed first, which makes
  // jpeg_destroy_decompress safe on a state that jpeg_create left half made.
  struct State : JpegRead {
    State() : JpegRead{} {}
    State(const State&) = delete;
    State& operator=(const State&) = delete;
    ~State() { jpeg_destroy_decompress(&cinfo); }
  };

  std::string what_;
  State r_;
  Header header_;
};

// ---- WebP --------------------------------------------------------------------------------------

// libwebp's status codes in words.
std::string webp_status(VP8StatusCode status) {
  switch (status) {
    case VP8_STATUS_OUT_OF_MEMORY:
      return "out of memory";
    case VP8_STATUS_BITSTREAM_ERROR:
      return "bitstream error";
    case VP8_STATUS_UNSUPPORTED_FEATURE:
      return "a feature libwebp does not decode";
    case VP8_STATUS_SUSPENDED:
    case VP8_STATUS_NOT_ENOUGH_DATA:
      return "the data ends before the image does (truncated file)";
    default:
      return "libwebp's status " + std::to_string(int(status));
  }
}

class WebpDecoder {
 public:
  // The header (RIFF, VP8X, and the VP8 or VP8L frame header) only: nothing is allocated.
  WebpDecoder(const unsigned char* bytes, size_t size, const std::string& what)
      : bytes_(bytes), size_(size), what_(what) {
    if (!WebPInitDecoderConfig(&config_)) fail(what_, "libwebp's version does not match");
    const VP8StatusCode status = WebPGetFeatures(bytes, size, &config_.input);
    if (status != VP8_STATUS_OK) failed(status);
    if (config_.input.has_animation)
      fail(what_, "it is an animated WebP (only still WebP images are supported)");
    header_.width = uint32_t(config_.input.width);
    header_.height = uint32_t(config_.input.height);
    check_size(header_, what_);
  }
  WebpDecoder(const WebpDecoder&) = delete;
  WebpDecoder& operator=(const WebpDecoder&) = delete;

  const Header& header() const { return header_; }

  TextureImage decode() {
    TextureImage image;
    image.width = int(header_.width);
    image.height = int(header_.height);
    image.rgba8.assign(4 * size_t(header_.width) * header_.height, 0);
    WebPDecBuffer& out = config_.output;
    out.colorspace = MODE_RGBA;  // not premultiplied (MODE_rgbA)
    out.is_external_memory = 1;
    out.u.RGBA.rgba = image.rgba8.data();
    out.u.RGBA.stride = int(4 * header_.width);
    out.u.RGBA.size = image.rgba8.size();
    const VP8StatusCode status = WebPDecode(bytes_, size_, &config_);
    WebPFreeDecBuffer(&out);  // frees nothing of ours: the memory is external
    if (status != VP8_STATUS_OK) failed(status);
    return image;
  }

 private:
  [[noreturn]] void failed(VP8StatusCode status) {
    fail(what_, std::string("invalid WebP data: ") + webp_status(status));
  }

  const unsigned char* bytes_;
  size_t size_;
  std::string what_;
  WebPDecoderConfig config_;
  Header header_;
};

}  // namespace

uint64_t decoded_size(const unsigned char* bytes, size_t size, const std::string& what) {
  Header h;
  switch (sniff(bytes, size, what)) {
    case Format::png:
      h = PngDecoder(bytes, size, what).header();
      break;
    case Format::jpeg:
      h = JpegDecoder(bytes, size, what).header();
      break;
    case Format::webp:
      h = WebpDecoder(bytes, size, what).header();
      break;
  }
  return uint64_t(h.width) * h.height * 4 * (h.wide ? 2 : 1);
}

TextureImage decode_image(const unsigned char* bytes, size_t size, const std::string& what) {
  switch (sniff(bytes, size, what)) {
    case Format::png:
      return PngDecoder(bytes, size, what).decode();
    case Format::jpeg:
      return JpegDecoder(bytes, size, what).decode();
    case Format::webp:
      break;
  }
  return WebpDecoder(bytes, size, what).decode();
}

}  // namespace dacrt
