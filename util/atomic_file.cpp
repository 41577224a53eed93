#include "dacrt/util/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <atomic>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <ext/stdio_filebuf.h>
#include <fstream>
#include <iterator>
#include <set>
#include <system_error>

#include "dacrt/util/error.h"
#include "dacrt/util/paths.h"

namespace dacrt {

namespace fs = std::filesystem;

namespace {

// The temporary file being written, for the signal handler: an interrupted run removes it, so
// Ctrl-C leaves neither a half-written output nor a stray temporary. The handler is installed
// only while a file is written and hands the signal on to whatever handler was there before. A
// handler that returns (util/interrupt.h's, which asks a render to stop and write what it has) is
// called without removing the file, which is then finished. The signals are those whose default
// action ends the process and that can be caught. (The CLI ignores SIGXFSZ, so that a file-size
// limit is a write error it reports rather than a kill, and SIGPIPE, so that a closed stderr does
// not end a render.)
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

// The handlers are installed first; arm() then names the file the moment it exists, so that a
// signal arriving right after its creation (a second Ctrl-C, as soon as the file appears) finds
// it named: the window is a copy of its name, not the system calls of the set-up.
struct PendingFile {
  PendingFile() {
    struct sigaction action {};
    action.sa_handler = remove_pending_and_pass_on;
    sigemptyset(&action.sa_mask);
    for (size_t k = 0; k < std::size(handled); ++k) {
      sigaction(handled[k], nullptr, &previous[k]);
      if (previous[k].sa_handler != SIG_IGN) sigaction(handled[k], &action, nullptr);
    }
  }
  void arm(const std::string& path) {
    if (path.size() >= sizeof pending) return;
    std::memcpy(pending, path.c_str(), path.size() + 1);
    std::atomic_signal_fence(std::memory_order_release);  // the name before the flag
    pending_active = 1;
  }
  ~PendingFile() {
    pending_active = 0;
    for (size_t k = 0; k < std::size(handled); ++k) sigaction(handled[k], &previous[k], nullptr);
  }
  PendingFile(const PendingFile&) = delete;
  PendingFile& operator=(const PendingFile&) = delete;
};

std::string system_message(int err) {
  return std::generic_category().message(err);
}

// The process's umask, without changing it (Linux 4.7+ shows it in /proc/self/status; elsewhere
// it is read by setting it and setting it back).
mode_t current_umask() {
  if (std::FILE* f = std::fopen("/proc/self/status", "re")) {
    char line[256];
    unsigned mask = 0;
    bool found = false;
    while (!found && std::fgets(line, sizeof line, f))
      found = std::sscanf(line, "Umask: %o", &mask) == 1;
    std::fclose(f);
    if (found) return mode_t(mask);
  }
  const mode_t mask = ::umask(022);
  ::umask(mask);
  return mask;
}

// A new file "<target>.tmp-XXXXXX" that did not exist (O_CREAT | O_EXCL: never a planted file or
// link), named to `pending` as soon as it exists, then given the mode a new file would have.
// Returns its descriptor and sets `name`.
int create_temporary(const fs::path& target, PendingFile& pending, std::string& name) {
  std::string pattern = target.string() + ".tmp-XXXXXX";
  const int fd = ::mkostemp(pattern.data(), O_CLOEXEC);
  if (fd < 0) return -1;
  pending.arm(pattern);
  name = pattern;
  ::fchmod(fd, 0666 & ~current_umask());
  return fd;
}

bool sticky_shared(const struct stat& dir) {
  return (dir.st_mode & S_ISVTX) && (dir.st_mode & S_IWOTH);
}

}  // namespace

fs::path output_target(const std::string& path) {
  std::error_code ec;
  fs::path p = fs::absolute(path, ec);
  if (ec) p = path;
  for (int hops = 0;; ++hops) {
    struct stat link {};
    if (::lstat(p.c_str(), &link) != 0 || !S_ISLNK(link.st_mode)) break;
    if (hops == 40) throw Error(path + ": cannot write: a symbolic link that loops");
    struct stat dir {};
    const uid_t me = ::geteuid();
    if (::stat(p.parent_path().c_str(), &dir) == 0 && sticky_shared(dir) && link.st_uid != me &&
        link.st_uid != dir.st_uid)
      throw Error(path + ": cannot write: " + (hops ? "it leads to " + p.string() + ", " : "") +
                  "a symbolic link owned by another user in the shared directory " +
                  p.parent_path().string() + ", which is not followed");
    const fs::path to = fs::read_symlink(p, ec);
    if (ec)
      throw Error(path + ": cannot write: the symbolic link cannot be read (" + ec.message() + ")");
    p = to.is_absolute() ? to : p.parent_path() / to;
  }
  const fs::path canonical = fs::weakly_canonical(p, ec);
  return ec ? p.lexically_normal() : canonical;
}

void remove_pending_file() noexcept {
  if (pending_active) ::unlink(pending);
}

void write_atomically(const std::string& path, const std::string& what,
                      const std::function<void(std::ostream&)>& write) {
  const std::string prefix = "cannot write " + what + " '" + path + "': ";
  std::error_code ec;
  const fs::path target = output_target(path);
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

  std::string tmp;
  PendingFile pending_file;
  errno = 0;
  const int fd = create_temporary(target, pending_file, tmp);
  if (fd < 0)
    throw Error(prefix + "cannot create a temporary file in '" + dir.string() + "' (" +
                system_message(errno) + ")");
  auto fail = [&](const std::string& reason) {
    ::unlink(tmp.c_str());
    return Error(prefix + one_line(reason));
  };
  // The reason the system gave for a failed write (ENOSPC, EFBIG, EIO…), when there is one.
  auto system_reason = [](int err) {
    return err ? " (" + system_message(err) + ")" : std::string();
  };
  __gnu_cxx::stdio_filebuf<char> buffer(fd, std::ios::out | std::ios::binary);  // owns fd
  std::ostream stream(&buffer);
  errno = 0;
  try {
    write(stream);
  } catch (const std::exception& e) {
    const int err = errno;
    buffer.close();
    const std::string message = e.what();
    throw fail(message + (message.find(system_message(err)) == std::string::npos
                              ? system_reason(err)
                              : std::string()));
  }
  if (stream) stream.flush();
  int err = stream ? 0 : errno;
  errno = 0;
  const bool closed = buffer.close() != nullptr;
  if (!err && !closed) err = errno;
  if (!stream || !closed)
    throw fail("writing '" + tmp + "' failed" + (err ? system_reason(err) : " (disk full?)"));
  fs::rename(tmp, target, ec);
  if (ec) throw fail(ec.message());
}

namespace {

// check_writable, making the probe file only where `probed` (when given) holds no earlier probe
// in the same directory with a name of the same length (what decides whether one can be made).
void check_target(const std::string& path, std::set<std::string>* probed) {
  if (path.empty()) return;
  const fs::path target = output_target(path);
  const std::string named = target == fs::absolute(path).lexically_normal()
                                ? std::string()
                                : " (" + target.string() + ")";
  auto refuse = [&](const std::string& why) {
    return Error(path + named + ": cannot write: " + why);
  };
  fs::path dir = target.parent_path();
  if (dir.empty()) dir = ".";
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw refuse("directory " + dir.string() + " does not exist");
  // The file is replaced by renaming a new one over it: a device or a FIFO would be replaced by a
  // regular file (as root, /dev/null itself), a directory cannot be.
  struct stat file {
  }, parent{};
  const bool exists = ::stat(target.c_str(), &file) == 0;
  if (exists && !S_ISREG(file.st_mode))
    throw refuse("it is " + std::string(file_kind(fs::status(target, ec))) +
                 ", not a regular file");
  // In a sticky directory only the file's owner, the directory's and root may replace a file.
  const uid_t me = ::geteuid();
  if (exists && ::stat(dir.c_str(), &parent) == 0 && (parent.st_mode & S_ISVTX) && me != 0 &&
      file.st_uid != me && parent.st_uid != me)
    throw refuse("it belongs to another user (uid " + std::to_string(file.st_uid) +
                 ") in a directory with the sticky bit, " + dir.string() +
                 ", so it cannot be replaced");
  // Whether a file can be made there is known only by making one: permissions, a read-only file
  // system, /proc and /sys, quotas.
  if (probed &&
      !probed->insert(dir.string() + '\0' + std::to_string(target.filename().string().size()))
           .second)
    return;
  std::string probe;
  PendingFile pending;
  errno = 0;
  const int fd = create_temporary(target, pending, probe);
  if (fd < 0)
    throw refuse("no file can be created in " + dir.string() + " (" + system_message(errno) + ")");
  ::close(fd);
  ::unlink(probe.c_str());
}

}  // namespace

void check_writable(const std::string& path) {
  check_target(path, nullptr);
}

void check_writable(const std::vector<std::string>& paths) {
  std::set<std::string> probed;
  for (const std::string& path : paths) check_target(path, &probed);
}

}  // namespace dacrt

