// Reading a glTF file into tinygltf's model (io/gltf/file.h): the GLB container, the JSON checks
// (nesting depth, then io/gltf/schema.h), external files, and tinygltf's messages made one line.
#include "io/gltf/file.h"

#include <bit>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string_view>
#include <vector>

#include "io/gltf/schema.h"
#include "util/error.h"
#include "util/paths.h"

namespace dacrt {

namespace {

// tinygltf's messages are multi-line and may quote a whole data URI: one short line of them, the
// lines joined by "; ".
std::string summary(std::string_view text, size_t max_chars = 400) {
  std::string out;
  for (char c : text) {
    bool newline = c == '\n' || c == '\r';
    if (!newline)
      out += c;
    else if (!out.empty() && out.back() != ' ')
      out += "; ";
  }
  while (!out.empty() && (out.back() == ' ' || out.back() == ';')) out.pop_back();
  if (out.size() > max_chars) out = out.substr(0, max_chars) + "...";
  return out;
}

using Bytes = std::vector<unsigned char>;

// tinygltf converts `extras` and `extensions` to its Value type recursively; bounding the JSON
// nesting keeps a hostile file from overflowing the stack there.
constexpr int kMaxJsonDepth = 512;

Bytes read_file(const std::string& path) {
  check_input_file(path, "file");
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw Error(path + ": file cannot be opened: " + std::strerror(errno));
  std::streamoff size = in.tellg();
  // tinygltf takes sizes as unsigned int (and GLB lengths are 32-bit).
  if (size < 0 || uint64_t(size) > std::numeric_limits<uint32_t>::max())
    throw Error(path + ": file is larger than 4 GiB");
  Bytes data(static_cast<size_t>(size));
  in.seekg(0);
  if (!in.read(reinterpret_cast<char*>(data.data()), size))
    throw Error(path + ": file cannot be read");
  if (data.empty()) throw Error(path + ": file is empty");
  return data;
}

uint32_t le32(const unsigned char* p) {
  return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

// tinygltf 2.7 lets the BIN chunk end 8 bytes past the data (its bounds check forgets the chunk
// header), so the GLB container is checked here first. Returns the JSON chunk's size.
size_t check_glb(const std::string& path, const Bytes& data) {
  auto bad = [&](const std::string& what) { throw Error(path + ": GLB " + what); };
  if (data.size() < 20) bad("header is truncated (" + std::to_string(data.size()) + " bytes)");
  uint32_t version = le32(&data[4]), length = le32(&data[8]);
  if (version != 2) bad("version " + std::to_string(version) + " is not 2");
  if (length > data.size())
    bad("length " + std::to_string(length) + " exceeds the file size " +
        std::to_string(data.size()));
  uint64_t json_size = le32(&data[12]), json_end = 20 + json_size;
  if (le32(&data[16]) != 0x4E4F534Au) bad("chunk 0 is not JSON");
  if (json_end > length)
    bad("JSON chunk overruns the file (ends at " + std::to_string(json_end) + ")");
  if (json_end < length) {  // a BIN chunk follows
    if (json_end + 8 > length) bad("BIN chunk header is truncated");
    uint64_t bin_end = json_end + 8 + le32(&data[json_end]);
    if (bin_end > length)
      bad("BIN chunk overruns the file (ends at " + std::to_string(bin_end) + ", file has " +
          std::to_string(length) + " bytes)");
  }
  return static_cast<size_t>(json_size);
}

int json_depth(const unsigned char* s, size_t n) {
  int depth = 0, deepest = 0;
  bool in_string = false;
  for (size_t i = 0; i < n; ++i) {
    unsigned char c = s[i];
    if (in_string) {
      i += c == '\\';  // skip the escaped character
      in_string = c != '"';
    } else {
      in_string = c == '"';
      depth += (c == '[' || c == '{') - (c == ']' || c == '}');
      deepest = std::max(deepest, depth);
    }
  }
  return deepest;
}

// Images are decoded later, and only those a material uses (io/gltf/images.cpp): here the encoded
// bytes of a data URI or an external file are kept in Image::image as they are. Images in a
// bufferView are left alone: tinygltf passes them without checking the view against its buffer, and
// the loader reads them through its own bounds checks. A missing external file leaves the image
// empty.
bool keep_encoded_image(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                        const unsigned char* bytes, int size, void*) {
  if (image->bufferView == -1 && bytes && size > 0) image->image.assign(bytes, bytes + size);
  return true;
}

// Buffer and image URIs may name any path. tinygltf tests existence with fopen, which blocks
// forever on a FIFO: accept only regular files.
bool regular_file_exists(const std::string& path, void*) {
  std::error_code ec;
  return std::filesystem::is_regular_file(path, ec);
}

// tinygltf reports failures as text only. Buffers are parsed first and in order, so a file or
// data-URI failure is about buffer number model.buffers.size() (the ones before it succeeded).
[[noreturn]] void parse_failed(const std::string& path, const tinygltf::Model& model,
                               const std::string& err, const std::string& warn) {
  std::string why = summary(err.empty() ? warn : err);
  if (why.empty()) why = "tinygltf gives no reason";
  if (err.find("json.exception") != std::string::npos || err.find("JSON string too short") == 0)
    throw Error(path + ": JSON does not parse: " + why);
  for (const char* buffer_error : {"File not found", "File read error", "File is empty",
                                   "File size mismatch", "in Buffer", "`Buffer'", "binary size"})
    if (err.find(buffer_error) != std::string::npos)
      throw Error(path + ": buffer " + std::to_string(model.buffers.size()) +
                  " cannot be read: " + why);
  throw Error(path + ": is not valid glTF: " + why);
}

// tinygltf's file reader, noting each file it reads (external buffers and images) in the
// std::vector<std::string> at `files`.
bool read_and_note(std::vector<unsigned char>* out, std::string* err, const std::string& file,
                   void* files) {
  static_cast<std::vector<std::string>*>(files)->push_back(file);
  return tinygltf::ReadWholeFile(out, err, file, nullptr);
}

tinygltf::Model parse(const std::string& path, const Bytes& data, std::vector<std::string>* files) {
  bool binary = data.size() >= 4 && std::memcmp(data.data(), "glTF", 4) == 0;
  std::string ext = std::filesystem::path(path).extension().string();
  if (!binary && (ext == ".glb" || ext == ".GLB"))
    throw Error(path + ": GLB magic \"glTF\" is missing");

  size_t json_size = binary ? check_glb(path, data) : data.size();
  const unsigned char* json_text = data.data() + (binary ? 20 : 0);
  if (json_depth(json_text, json_size) > kMaxJsonDepth)
    throw Error(path + ": JSON nests deeper than " + std::to_string(kMaxJsonDepth) + " levels");
  // The schema is checked on the JSON as nlohmann reads it (tinygltf parses it again with the same
  // library, so both see the same values), before tinygltf turns what is mistyped into defaults.
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(json_text, json_text + json_size);
  } catch (const nlohmann::json::exception& e) {
    throw Error(path + ": JSON does not parse: " + summary(e.what()));
  }
  for (const std::string& warning : check_gltf_schema(path, doc))
    std::cerr << "warning: " << warning << "\n";

  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(&keep_encoded_image, nullptr);
  std::vector<std::string> read;
  loader.SetFsCallbacks({&regular_file_exists, &tinygltf::ExpandFilePath, &read_and_note,
                         &tinygltf::WriteWholeFile, &read});
  tinygltf::Model model;
  std::string err, warn;  // warnings only concern images, which the loader checks itself
  std::string base_dir = std::filesystem::path(path).parent_path().string();
  auto size = static_cast<unsigned int>(data.size());
  bool ok =
      binary ? loader.LoadBinaryFromMemory(&model, &err, &warn, data.data(), size, base_dir)
             : loader.LoadASCIIFromString(
                   &model, &err, &warn, reinterpret_cast<const char*>(data.data()), size, base_dir);
  if (!ok) parse_failed(path, model, err, warn);
  if (files) *files = std::move(read);
  return model;
}

}  // namespace

tinygltf::Model read_gltf_model(const std::string& path, std::vector<std::string>* files) {
  Bytes data = read_file(path);
  return parse(path, data, files);  // a GLB's BIN chunk is copied into model.buffers
}

tinygltf::Model parse_gltf_model(const std::string& path, const unsigned char* data, size_t size,
                                 std::vector<std::string>* files) {
  return parse(path, Bytes(data, data + size), files);
}

}  // namespace dacrt
