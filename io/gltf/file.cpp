// Reading a glTF file into tinygltf's model (io/gltf/file.h): the GLB container, the JSON checks
// (nesting depth, then io/gltf/schema.h), external files, and tinygltf's messages made one line.
#include "dacrt/io/gltf/file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <bit>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string_view>
#include <vector>

#include "dacrt/io/gltf/file_json.h"
#include "dacrt/io/gltf/schema.h"
#include "dacrt/util/error.h"
#include "dacrt/util/memory.h"
#include "dacrt/util/paths.h"
#include "dacrt/util/text.h"

namespace dacrt {

namespace {

using gltf_json::array_size;
using gltf_json::index_at;
using gltf_json::is_data_uri;
using gltf_json::member;
using gltf_json::used_images;

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

// What the file's external references ask of tinygltf's file reader, worked out from the JSON
// before tinygltf runs: each external buffer's byteLength (the spec: its file holds at least that
// many bytes, and more is allowed, so only byteLength bytes are read), and which images the
// render uses (the others are never read, and their encoded bytes not kept).
struct ExternalFiles {
  struct Buffer {
    std::string path;  // its URI's path
    uint64_t byte_length;
    std::string name;  // "buffer 2 (a.bin)"
  };
  // Every buffer with a URI, in order. tinygltf reads the external ones first, in order, once
  // each: a call is for the first buffer from `next_buffer` on with its path, else for an image.
  // (Paths are those tinygltf makes of URIs relative to the glTF file.)
  std::vector<Buffer> buffers;
  size_t next_buffer = 0;
  std::set<std::string> image_paths, used_image_paths;  // of all images, of those the render uses
  std::map<std::string, std::string> image_name;        // "image 0 (b.png)" by path
  std::vector<bool> image_used;                         // by image index
  std::set<std::string> uri_paths;                      // of every buffer and image
  uint64_t buffer_bytes = 0, available_memory = 0;
  std::vector<FileRead> noted;  // every external file the scene names and tinygltf finds
  std::string error;               // the first failure, a message after the scene's path
};

// tinygltf 2.7's dlib::urldecode ('+' is a space, %XX a byte, bad hex digits 0), for the same path.
std::string url_decode(const std::string& s) {
  auto hex = [](unsigned char c) -> unsigned {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return 0;
  };
  std::string out;
  for (size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '+') {
      out += ' ';
    } else if (s[i] == '%' && s.size() > i + 2) {
      out += char(hex(static_cast<unsigned char>(s[i + 1])) << 4 |
                  hex(static_cast<unsigned char>(s[i + 2])));
      i += 2;
    } else {
      out += s[i];
    }
  }
  return out;
}

// The path tinygltf makes of a URI relative to the glTF file (it would then try the working
// directory, which regular_file_exists refuses).
std::string uri_path(const std::string& base_dir, const std::string& uri) {
  const std::string file = url_decode(uri);
  return base_dir.empty() ? file : base_dir.back() == '/' ? base_dir + file : base_dir + "/" + file;
}

// Works out what the file's buffers and images ask for (ExternalFiles).
void plan_external_files(const nlohmann::json& doc, const std::string& base_dir, int scene,
                         const std::string& variant, ExternalFiles& files) {
  auto named = [](const char* kind, size_t i, const nlohmann::json& uri) {
    return std::string(kind) + " " + std::to_string(i) + " (" +
           one_line(uri.get_ref<const std::string&>().substr(0, 200)) + ")";
  };
  const nlohmann::json& buffers = member(doc, "buffers");
  for (size_t i = 0; i < array_size(doc, "buffers"); ++i) {
    const nlohmann::json& uri = member(buffers[i], "uri");
    const nlohmann::json& length = member(buffers[i], "byteLength");
    if (!uri.is_string() || !length.is_number_unsigned()) continue;  // the schema refused these
    // Data URIs are no files (and may be hundreds of MB: not copied into paths).
    if (is_data_uri(uri)) continue;
    files.buffers.push_back({uri_path(base_dir, uri.get_ref<const std::string&>()),
                             length.get<uint64_t>(), named("buffer", i, uri)});
    files.uri_paths.insert(files.buffers.back().path);
  }
  files.image_used = used_images(doc, scene, variant);
  const nlohmann::json& images = member(doc, "images");
  for (size_t i = 0; i < array_size(doc, "images"); ++i) {
    const nlohmann::json& uri = member(images[i], "uri");
    // Data URIs are no files: tinygltf decodes some, decode_data_uris the others.
    if (!uri.is_string() || is_data_uri(uri)) continue;
    const std::string path = uri_path(base_dir, uri.get_ref<const std::string&>());
    files.uri_paths.insert(path);
    files.image_paths.insert(path);
    if (files.image_used[i]) files.used_image_paths.insert(path);
    files.image_name.emplace(path, named("image", i, uri));
  }
}

// Reads `want` bytes of regular file `file` into `out` (all of it when `want` is nothing),
// checking its size first; false with `why` set if it is not a regular file, is shorter, needs
// more than `max_size` bytes (`max_what` says what that is), or cannot be read.
bool read_bytes(const std::string& file, std::optional<uint64_t> want, uint64_t max_size,
                const std::string& max_what, std::vector<unsigned char>& out, std::string& why) {
  // O_NONBLOCK: a FIFO swapped in after tinygltf's existence check must not block the open.
  const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) return why = std::strerror(errno), false;
  struct FdCloser {
    int fd;
    ~FdCloser() { ::close(fd); }
  } closer{fd};
  struct stat st;
  if (::fstat(fd, &st) != 0) return why = std::strerror(errno), false;
  if (!S_ISREG(st.st_mode)) return why = "it is not a regular file", false;
  const uint64_t size = uint64_t(st.st_size);
  if (want && size < *want)
    return why = "its file has " + std::to_string(size) + " bytes, fewer than its byteLength " +
                 std::to_string(*want),
           false;
  const uint64_t n = want ? *want : size;
  if (n > max_size)
    return why = "it would take " + format_bytes(n) + ", more than " + max_what, false;
  out.resize(size_t(n));
  for (size_t done = 0; done < n;) {
    const ssize_t got = ::pread(fd, out.data() + done, n - done, off_t(done));
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) {
      why = got < 0 ? std::strerror(errno) : "the file ended early";
      out.clear();
      return false;
    }
    done += size_t(got);
  }
  return true;
}

