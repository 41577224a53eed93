// bench_command: `dacrt bench` from its arguments to its table (on `out`) and its JSON file. The
// CLI's bench_main calls it with std::cout; the tests call it directly with a string stream.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

#include "bench/args.h"
#include "bench/report.h"
#include "dacrt/util/paths.h"

namespace dacrt::bench {

// What `dacrt bench` measures with these arguments: the backends checked, the scene loaded (none
// of its files may be one of `outputs`), every case run. The table, the JSON and the report are
// made from it (the Python module's bench() returns its JSON).
BenchReport bench_report(const BenchArgs& args, const std::vector<NamedFile>& outputs = {});

int bench_command(const std::vector<std::string>& argv, std::ostream& out);

}  // namespace dacrt::bench
