// `dacrt bench`: see bench.h; the work is in bench/command.cpp, part of the dacrt_bench library
// that the tests link too, so that they can run it without the CLI.
#include "bench/bench.h"

#include <iostream>

#include "bench/command.h"

namespace dacrt {

int bench_main(const std::vector<std::string>& args) {
  return bench::bench_command(args, std::cout);
}

}  // namespace dacrt
