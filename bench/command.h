// bench_command: `dacrt bench` from its arguments to its table (on `out`) and its JSON file. The
// CLI's bench_main calls it with std::cout; the tests call it directly with a string stream.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

namespace dacrt::bench {

int bench_command(const std::vector<std::string>& argv, std::ostream& out);

}  // namespace dacrt::bench
