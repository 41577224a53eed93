// Stats: what a backend counts while it works, summed over all calls since it was created.
#pragma once

#include <cstdint>

namespace dacrt {

struct Stats {
  uint64_t rays = 0;            // rays handed to intersect/occluded
  uint64_t triangle_tests = 0;  // ray/triangle tests
  uint64_t box_tests = 0;       // ray/box tests (filtering and sampling)
  uint64_t nodes = 0;           // inner nodes (DACRT)
  uint64_t leaves = 0;          // leaves (DACRT)
  uint64_t leaf_rays = 0;       // rays entering leaves, summed over the leaves (DACRT)
  uint64_t kept_nodes = 0;      // of the nodes, those of the kept top levels (DACRT)
  uint64_t binned = 0;          // triangle records binned to choose splits (DACRT): triangle work
  uint64_t filter_skips = 0;    // children entered without ray filtering (DACRT)
  uint64_t tasks = 0;           // subtrees traversed by another thread beside their sibling (DACRT)
  double build_seconds = 0.0;   // preparation at create()
  uint64_t peak_bytes = 0;      // largest working memory of one call, beyond inputs and outputs

  Stats& operator+=(const Stats& o) {
    rays += o.rays, triangle_tests += o.triangle_tests, box_tests += o.box_tests;
    nodes += o.nodes, leaves += o.leaves, leaf_rays += o.leaf_rays, filter_skips += o.filter_skips;
    kept_nodes += o.kept_nodes, binned += o.binned;
    tasks += o.tasks;
    return *this;
  }
};

}  // namespace dacrt
