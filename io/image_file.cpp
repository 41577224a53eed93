// Images written by their names (see image_file.h): PNG and HDR through stb_image_write (its
// implementation is libstb's, shared with tinygltf), JPEG through libjpeg-turbo, EXR through
// io/exr.cpp.
#include "dacrt/io/image_file.h"

// clang-format off
#include <cstdio>  // before jpeglib.h, which uses size_t and FILE without including them
#include <jpeglib.h>
// clang-format on
#include <stb_image_write.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <csetjmp>
#include <cstdlib>
#include <filesystem>

#include "dacrt/util/atomic_file.h"
#include "dacrt/util/error.h"

namespace dacrt {

namespace {

// RGBE holds exponents up to 2^127; anything this bright is far beyond any use of the file.
constexpr float kMaxHdrValue = 1e30f;

void write_bytes(const std::string& path, const char* what,
                 const std::vector<unsigned char>& bytes) {
  write_atomically(path, what, [&](std::ostream& out) {
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  });
}

// stb_image_write's callback: the encoded bytes appended to a vector.
void append_bytes(void* context, void* data, int size) {
  auto* bytes = static_cast<std::vector<unsigned char>*>(context);
  bytes->insert(bytes->end(), static_cast<unsigned char*>(data),
                static_cast<unsigned char*>(data) + size);
}

uint8_t alpha_byte(float a) {
  if (!(a > 0.f)) return 0;  // NaN too
  return uint8_t(std::lround(std::min(a, 1.f) * 255.f));
}

void write_png_file(const std::string& path, const Image& image, const DisplayOptions& display,
                    std::span<const float> alpha) {
  std::vector<uint8_t> rgb = display_bytes(image, display);
  if (alpha.empty()) return write_png(path, image.width, image.height, rgb);
  const size_t pixels = size_t(image.width) * size_t(image.height);
  std::vector<uint8_t> rgba(4 * pixels);
  for (size_t p = 0; p < pixels; ++p) {
    std::copy_n(&rgb[3 * p], 3, &rgba[4 * p]);
    rgba[4 * p + 3] = alpha_byte(alpha[p]);
  }
  std::vector<unsigned char> png;
  if (!stbi_write_png_to_func(append_bytes, &png, image.width, image.height, 4, rgba.data(),
                              4 * image.width))
    throw Error("cannot write PNG '" + path + "': encoding failed");
  write_bytes(path, "PNG", png);
}

// libjpeg's state for one image: C data only, so that the error handler's longjmp may leave it.
struct JpegWrite {
  jpeg_compress_struct cinfo;
  jpeg_error_mgr errors;
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX] = "";
  unsigned char* out = nullptr;
  unsigned long size = 0;
};

void jpeg_write_failed(j_common_ptr cinfo) {
  auto* w = reinterpret_cast<JpegWrite*>(cinfo);  // cinfo is its first member
  cinfo->err->format_message(cinfo, w->message);
  std::longjmp(w->jump, 1);
}

// Encodes in one function that armed the jump, touching only C data after it.
bool encode_jpeg(JpegWrite& w, const uint8_t* rgb, int width, int height) {
  w.cinfo.err = jpeg_std_error(&w.errors);
  w.errors.error_exit = jpeg_write_failed;
  if (setjmp(w.jump)) return false;
  jpeg_create_compress(&w.cinfo);
  jpeg_mem_dest(&w.cinfo, &w.out, &w.size);
  w.cinfo.image_width = JDIMENSION(width);
  w.cinfo.image_height = JDIMENSION(height);
  w.cinfo.input_components = 3;
  w.cinfo.in_color_space = JCS_RGB;
  jpeg_set_defaults(&w.cinfo);
  jpeg_set_quality(&w.cinfo, 95, TRUE);
  // No chroma subsampling: a render's edges in colour stay sharp.
  for (int c = 0; c < w.cinfo.num_components; ++c)
    w.cinfo.comp_info[c].h_samp_factor = w.cinfo.comp_info[c].v_samp_factor = 1;
  jpeg_start_compress(&w.cinfo, TRUE);
  while (w.cinfo.next_scanline < w.cinfo.image_height) {
    JSAMPROW row = const_cast<JSAMPROW>(rgb + size_t(w.cinfo.next_scanline) * 3 * size_t(width));
    jpeg_write_scanlines(&w.cinfo, &row, 1);
  }
  jpeg_finish_compress(&w.cinfo);
  return true;
}

void write_jpeg_file(const std::string& path, const Image& image, const DisplayOptions& display) {
  const std::vector<uint8_t> rgb = display_bytes(image, display);
  JpegWrite w{};
  const bool ok = encode_jpeg(w, rgb.data(), image.width, image.height);
  std::vector<unsigned char> bytes;
  if (ok) bytes.assign(w.out, w.out + w.size);
  jpeg_destroy_compress(&w.cinfo);
  std::free(w.out);
  if (!ok) throw Error("cannot write JPEG '" + path + "': " + std::string(w.message));
  write_bytes(path, "JPEG", bytes);
}

void write_hdr_file(const std::string& path, const Image& image) {
  // RGBE has no sign and no NaN: such values are 0, as in the preview.
  std::vector<float> rgb(image.rgb.size());
  std::transform(image.rgb.begin(), image.rgb.end(), rgb.begin(),
                 [](float v) { return v > 0.f ? std::min(v, kMaxHdrValue) : 0.f; });
  std::vector<unsigned char> bytes;
  if (!stbi_write_hdr_to_func(append_bytes, &bytes, image.width, image.height, 3, rgb.data()))
    throw Error("cannot write HDR '" + path + "': encoding failed");
  write_bytes(path, "HDR", bytes);
}

void write_exr_file(const std::string& path, const Image& image, const ExrMetadata& metadata,
                    std::span<const float> alpha) {
  if (alpha.empty()) return write_exr(path, image, metadata);
  const size_t pixels = size_t(image.width) * size_t(image.height);
  std::vector<Channel> channels = {{"R", {}}, {"G", {}}, {"B", {}}, {"A", {}}};
  for (int c = 0; c < 3; ++c) {
    channels[c].values.resize(pixels);
    for (size_t p = 0; p < pixels; ++p) channels[c].values[p] = image.rgb[3 * p + c];
  }
  channels[3].values.assign(alpha.begin(), alpha.end());
  write_exr(path, image.width, image.height, channels, metadata);
}

}  // namespace

