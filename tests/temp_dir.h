// TempDir: a fresh directory under the system temp dir for one test, removed with everything in
// it when the test's scope ends.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <string>

namespace dacrt::test {

class TempDir {
 public:
  explicit TempDir(const std::string& name = "test") {
    static int counter = 0;
    path_ = std::filesystem::temp_directory_path() /
            ("dacrt-" + std::to_string(getpid()) + "-" + std::to_string(counter++) + "-" + name);
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  // The path of `file` inside this directory, as a string.
  std::string operator/(const std::string& file) const { return (path_ / file).string(); }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace dacrt::test
