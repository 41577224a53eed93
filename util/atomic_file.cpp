#include "util/atomic_file.h"

#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <system_error>

#include "util/error.h"

namespace dacrt {

namespace fs = std::filesystem;

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
  auto fail = [&](std::string reason) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    for (char& c : reason)
      if (c == '\n' || c == '\r') c = ' ';
    return Error(prefix + reason);
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

}  // namespace dacrt
