// `dacrt bench SCENE`: every backend on the same rays of each type, in the same run: build and
// trace seconds, Mrays/s trace-only and with build, peak working memory; medians of --repeat runs.
#pragma once

#include <string>
#include <vector>

namespace dacrt {

// args: everything after `dacrt bench`. Prints the table on stdout and returns the exit code (0);
// throws std::invalid_argument for usage errors (exit 2) and dacrt::Error for others (exit 1).
// `-h`/`--help` prints the help on stdout and returns 0. The work is in bench/command.cpp.
int bench_main(const std::vector<std::string>& args);

}  // namespace dacrt
