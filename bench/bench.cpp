// `dacrt bench`: see bench.h; the work is in the header-only bench/command.h so that the tests can
// run it without linking the CLI.
#include "bench/bench.h"

#include <iostream>

#include "bench/command.h"

namespace dacrt {

int bench_main(const std::vector<std::string>& args) {
  return bench::bench_command(args, std::cout);
}

}  // namespace dacrt