// tinygltf's file reader (its ReadWholeFile reads a whole file, however large, before checking
// its size): an external buffer's byteLength bytes, the whole file of an image the render uses,
// nothing of an image it does not use (tinygltf then keeps the image without data, which the
// loader never looks at). Every file is noted in ExternalFiles::noted.
bool read_external(std::vector<unsigned char>* out, std::string* err, const std::string& file,
                   void* user) {
  ExternalFiles& files = *static_cast<ExternalFiles*>(user);
  files.noted.push_back({file, 0});  // the bytes read are set once they are
  out->clear();
  auto fail = [&](const std::string& what) {
    if (files.error.empty()) files.error = what;
    if (err) *err = what;
    return false;
  };
  std::string why;
  for (size_t b = files.next_buffer; b < files.buffers.size(); ++b) {
    const ExternalFiles::Buffer& buffer = files.buffers[b];
    if (file != buffer.path) continue;
    files.next_buffer = b + 1;
    // All buffers are held at once: their sum is bounded by the memory available.
    const uint64_t room = files.available_memory > files.buffer_bytes
                              ? files.available_memory - files.buffer_bytes
                              : 0;
    if (!read_bytes(file, buffer.byte_length, room,
                    "the " + format_bytes(room) + " of memory available" +
                        (files.buffer_bytes ? " besides the buffers before it" : ""),
                    *out, why))
      return fail(buffer.name + " cannot be read: " + why);
    files.buffer_bytes += out->size();
    files.noted.back().bytes = out->size();
    return true;
  }
  if (files.image_paths.count(file) && !files.used_image_paths.count(file))
    return true;  // an image the render does not use: not read
  // tinygltf hands the bytes on with an int size; decoded images are far smaller anyway.
  constexpr uint64_t kMaxImageFile = uint64_t(1) << 30;
  if (!read_bytes(file, std::nullopt, kMaxImageFile,
                  "the " + format_bytes(kMaxImageFile) + " an image file may have", *out, why)) {
    auto name = files.image_name.find(file);
    return fail((name != files.image_name.end() ? name->second : "file " + one_line(file)) +
                " cannot be read: " + why);
  }
  files.noted.back().bytes = out->size();
  return true;
}

// Images are decoded later, and only those a material uses (io/gltf/images.cpp): here the encoded
// bytes of a data URI or an external file are kept in Image::image as they are, for the images the
// render uses (ExternalFiles::image_used). Images in a bufferView are left alone: tinygltf passes
// them without checking the view against its buffer, and the loader reads them through its own
// bounds checks. A missing external file leaves the image empty.
bool keep_encoded_image(tinygltf::Image* image, const int index, std::string*, std::string*, int,
                        int, const unsigned char* bytes, int size, void* user) {
  const auto& used = static_cast<const ExternalFiles*>(user)->image_used;
  const bool needed = index < 0 || size_t(index) >= used.size() || used[size_t(index)];
  if (needed && image->bufferView == -1 && bytes && size > 0)
    image->image.assign(bytes, bytes + size);
  return true;
}

