#include "dacrt/util/paths.h"

#include <sys/stat.h>

#include <filesystem>
#include <algorithm>
#include <cstdio>
#include <map>
#include <system_error>

#include "dacrt/util/error.h"

namespace dacrt {

namespace fs = std::filesystem;

const char* file_kind(const fs::file_status& status) {
  switch (status.type()) {
    case fs::file_type::directory:
      return "a directory";
    case fs::file_type::fifo:
      return "a FIFO";
    case fs::file_type::socket:
      return "a socket";
    case fs::file_type::character:
      return "a character device";
    case fs::file_type::block:
      return "a block device";
    case fs::file_type::regular:
      return "a file";
    default:
      return "not a regular file";
  }
}

fs::path resolved_path(const std::string& path) {
  std::error_code ec;
  fs::path p = fs::absolute(path, ec);
  for (int hops = 0; hops < 40 && fs::is_symlink(fs::symlink_status(p, ec)); ++hops) {
    const fs::path target = fs::read_symlink(p, ec);
    if (ec) break;
    p = target.is_absolute() ? target : p.parent_path() / target;
  }
  const fs::path canonical = fs::weakly_canonical(p, ec);
  return ec ? p.lexically_normal() : canonical;
}

void check_input_file(const std::string& path, const std::string& what) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (!fs::exists(status)) throw Error(path + ": " + what + " does not exist");
  if (!fs::is_regular_file(status))
    throw Error(path + ": " + what + " is " + file_kind(status) + ", not a regular file");
}

bool same_file(const std::string& a, const std::string& b) {
  struct stat sa {
  }, sb{};
  if (::stat(a.c_str(), &sa) == 0 && ::stat(b.c_str(), &sb) == 0)
    return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
  return resolved_path(a) == resolved_path(b);
}

namespace {

// What same_file compares, as one value: the device and inode of a file that exists, else its
// resolved path. (Two paths of which one exists are never one file: resolving the existing one
// gives that file's own path, which the other, not existing, cannot have.)
std::string file_identity(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0)
    return "inode " + std::to_string(st.st_dev) + ":" + std::to_string(st.st_ino);
  return "path " + resolved_path(path).string();
}

}  // namespace

void check_outputs(const std::vector<NamedFile>& outputs, const std::vector<NamedFile>& inputs) {
  // Each path resolved once, then looked up: a sequence of 100 000 frames names 200 000 outputs.
  std::map<std::string, const NamedFile*> input_at, output_at;
  for (const NamedFile& in : inputs)
    if (!in.path.empty()) input_at.emplace(file_identity(in.path), &in);
  for (const NamedFile& out : outputs) {
    if (out.path.empty()) continue;
    const std::string identity = file_identity(out.path);
    if (const auto in = input_at.find(identity); in != input_at.end())
      throw Error(out.option + " " + out.path + " would overwrite " + in->second->option +
                  (in->second->path == out.path ? "" : " " + in->second->path));
    const auto [earlier, first] = output_at.emplace(identity, &out);
    if (!first)
      throw Error(out.option + " " + out.path + " is the same file as " + earlier->second->option +
                  (earlier->second->path == out.path ? "" : " " + earlier->second->path) +
                  ": each output needs its own");
  }
}

std::vector<std::string> split_list(const std::string& list) {
  std::vector<std::string> parts;
  size_t begin = 0;
  while (begin <= list.size()) {
    const size_t comma = std::min(list.find(',', begin), list.size());
    if (comma > begin) parts.push_back(list.substr(begin, comma - begin));
    begin = comma + 1;
  }
  return parts;
}

std::string with_backend(const std::string& path, const std::string& backend) {
  if (path.empty()) return path;
  std::filesystem::path p(path);
  return (p.parent_path() / (p.stem().string() + "." + backend + p.extension().string())).string();
}

std::string with_frame(const std::string& path, int frame) {
  char number[16];
  std::snprintf(number, sizeof number, "%04d", frame);
  return with_backend(path, number);
}

}  // namespace dacrt