std::optional<ImageFormat> image_format(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  if (ext == ".exr") return ImageFormat::exr;
  if (ext == ".png") return ImageFormat::png;
  if (ext == ".jpg" || ext == ".jpeg") return ImageFormat::jpeg;
  if (ext == ".hdr") return ImageFormat::hdr;
  return std::nullopt;
}

const char* image_extensions() {
  return ".exr, .png, .jpg, .jpeg or .hdr";
}

const char* format_name(ImageFormat format) {
  switch (format) {
    case ImageFormat::exr:
      return "EXR";
    case ImageFormat::png:
      return "PNG";
    case ImageFormat::jpeg:
      return "JPEG";
    case ImageFormat::hdr:
      return "HDR";
  }
  return "?";
}

bool holds_display_values(ImageFormat format) {
  return format == ImageFormat::png || format == ImageFormat::jpeg;
}

ImageFormat output_format(const std::string& option, const std::string& path) {
  if (const std::optional<ImageFormat> format = image_format(path)) return *format;
  const std::string ext = std::filesystem::path(path).extension().string();
  throw UsageError(option + " " + path + ": " +
                   (ext.empty() ? std::string("no extension") : "unknown extension '" + ext + "'") +
                   " (the format follows the name: " + image_extensions() + ")");
}

std::vector<uint8_t> display_bytes(const Image& image, const DisplayOptions& options) {
  const std::vector<float> display = to_display(image, options);
  std::vector<uint8_t> bytes(display.size());
  // Round to nearest: values are already clamped to [0, 1].
  std::transform(display.begin(), display.end(), bytes.begin(),
                 [](float v) { return uint8_t(std::lround(v * 255.f)); });
  return bytes;
}

void write_image(const std::string& path, const Image& image, const DisplayOptions& display,
                 const ExrMetadata& metadata, std::span<const float> alpha,
                 const std::string& option) {
  const ImageFormat format = output_format(option, path);
  const char* name = format_name(format);
  if (image.width <= 0 || image.height <= 0 ||
      image.rgb.size() != size_t(3) * size_t(image.width) * size_t(image.height))
    throw Error(std::string("cannot write ") + name + " '" + path +
                "': the image is empty or its size is wrong");
  if (!alpha.empty() && alpha.size() != size_t(image.width) * size_t(image.height))
    throw Error(std::string("cannot write ") + name + " '" + path +
                "': " + std::to_string(alpha.size()) + " alpha values for " +
                std::to_string(image.width) + "x" + std::to_string(image.height) + " pixels");
  switch (format) {
    case ImageFormat::exr:
      return write_exr_file(path, image, metadata, alpha);
    case ImageFormat::png:
      return write_png_file(path, image, display, alpha);
    case ImageFormat::jpeg:
      return write_jpeg_file(path, image, display);
    case ImageFormat::hdr:
      return write_hdr_file(path, image);
  }
}

}  // namespace dacrt
