// write_atomically: every output file (EXR, PNG preview, statistics) is written to a temporary
// name beside its target and renamed over it, so a failed or interrupted run never leaves a
// half-written file. Errors become one-line dacrt::Error messages naming the target.
#pragma once

#include <fstream>
#include <functional>
#include <string>

namespace dacrt {

// Calls `write` with a binary stream on "<path>.tmp-<pid>", then renames it to `path`. `what`
// names the kind of file in messages ("cannot write EXR 'x.exr': …"). On any failure, including
// an exception from `write`, the temporary file is removed and Error is thrown.
void write_atomically(const std::string& path, const std::string& what,
                      const std::function<void(std::ofstream&)>& write);

// Removes the temporary file being written, if any (async-signal-safe): for a signal handler that
// ends the process while write_atomically may be running.
void remove_pending_file() noexcept;

// Throws Error if `path` could not be written later (no such directory, not writable, or a
// directory itself): lets a command fail before hours of work rather than after.
void check_writable(const std::string& path);

}  // namespace dacrt
