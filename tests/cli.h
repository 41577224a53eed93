// Running the dacrt executable from a test, as a user would: its exit code, stderr and stdout.
#pragma once

#include <doctest/doctest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "temp_dir.h"

namespace dacrt::test {

namespace fs = std::filesystem;

struct Run {
  int code;
  std::string err, out;
};

inline std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// `dacrt ARGS` through the shell, after `before` (environment assignments, `ulimit -f 20;`…).
// stdout goes to `stdout_to` when given (then Run::out is empty), else it is captured.
inline Run run(const TempDir& dir, const std::string& args, const std::string& before = "",
               const std::string& stdout_to = "") {
  std::string cmd = before + " " + std::string(DACRT_CLI) + " " + args + " >" +
                    (stdout_to.empty() ? dir / "stdout.txt" : stdout_to) + " 2>" +
                    (dir / "stderr.txt") + " </dev/null";
  int status = std::system(cmd.c_str());
  Run r{WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(dir / "stderr.txt"),
        slurp(dir / "stdout.txt")};
  fs::remove(dir / "stdout.txt");
  fs::remove(dir / "stderr.txt");
  return r;
}

inline size_t lines(const std::string& s) {
  return size_t(std::count(s.begin(), s.end(), '\n'));
}

// Nothing but the inputs in `dir`: no image, no preview, no stats, no temporary files.
inline void check_no_outputs(const TempDir& dir) {
  for (const auto& e : fs::directory_iterator(dir.path())) {
    std::string name = e.path().filename().string();
    CHECK_MESSAGE(name.find(".gltf") != std::string::npos, "left behind: " << name);
  }
}

}  // namespace dacrt::test
