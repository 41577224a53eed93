#include "util/atomic_file.h"

#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <iterator>
#include <system_error>

#include "util/error.h"

namespace dacrt {

namespace fs = std::filesystem;

namespace {

// The temporary file being written, for the signal handler: an interrupted run removes it, so
// Ctrl-C leaves neither a half-written output nor a stray temporary. The handler is installed
// only while a file is written and hands the signal on to whatever handler was there before.
constexpr int handled[] = {SIGINT, SIGTERM, SIGHUP};
char pending[4096];
struct sigaction previous[std::size(handled)];

extern "C" void remove_pending_and_pass_on(int sig) {
  ::unlink(pending);
  for (size_t k = 0; k < std::size(handled); ++k)
    if (handled[k] == sig) sigaction(sig, &previous[k], nullptr);
  std::raise(sig);
}

struct PendingFile {
  bool active = false;
  explicit PendingFile(const std::string& path) {
    if (path.size() >= sizeof pending) return;
    std::memcpy(pending, path.c_str(), path.size() + 1);
    struct sigaction action {};
    action.sa_handler = remove_pending_and_pass_on;
    sigemptyset(&action.sa_mask);
    for (size_t k = 0; k < std::size(handled); ++k) {
      sigaction(handled[k], nullptr, &previous[k]);
      if (previous[k].sa_handler != SIG_IGN) sigaction(handled[k], &action, nullptr);
    }
    active = true;
  }
  ~PendingFile() {
    if (!active) return;
    for (size_t k = 0; k < std::size(handled); ++k) sigaction(handled[k], &previous[k], nullptr);
  }
};

}  // namespace

void write_atomically(const std::string& path, const std::string& what,
                      const std::function<void(std::ofstream&)>& write) {
  const std::string prefix = "cannot write " + what + " '" + path + "': ";
  const fs::path target(path), dir = target.parent_path();
  std::error_code ec;
  if (!dir.empty() && !fs::exists(dir, ec))
    throw Error(prefix + "directory '" + dir.string() + "' does not exist");
  if (!dir.empty() && !fs::is_directory(dir, ec))
    throw Error(prefix + "'" + dir.string() + "' is not a directory");

  const std::string tmp = path + ".tmp-" + std::to_string(::getpid());
  const PendingFile pending_file(tmp);
  auto fail = [&](const std::string& reason) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    return Error(prefix + one_line(reason));
  };
  errno = 0;
  std::ofstream stream(tmp, std::ios::binary | std::ios::trunc);
  if (!stream) {
    const int err = errno;
    throw Error(prefix + "cannot create '" + tmp + "'" +
                (err ? " (" + std::generic_category().message(err) + ")" : std::string()));
  }
  try {
    write(stream);
  } catch (const std::exception& e) {
    stream.close();
    throw fail(e.what());
  }
  stream.close();
  if (!stream) throw fail("writing '" + tmp + "' failed (disk full?)");
  fs::rename(tmp, target, ec);
  if (ec) throw fail(ec.message());
}

void check_writable(const std::string& path) {
  if (path.empty()) return;
  fs::path dir = fs::path(path).parent_path();
  if (dir.empty()) dir = ".";
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw Error(path + ": cannot write: directory " + dir.string() + " does not exist");
  if (fs::is_directory(path, ec)) throw Error(path + ": cannot write: it is a directory");
  if (::access(dir.c_str(), W_OK) != 0)
    throw Error(path + ": cannot write: directory " + dir.string() + " is not writable");
}

}  // namespace dacrt
