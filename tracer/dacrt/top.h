// TopLevels: the top of the implicit tree, kept from call to call. The geometry does not change
// within a frame, so the splits of the largest nodes (the triangle order and boxes of the top
// levels) need not be binned and partitioned again by every batch: a call with a few rays would
// otherwise pay O(triangles) per level before its rays thin out. The kept nodes are split by the
// SAH, once, when the backend is created (a split chosen by one batch's α would serve that
// batch's ray type, and a frame mixes camera, shadow and bounce rays); each call still samples its
// own rays at every kept node for the children's order and for whether filtering pays, and below
// the kept levels everything is chosen anew, by ray sampling, as in pure DACRT. Nodes of at least
// DacrtParams::top_triangles triangles are kept, at most max_nodes() of them, so the memory is
// bounded and stated in advance (dacrt_memory_bound). top_triangles=0 keeps nothing.
#pragma once

#include <atomic>
#include <cstdint>
#include <vector>

#include "dacrt/tracer/dacrt/traversal.h"

namespace dacrt::kernel {

struct TopLevels {
  struct Node {
    Traversal::Split split;  // children in left, right order along `axis`
    int axis;                // the binning axis: rays heading along it visit the left child first
  };
  std::vector<Node> nodes;  // nodes[0] is the root, when any is kept
  int levels = 0;           // the depth of the deepest kept node, plus one
  // Traversal::walk keeps one child per level on its stack: deeper kept trees are not walked.
  static constexpr int max_walk_depth = 64;

  static uint64_t max_nodes(uint64_t triangles, const DacrtParams& params) {
    if (params.top_triangles <= 0) return 0;
    return 2 * ((triangles + uint64_t(params.top_triangles) - 1) / uint64_t(params.top_triangles));
  }

  // Splits the records tris[0, n) in place down to nodes of fewer than top_triangles triangles.
  void build(const Kernel& k, TriangleRef* tris, uint32_t n, const Box& bounds, const Box& centres);
  // The same splits for moved triangles: `tris` are the records build() ordered (each child's
  // range holds the same triangles, in any order), encoded again for the new positions. Every
  // child's box and centres' box is recomputed from them, bottom-up (exact: the unions the build
  // would bin for these ranges), and each node's axis and child order are chosen again as the
  // build chooses them (the longest axis of its centres' box, the lower child first).
  void refit(const TriangleRef* tris);

 private:
  int32_t build_node(Traversal& t, const Box& box, const Box& centres, uint32_t tb, uint32_t te,
                     int depth);
  std::atomic<uint32_t> count_{0};
  std::atomic<int> levels_{0};
};

}  // namespace dacrt::kernel
