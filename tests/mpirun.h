// mpirun from a test, as a user on this machine runs it: for the CLI tests that render on ranks.
#pragma once

#include <cstdlib>
#include <string>

namespace dacrt::test {

inline bool have_mpirun() {
  return std::system("command -v mpirun >/dev/null 2>&1") == 0;
}

// OpenMPI as root needs --allow-run-as-root, more ranks than cores --oversubscribe; -q keeps
// mpirun's own notes (a rank exited non-zero) off stderr, which then holds dacrt's lines alone.
// Under the sanitizers, OpenMPI's own leaks are suppressed (tests/support/openmpi-leaks.supp
// says why), without the table of suppressions a rank that ends after MPI_Init would print on
// stderr; the options are ignored by a build without them.
inline std::string mpirun(int ranks) {
  return "ASAN_OPTIONS=detect_leaks=1:fast_unwind_on_malloc=0 LSAN_OPTIONS=suppressions=" +
         std::string(DACRT_SOURCE_DIR) + "/tests/support/openmpi-leaks.supp:print_suppressions=0 " +
         "mpirun -q --allow-run-as-root --oversubscribe -np " + std::to_string(ranks);
}

}  // namespace dacrt::test
