#include "dacrt/util/file_hash.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <vector>

#include "dacrt/util/error.h"

namespace dacrt {
namespace {

constexpr uint64_t fnv_offset = 0xcbf29ce484222325ull, fnv_prime = 0x100000001b3ull;

// Whole words, then the bytes left over (only at a file's end: the chunks are whole MiB).
void mix(uint64_t& h, const unsigned char* bytes, size_t n) {
  size_t i = 0;
  for (; i + 8 <= n; i += 8) {
    uint64_t word = 0;
    for (int k = 0; k < 8; ++k) word |= uint64_t(bytes[i + size_t(k)]) << (8 * k);
    h = (h ^ word) * fnv_prime;
  }
  for (; i < n; ++i) h = (h ^ bytes[i]) * fnv_prime;
}

}  // namespace

uint64_t hash_files(const std::vector<FileRead>& files) {
  uint64_t h = fnv_offset;
  std::vector<char> buffer(size_t(1) << 20);
  for (const FileRead& file : files) {
    const std::string& path = file.path;
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path + ": cannot be read: " + std::strerror(errno));
    in.seekg(0, std::ios::end);
    const uint64_t whole = uint64_t(std::streamoff(in.tellg()));
    in.seekg(0);
    if (file.bytes && *file.bytes > whole)
      throw Error(path + ": has " + std::to_string(whole) + " bytes, fewer than the " +
                  std::to_string(*file.bytes) + " read of it (it changed while read?)");
    const uint64_t size = file.bytes.value_or(whole);
    unsigned char length[8];
    for (int k = 0; k < 8; ++k) length[k] = (unsigned char)(size >> (8 * k));
    mix(h, length, 8);
    uint64_t read = 0;
    while (read < size) {
      in.read(buffer.data(), std::streamsize(std::min<uint64_t>(buffer.size(), size - read)));
      const std::streamsize got = in.gcount();
      if (got <= 0) throw Error(path + ": cannot be read to its end (it changed while read?)");
      mix(h, reinterpret_cast<const unsigned char*>(buffer.data()), size_t(got));
      read += uint64_t(got);
    }
  }
  return h;
}

std::string hash_text(uint64_t hash) {
  char text[32];
  std::snprintf(text, sizeof text, "fnv1a64w:%016llx", (unsigned long long)hash);
  return text;
}

}  // namespace dacrt