// tinygltf decodes only the data URIs of the types it knows (PNG, JPEG, BMP, GIF...), and takes
// the others (data:image/webp;base64,...) for file names: the base64 ones of the images the render
// uses are decoded here. Any other data URI leaves its image empty (the loader says so).
void decode_data_uris(const nlohmann::json& doc, const std::vector<bool>& image_used,
                      tinygltf::Model& model) {
  const nlohmann::json& images = member(doc, "images");
  for (size_t i = 0; i < model.images.size() && i < image_used.size(); ++i) {
    const nlohmann::json& uri = member(images[i], "uri");
    if (!image_used[i] || !uri.is_string()) continue;
    const std::string& text = uri.get_ref<const std::string&>();
    const size_t comma = text.find(',');
    if (!text.starts_with("data:") || comma == std::string::npos ||
        !std::string_view(text).substr(0, comma).ends_with(";base64") || tinygltf::IsDataURI(text))
      continue;
    std::string mime_type;
    tinygltf::DecodeDataURI(&model.images[i].image, mime_type,
                            "data:application/octet-stream;base64," + text.substr(comma + 1), 0,
                            false);
  }
}

// Buffer and image URIs may name any path. tinygltf tests existence with fopen, which blocks
// forever on a FIFO: accept only regular files. And only where the spec puts them, relative to
// the glTF file: tinygltf would then look in the working directory, and read whatever file of the
// user's has that name.
bool regular_file_exists(const std::string& path, void* user) {
  if (!static_cast<const ExternalFiles*>(user)->uri_paths.count(path)) return false;
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

// What tinygltf 2.7 refuses although the spec allows it, taken out of the JSON it parses and put
// back into its model after: primitive indices in an accessor without a bufferView (all zeros, or
// Draco's: KHR_draco_mesh_compression), and EXT_meshopt_compression's fallback buffers, which have
// no data (tinygltf would take a GLB's BIN chunk for them, or refuse a .gltf's buffer without a
// uri). A fallback buffer is given to tinygltf as one byte and left empty in the model.
struct Workarounds {
  std::vector<std::array<size_t, 3>> indices;  // mesh, primitive, accessor
  std::vector<size_t> fallback_buffers;
  bool any() const { return !indices.empty() || !fallback_buffers.empty(); }
};

// JSON has one number type: 1.0 is the integer 1 (the validator agrees), but tinygltf ignores an
// index or count written with a decimal point. Every whole number written so (within 2^53, where
// doubles are exact) becomes an integer literal. True when any did.
bool whole_numbers_as_integers(nlohmann::json& v) {
  bool changed = false;
  if (v.is_number_float()) {
    const double x = v.get<double>();
    if (x == std::floor(x) && std::fabs(x) <= 9007199254740992.0) {
      v = x < 0 ? nlohmann::json(int64_t(x)) : nlohmann::json(uint64_t(x));
      changed = true;
    }
  } else if (v.is_structured()) {
    for (nlohmann::json& child : v) changed |= whole_numbers_as_integers(child);
  }
  return changed;
}

Workarounds work_around_tinygltf(nlohmann::json& doc) {
  Workarounds w;
  auto array = [&](const char* key) -> nlohmann::json* {
    auto it = doc.find(key);
    return it != doc.end() && it->is_array() ? &*it : nullptr;
  };
  nlohmann::json *meshes = array("meshes"), *accessors = array("accessors"),
                 *buffers = array("buffers");
  if (meshes && accessors)
    for (size_t m = 0; m < meshes->size(); ++m) {
      auto primitives = (*meshes)[m].find("primitives");
      if (primitives == (*meshes)[m].end() || !primitives->is_array()) continue;
      for (size_t p = 0; p < primitives->size(); ++p) {
        nlohmann::json& prim = (*primitives)[p];
        auto indices = prim.find("indices");
        if (indices == prim.end() || !indices->is_number_unsigned()) continue;
        const size_t a = indices->get<size_t>();
        if (a >= accessors->size() || (*accessors)[a].contains("bufferView")) continue;
        w.indices.push_back({m, p, a});
        prim.erase("indices");
      }
    }
  if (buffers)
    for (size_t b = 0; b < buffers->size(); ++b) {
      nlohmann::json& buffer = (*buffers)[b];
      const nlohmann::json* x = nullptr;
      if (auto e = buffer.find("extensions"); e != buffer.end() && e->is_object())
        if (auto m = e->find("EXT_meshopt_compression"); m != e->end()) x = &*m;
      if (!x || !x->is_object() || x->value("fallback", false) != true || buffer.contains("uri"))
        continue;
      w.fallback_buffers.push_back(b);
      buffer["uri"] = "data:application/octet-stream;base64,AA==";
      buffer["byteLength"] = 1;
    }
  return w;
}

void restore(tinygltf::Model& model, const Workarounds& w) {
  for (const auto& [m, p, a] : w.indices) model.meshes[m].primitives[p].indices = int(a);
  for (size_t b : w.fallback_buffers) model.buffers[b].data.clear(), model.buffers[b].uri.clear();
}

// The file tinygltf is given after work_around_tinygltf changed its JSON: the new JSON, and for a
// GLB the chunks after the JSON chunk as they were.
Bytes rewritten(const Bytes& data, bool binary, size_t json_size, const nlohmann::json& doc) {
  std::string json = doc.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  if (!binary) return Bytes(json.begin(), json.end());
  json.append((4 - json.size() % 4) % 4, ' ');
  const size_t rest = 20 + json_size;
  Bytes out(data.begin(), data.begin() + 12);
  auto put32 = [&](uint32_t v) {
    for (int k = 0; k < 4; ++k) out.push_back(static_cast<unsigned char>(v >> (8 * k)));
  };
  put32(static_cast<uint32_t>(json.size()));
  put32(0x4E4F534Au);
  out.insert(out.end(), json.begin(), json.end());
  out.insert(
      out.end(), data.begin() + static_cast<std::ptrdiff_t>(std::min(rest, data.size())),
      data.begin() + static_cast<std::ptrdiff_t>(std::min<size_t>(le32(&data[8]), data.size())));
  const uint32_t length = static_cast<uint32_t>(out.size());
  for (int k = 0; k < 4; ++k) out[8 + size_t(k)] = static_cast<unsigned char>(length >> (8 * k));
  return out;
}

tinygltf::Model parse(const std::string& path, const Bytes& original, int scene,
                      std::vector<FileRead>* files, const std::string& variant) {
  const Bytes* input = &original;
  Bytes changed;
  const Bytes& data = original;
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
  const SchemaCheck schema = check_gltf_schema(path, doc);
  for (const std::string& warning : schema.warnings) print_message("warning: " + warning);
  const bool whole_numbers = schema.whole_floats && whole_numbers_as_integers(doc);
  const Workarounds workarounds = work_around_tinygltf(doc);
  if (workarounds.any() || whole_numbers) {
    changed = rewritten(data, binary, json_size, doc);
    input = &changed;
  }

  const std::string base_dir = std::filesystem::path(path).parent_path().string();
  ExternalFiles external;
  external.available_memory = available_memory();
  plan_external_files(doc, base_dir, scene, variant, external);
  // The buffers' data URIs are tinygltf's to decode (from the text it parses): this copy of
  // them, as large as the file, goes before tinygltf makes its own.
  if (auto buffers = doc.find("buffers"); buffers != doc.end() && buffers->is_array())
    for (nlohmann::json& buffer : *buffers)
      if (auto uri = buffer.find("uri"); uri != buffer.end() && is_data_uri(*uri)) *uri = "data:";

  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(&keep_encoded_image, &external);
  loader.SetFsCallbacks({&regular_file_exists, &tinygltf::ExpandFilePath, &read_external,
                         &tinygltf::WriteWholeFile, &external});
  tinygltf::Model model;
  std::string err, warn;  // warnings only concern images, which the loader checks itself
  auto size = static_cast<unsigned int>(input->size());
  bool ok = binary ? loader.LoadBinaryFromMemory(&model, &err, &warn, input->data(), size, base_dir)
                   : loader.LoadASCIIFromString(&model, &err, &warn,
                                                reinterpret_cast<const char*>(input->data()), size,
                                                base_dir);
  if (!external.error.empty()) throw Error(path + ": " + external.error);
  if (!ok) parse_failed(path, model, err, warn);
  restore(model, workarounds);
  decode_data_uris(doc, external.image_used, model);
  if (files) *files = std::move(external.noted);
  return model;
}

}  // namespace

tinygltf::Model read_gltf_model(const std::string& path, int scene, std::vector<FileRead>* files,
                                const std::string& variant) {
  Bytes data = read_file(path);
  // A GLB's BIN chunk is copied into model.buffers.
  return parse(path, data, scene, files, variant);
}

tinygltf::Model parse_gltf_model(const std::string& path, const unsigned char* data, size_t size,
                                 int scene, std::vector<FileRead>* files,
                                 const std::string& variant) {
  return parse(path, Bytes(data, data + size), scene, files, variant);
}

}  // namespace dacrt
