// write_atomically: the target appears whole or not at all, and no temporary file survives a
// failure or an interruption.
#include "dacrt/util/atomic_file.h"

#include <doctest/doctest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "temp_dir.h"
#include "dacrt/util/error.h"

using namespace dacrt;
using namespace dacrt::test;

namespace {
size_t files_in(const std::filesystem::path& dir) {
  size_t n = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir)) ++n;
  return n;
}
}  // namespace

TEST_CASE("write_atomically: a failing writer leaves nothing, a good one replaces the target") {
  TempDir dir("atomic");
  const std::string path = dir / "out.txt";
  CHECK_THROWS_WITH_AS(write_atomically(path, "test",
                                        [](std::ostream& out) {
                                          out << "partial";
                                          throw std::runtime_error("writer\nfailed");
                                        }),
                       doctest::Contains("out.txt': writer failed"), Error);
  CHECK(files_in(dir.path()) == 0);
  write_atomically(path, "test", [](std::ostream& out) { out << "first"; });
  write_atomically(path, "test", [](std::ostream& out) { out << "second"; });
  CHECK(files_in(dir.path()) == 1);
  std::ifstream in(path);
  std::string text;
  in >> text;
  CHECK(text == "second");
}

TEST_CASE("write_atomically: a run interrupted while writing leaves no temporary file") {
  // Every signal that ends a process by default and can be caught: interruptions, limits (a
  // file-size or CPU limit), a closed pipe, timers, and crashes.
  for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGPIPE, SIGALRM, SIGUSR1, SIGUSR2, SIGXCPU,
                  SIGXFSZ, SIGVTALRM, SIGPROF, SIGABRT, SIGBUS, SIGFPE, SIGILL, SIGSEGV, SIGSYS}) {
    INFO(strsignal(sig));
    TempDir dir("interrupted");
    const std::string path = dir / "out.exr";
    pid_t child = fork();
    REQUIRE(child >= 0);
    if (child == 0) {
      const rlimit no_core{0, 0};
      setrlimit(RLIMIT_CORE, &no_core);
      std::signal(sig, SIG_DFL);  // the test runner's own crash handler has no business here
      write_atomically(path, "test", [sig](std::ostream& out) {
        out << "half of an image";
        out.flush();
        std::raise(sig);
      });
      _exit(0);  // not reached: the signal ends the child
    }
    int status = 0;
    REQUIRE(waitpid(child, &status, 0) == child);
    CHECK(WIFSIGNALED(status));
    CHECK(WTERMSIG(status) == sig);
    CHECK(files_in(dir.path()) == 0);
  }
}

TEST_CASE("OutputDirectory: made on demand, removed with its files unless kept, never if it was there") {
  namespace fs = std::filesystem;
  TempDir dir("output-directory");
  {  // Made, written into, not kept (the command failed): gone, parents it made too.
    dacrt::OutputDirectory out("--report", dir / "a/b/c");
    CHECK(!fs::exists(dir / "a"));  // checking makes nothing
    out.make();
    std::ofstream(dir / "a/b/c/index.html") << "page";
    CHECK(fs::exists(dir / "a/b/c/index.html"));
  }
  CHECK(!fs::exists(dir / "a"));
  {  // Kept: stays.
    dacrt::OutputDirectory out("--report", dir / "k");
    out.make();
    out.keep();
  }
  CHECK(fs::is_directory(dir / "k"));
  {  // There before: never removed, whatever happens.
    dacrt::OutputDirectory out("--report", dir / "k");
    CHECK(out.existed());
    out.make();
  }
  CHECK(fs::is_directory(dir / "k"));
  // Where no directory can be made: refused when checked, naming the option and the path.
  std::ofstream(dir / "file") << "x";
  for (const std::string& bad : {dir / "file", dir / "file/sub"}) {
    CAPTURE(bad);
    try {
      dacrt::OutputDirectory out("--report", bad);
      FAIL("accepted");
    } catch (const dacrt::Error& e) {
      CHECK(std::string(e.what()).find("--report " + bad + ": cannot write") == 0);
      CHECK(std::string(e.what()).find("a file, not a directory") != std::string::npos);
    }
  }
}
