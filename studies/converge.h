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

// What the command says besides its files when a library runs it (Python's converge()).
struct ConvergeSaid {
  std::vector<std::string> warnings;  // its warnings and the shot's notes, a line each
};
// converge_main for a library: the same files, nothing on stdout (no summary, no help), no list
// of the files written, and its warnings and notes (even with --quiet) into `said` rather than
// on stderr. Its progress (unless --quiet) is on stderr, as the command's.
int converge_for_library(const std::vector<std::string>& args, ConvergeSaid& said);

}  // namespace dacrt
