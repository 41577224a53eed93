// A fingerprint of input files: FNV-1a (64-bit) over their bytes in order, eight at a time (as
// little-endian words: every render computes it at start-up, and byte by byte it took 25 ms of a
// 16 MB scene's 430 ms load), each file's length hashed folded in first so that moving bytes from one
// file to the next changes it. Not cryptographic: it tells whether renders were made from the
// same scene, not whether someone forged one.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace dacrt {

// A file a command read, and how much of it: its first `bytes` (an external buffer's byteLength
// of a larger file, none of an image the render does not use), or all of it (no value).
struct FileRead {
  std::string path;
  std::optional<uint64_t> bytes;
};

// The fingerprint of what was read of each file: a file's bytes beyond what its reader took
// are not hashed (nor read), so that a 36-byte buffer in a 2 GiB file costs 36 bytes. Throws
// Error naming a file that cannot be read, or is now shorter than what was read of it.
uint64_t hash_files(const std::vector<FileRead>& files);
// "fnv1a64w:0123456789abcdef".
std::string hash_text(uint64_t hash);

}  // namespace dacrt
