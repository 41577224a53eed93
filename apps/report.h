// What `dacrt render --backend a,b,c` prints after the renders: one table, the backends side by
// side.
#pragma once

#include <cstdio>
#include <string>
#include <vector>

#include "dacrt/render/run_report.h"

namespace dacrt {

// The comparison's rows: a label, then one cell per backend; the first row names the backends, an
// empty row is a rule, and the last row is each one's speed-up against the first (the first's
// render seconds over its own: higher is faster).
std::vector<std::vector<std::string>> comparison_rows(const std::vector<BackendRun>& runs);
// The rows as a text table, one column per backend.
void print_comparison(std::FILE* out, const std::vector<BackendRun>& runs);

}  // namespace dacrt
