// What a piece of code writes to stderr, captured by pointing fd 2 at a temporary file (which
// also makes stderr a non-TTY): both std::cerr and fprintf(stderr, ...) reach it.
#pragma once

#include <doctest/doctest.h>
#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <string>

namespace dacrt::test {

// Redirects stderr to an unlinked temporary file while alive; text() returns what was written.
class CapturedStderr {
 public:
  CapturedStderr() {
    std::cerr.flush();
    std::fflush(stderr);
    file_ = std::tmpfile();
    REQUIRE(file_ != nullptr);
    saved_ = dup(STDERR_FILENO);
    REQUIRE(saved_ >= 0);
    REQUIRE(dup2(fileno(file_), STDERR_FILENO) >= 0);
  }
  ~CapturedStderr() {
    restore();
    if (file_) std::fclose(file_);
  }
  CapturedStderr(const CapturedStderr&) = delete;
  CapturedStderr& operator=(const CapturedStderr&) = delete;

  std::string text() {
    restore();
    std::rewind(file_);
    std::string out;
    char buffer[4096];
    size_t n;
    while ((n = std::fread(buffer, 1, sizeof buffer, file_)) > 0) out.append(buffer, n);
    return out;
  }

 private:
  void restore() {
    if (saved_ < 0) return;
    std::cerr.flush();
    std::fflush(stderr);
    dup2(saved_, STDERR_FILENO);
    close(saved_);
    saved_ = -1;
  }
  std::FILE* file_ = nullptr;
  int saved_ = -1;
};

// What `run()` writes to stderr; stderr is restored if it throws.
template <class Run>
std::string stderr_of(Run&& run) {
  CapturedStderr captured;
  run();
  return captured.text();
}

}  // namespace dacrt::test