namespace dacrt {

namespace {

// The outermost directory of `dir` that does not exist yet (`dir` itself when its parent exists):
// what making it creates first.
fs::path outermost_missing(const std::string& dir) {
  std::error_code ec;
  fs::path missing = fs::absolute(dir, ec).lexically_normal();
  while (missing.has_parent_path() && missing.parent_path() != missing &&
         !fs::exists(fs::status(missing.parent_path(), ec)))
    missing = missing.parent_path();
  return missing;
}

}  // namespace

OutputDirectory::OutputDirectory(std::string option, std::string dir)
    : option_(std::move(option)), dir_(std::move(dir)) {
  auto refuse = [&](const std::string& why) {
    return Error(option_ + " " + dir_ + ": cannot write: " + why);
  };
  std::error_code ec;
  const fs::path path = fs::absolute(dir_, ec).lexically_normal();
  const fs::file_status status = fs::status(path, ec);
  existed_ = fs::exists(status);
  if (existed_) {
    if (!fs::is_directory(status))
      throw refuse(std::string("it is ") + file_kind(status) + ", not a directory");
    return;
  }
  // The nearest ancestor that exists must be a directory in which the first missing one can be
  // made (check_writable makes and removes a file there).
  const fs::path missing = outermost_missing(dir_);
  const fs::file_status above = fs::status(missing.parent_path(), ec);
  if (!fs::is_directory(above))
    throw refuse(missing.parent_path().string() + " is " + file_kind(above) + ", not a directory");
  check_writable(missing.string());
}

OutputDirectory::~OutputDirectory() {
  if (kept_ || made_.empty()) return;
  std::error_code ec;
  fs::remove_all(made_, ec);
}

void OutputDirectory::make() {
  if (existed_ || !made_.empty()) return;
  const fs::path outermost = outermost_missing(dir_);
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (ec) throw Error(option_ + ": cannot create " + dir_ + ": " + ec.message());
  made_ = outermost;
}

}  // namespace dacrt
