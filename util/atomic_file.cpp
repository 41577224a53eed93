#include "util/atomic_file.h"

#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <iterator>
#include <system_error>

#include "util/error.h"
#include "util/paths.h"

namespace dacrt {

namespace fs = std::filesystem;

namespace {

// The temporary file being written, for the signal handler: an interrupted run removes it, so
// Ctrl-C leaves neither a half-written output nor a stray temporary. The handler is installed
// only while a file is written and hands the signal on to whatever handler was there before. A
// handler that returns (util/interrupt.h's, which asks a render to stop and write what it has) is
// called without removing the file, which is then finished. The signals are those whose default
// action ends the process and that can be caught. (The CLI ignores SIGXFSZ, so that a file-size
// limit is a write error it reports rather than a kill.)
constexpr int handled[] = {SIGHUP,  SIGINT,  SIGQUIT, SIGTERM, SIGPIPE,   SIGALRM,
                           SIGUSR1, SIGUSR2, SIGXCPU, SIGXFSZ, SIGVTALRM, SIGPROF,
                           SIGABRT, SIGBUS,  SIGFPE,  SIGILL,  SIGSEGV,   SIGSYS};
char pending[4096];
volatile std::sig_atomic_t pending_active = 0;
struct sigaction previous[std::size(handled)];

extern "C" void remove_pending_and_pass_on(int sig) {
  for (size_t k = 0; k < std::size(handled); ++k) {
    if (handled[k] != sig) continue;
    const auto handler = previous[k].sa_handler;
    if (!(previous[k].sa_flags & SA_SIGINFO) && handler != SIG_DFL && handler != SIG_IGN) {
      handler(sig);
      return;
    }
    remove_pending_file();
    sigaction(sig, &previous[k], nullptr);
  }
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
    pending_active = 1;
  }
  ~PendingFile() {
    if (!active) return;
    pending_active = 0;
    for (size_t k = 0; k < std::size(handled); ++k) sigaction(handled[k], &previous[k], nullptr);
  }
};

}  // namespace

void remove_pending_file() noexcept {
  if (pending_active) ::unlink(pending);
}

void write_atomically(const std::string& path, const std::string& what,
                      const std::function<void(std::ofstream&)>& write) {
  const std::string prefix = "cannot write " + what + " '" + path + "': ";
  std::error_code ec;
  // Through a symbolic link, the file it points to is replaced, not the link.
  const fs::path target =
      fs::is_symlink(fs::symlink_status(path, ec)) ? resolved_path(path) : fs::path(path);
  const fs::path dir = target.parent_path();
  if (!dir.empty() && !fs::exists(dir, ec))
    throw Error(prefix + "directory '" + dir.string() + "' does not exist");
  if (!dir.empty() && !fs::is_directory(dir, ec))
    throw Error(prefix + "'" + dir.string() + "' is not a directory");

  {
    const fs::file_status status = fs::status(target, ec);
    if (fs::exists(status) && !fs::is_regular_file(status))
      throw Error(prefix + "it is " + file_kind(status) + ", not a regular file");
  }

  const std::string tmp = target.string() + ".tmp-" + std::to_string(::getpid());
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
  // The reason the system gave for a failed write (ENOSPC, EFBIG, EIO…), when there is one.
  auto system_reason = [](int err) {
    return err ? " (" + std::generic_category().message(err) + ")" : std::string();
  };
  errno = 0;
  try {
    write(stream);
  } catch (const std::exception& e) {
    const int err = errno;
    stream.close();
    const std::string what = e.what();
    throw fail(what + (what.find(std::generic_category().message(err)) == std::string::npos
                           ? system_reason(err)
                           : std::string()));
  }
  if (stream) stream.flush();
  int err = stream ? 0 : errno;
  stream.close();
  if (!stream && !err) err = errno;
  if (!stream)
    throw fail("writing '" + tmp + "' failed" + (err ? system_reason(err) : " (disk full?)"));
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
  // The file is replaced by renaming a new one over it: a device or a FIFO would be replaced by a
  // regular file (as root, /dev/null itself), a directory cannot be.
  const fs::file_status status = fs::status(path, ec);
  if (fs::exists(status) && !fs::is_regular_file(status))
    throw Error(path + ": cannot write: it is " + file_kind(status) + ", not a regular file");
  if (::access(dir.c_str(), W_OK) != 0)
    throw Error(path + ": cannot write: directory " + dir.string() + " is not writable");
}

}  // namespace dacrt
