// The files a command names: every input must be a regular file (a FIFO blocks its reader
// forever, a device never ends), and the outputs must be distinct files, none of them an input.
// Paths are compared as files, not as text: `out.exr`, `./out.exr` and a symbolic or hard link to
// it are the same file.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace dacrt {

// Throws Error("<path>: <what> does not exist" / "... is a FIFO, not a regular file") unless
// `path` names a regular file (after following symbolic links). `what` says what the file is for
// ("environment map", "OCIO config").
void check_input_file(const std::string& path, const std::string& what);

// "a directory", "a FIFO", "a character device", "a file"…, for messages about what a path is.
const char* file_kind(const std::filesystem::file_status& status);

// The absolute path with its symbolic links resolved, `.` and `..` removed, for a file that may
// not exist yet: a dangling link is followed to the file it will create.
std::filesystem::path resolved_path(const std::string& path);

// A file named on the command line: the option that names it and the path.
struct NamedFile {
  std::string option;  // "-o", "--stats", "the scene", …
  std::string path;
};

// Whether two paths name the same file: the same inode when both exist, else the same absolute
// path with symbolic links in its existing part resolved.
bool same_file(const std::string& a, const std::string& b);

// Throws Error naming the first output that names the same file as an earlier output ("--stats
// out.exr is the same file as -o out.exr") or as an input ("-o scene.gltf would overwrite the
// scene"). Empty paths are skipped.
void check_outputs(const std::vector<NamedFile>& outputs, const std::vector<NamedFile>& inputs);

// "a,b,c" → {a, b, c}; empty parts are dropped.
std::vector<std::string> split_list(const std::string& list);
// out.exr → out.NAME.exr (empty stays empty): one output of several backends.
std::string with_backend(const std::string& path, const std::string& backend);
// out.exr → out.0007.exr for frame 7 (empty stays empty).
std::string with_frame(const std::string& path, int frame);

}  // namespace dacrt
