// write_atomically: every output file (EXR, PNG preview, statistics, CSV) is written to a new
// temporary file beside its target and renamed over it, so a failed or interrupted run never leaves
// a half-written file. The temporary is created with O_EXCL and a random name (mkstemp), so a file
// or symbolic link planted at a predictable name is never followed or overwritten. Errors become
// one-line dacrt::Error messages naming the target.
#pragma once

#include <filesystem>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

namespace dacrt {

// The file that writing `path` replaces: `path` itself or, when it is a symbolic link the user
// may follow, the file it points to (a dangling link: the file it will create). Throws Error for
// a link that loops, or a link in a sticky, world-writable directory (/tmp) owned by someone else
// than us and the directory's owner: such a link may have been planted, and is not followed (the
// rule of Linux's fs.protected_symlinks).
std::filesystem::path output_target(const std::string& path);

// Calls `write` with a binary stream on a new temporary file "<target>.tmp-XXXXXX" (mode 0666 less
// the umask) in the target's directory, then renames it to the target. `what` names the kind of
// file in messages ("cannot write EXR 'x.exr': …"). On any failure, including an exception from
// `write`, the temporary file is removed and Error is thrown.
void write_atomically(const std::string& path, const std::string& what,
                      const std::function<void(std::ostream&)>& write);

// Removes the temporary file being written, if any (async-signal-safe): for a signal handler that
// ends the process while write_atomically may be running.
void remove_pending_file() noexcept;

// Throws Error if `path` could not be written later, found the way the write will find it: the
// link resolved as output_target does, its directory exists, a file can be created there (a
// temporary one is, and removed: read-only file systems, /proc, permissions), the target is not a
// directory, FIFO or device, and it is not another user's file in a sticky directory (which the
// rename could not replace). Lets a command fail before hours of work rather than after.
void check_writable(const std::string& path);
// The same for many outputs (a sequence's frames): each checked, but a file made once in a
// directory for names of one length (200 000 outputs of --frames 0:99999 made 200 000 probes).
void check_writable(const std::vector<std::string>& paths);

// A directory named as an output (`--report DIR`): checked before the work, made only when the
// first file goes into it, and removed again with what was written into it when the command
// fails (destroyed without keep()): a failed command leaves no directory behind, not even an
// empty one. A directory that was there before is never removed.
class OutputDirectory {
 public:
  // Throws Error ("<option> <dir>: cannot write: …") unless `dir` is a directory in which files
  // can be made, or does not exist and could be made: its nearest existing ancestor is a
  // directory in which one can be created.
  OutputDirectory(std::string option, std::string dir);
  ~OutputDirectory();
  OutputDirectory(const OutputDirectory&) = delete;
  OutputDirectory& operator=(const OutputDirectory&) = delete;

  // Whether it was there before: then its files can be checked with check_writable now.
  bool existed() const { return existed_; }
  // Makes it and its missing parents (once); throws Error naming the option when it cannot.
  void make();
  // The command succeeded: what make() made stays.
  void keep() { kept_ = true; }

 private:
  std::string option_, dir_;
  bool existed_ = false, kept_ = false;
  std::filesystem::path made_;  // the outermost directory make() created
};

}  // namespace dacrt
