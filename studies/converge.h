// `dacrt converge SCENE`: run time against error. Renders each configuration (a set of render
// options, `--config "backend=embree"`) at 1, 2, 4, … samples per pixel until its time budget is
// spent, measures each point against a reference (and/or the noise between two seeds), fits the
// slopes of log error against log spp and log time, and writes a CSV, a gnuplot script and its
// plot (SVG and PNG), then prints equal-error and equal-time comparisons on stdout.
#pragma once

#include <string>
#include <vector>

namespace dacrt {

// The command's exit code (0, or 128 + the signal that stopped it); throws UsageError or Error.
int converge_main(const std::vector<std::string>& args);

}  // namespace dacrt
