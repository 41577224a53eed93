// A backend's counters as JSON, the same keys in `dacrt render --stats` and `dacrt bench --json`.
#pragma once

#include <nlohmann/json.hpp>

#include "dacrt/tracer/stats.h"

namespace dacrt {

inline nlohmann::json to_json(const Stats& b) {
  return {{"rays", b.rays},
          {"triangle_tests", b.triangle_tests},
          {"box_tests", b.box_tests},
          {"nodes", b.nodes},
          {"kept_nodes", b.kept_nodes},
          {"leaves", b.leaves},
          {"leaf_rays", b.leaf_rays},
          {"filter_skips", b.filter_skips},
          {"binned", b.binned},
          {"tasks", b.tasks},
          {"build_seconds", b.build_seconds},
          {"peak_bytes", b.peak_bytes}};
}

}  // namespace dacrt
