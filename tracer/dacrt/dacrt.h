// DACRT: divide-and-conquer ray tracing. No acceleration structure is built: each batch of rays
// and the triangles are partitioned together, recursively, until a leaf tests every ray against
// every triangle. Ray sampling (Nabata, Iwasaki, Dobashi, Nishita, "Efficient Divide-And-Conquer
// Ray Tracing using Ray Sampling", HPG 2013) picks the split, the traversal order, and when ray
// filtering cannot pay. Without sampling (dacrt-naive) the split is by the surface area heuristic,
// every child filters, and the left child goes first, as in Mora 2011 and Áfra 2012. Only the
// splits of the largest nodes are kept from call to call (top.h, bounded and stated in
// dacrt_memory_bound; top_triangles=0 keeps none), so that a small batch does not pay for every
// triangle near the root.
#pragma once

#include <cstdint>
#include <set>
#include <string>

#include "dacrt/tracer/options.h"

namespace dacrt {

struct DacrtParams {
  bool sampling = true;     // false: dacrt-naive
  int bins = 16;            // K, binned split candidates per node (Wald 2007)
  int leaf_triangles = 16;  // a node with at most this many triangles is a leaf
  // A node with at most leaf_rays rays is a leaf if its leaf_rays × triangles tests stay under
  // leaf_work: with few rays and many triangles, splitting (O(triangles)) is far cheaper than a
  // leaf (O(rays × triangles)). Below the kept top (nodes of under top_triangles) a split costs
  // its binning, partition and filters whatever its rays: with 32 rays and up to 32 triangles a
  // leaf is cheaper (the dragon, 384², 16 spp: 0.92× the render time of 16 and 256).
  int leaf_rays = 32;
  int leaf_work = 1024;
  // The cost C compares a split with its children as leaves; when rays start inside a node (a
  // camera in a room), α is 1 on both sides and no split looks cheaper than a leaf. Nodes with
  // more triangles than this split anyway, by the cheapest candidate.
  int max_leaf_triangles = 64;
  // The cost of a small node's leaf (and of its children as leaves) counts its triangle tests in
  // whole blocks of this many: the vector tests take 16 triangles at a time (TriangleBlock), so a
  // leaf of 20 costs what one of 32 does, and splitting 32 triangles in two pays only if few rays
  // enter both halves. 1: one by one, the paper's model. The same on every CPU, so the recursion
  // does not depend on the vector width.
  int leaf_lanes = 16;
  // A leaf with at least this many rays and no hit filter tests them sixteen at a time against one
  // triangle at a time, when the CPU has AVX-512 and simd is auto (triangle_block.h: RayGroup):
  // each lane keeps its nearest hit in registers, where one ray against a block of sixteen
  // triangles pays per ray for the candidates' masks and branches. 0: never. The same answers.
  int group_rays = 64;
  int sample_size = 100;        // rays drawn to estimate α
  int sample_threshold = 1000;  // sample only above this many active rays
  // At or below sample_threshold: `sah` splits by the surface area heuristic, orders the children
  // by the direction of up to 16 rays along the split axis and filters both (estimating α would
  // cost as many box tests as filtering, and skipping rarely pays for few triangles); `all`
  // estimates α of every candidate from every ray, the literal reading of the paper, which costs
  // 2(K−1) box tests per ray in each of the many small nodes of incoherent batches.
  bool small_nodes_sah = true;
  // The widest vector tests to use when the CPU has them: `auto` filters 16 rays per AVX-512
  // instruction and leaves test eight triangles per AVX2 instruction, `avx2` filters 8 rays per
  // instruction, `none` uses the scalar tests only. All give bit-identical answers (see
  // triangle_block.h and box_mask in dacrt.cpp), so the recursion is the same.
  enum class Simd : uint8_t { none, avx2, avx512 };
  Simd simd = Simd::avx512;
  // Skip filtering a child when its sampled α exceeds this; negative = the paper's rule
  // α > 1 − C_T / (N_child · C_I). Children without a sampled α are always filtered.
  double filter_skip_alpha = -1.0;
  double cost_traversal = 1.0;  // C_T, relative cost of the box tests of one split
  double cost_intersect = 1.0;  // C_I, relative cost of one ray/triangle test
  uint64_t seed = 1;            // ray sampling's random stream
  int max_depth = 512;          // recursion bound; deeper nodes become leaves
  // A node with at least this many rays runs its two children as parallel tasks (rays that need
  // both visit the second child after the first, as in one thread; see Traversal::fork).
  int task_rays = 8192;
  // A batch of at least 2 × task_rays rays is cut into up to this many chunks (no more than the
  // threads), traced at once, each with its own copy of the triangle records.
  int chunks = 2;
  // Nodes of at least this many triangles are kept from call to call (tracer/dacrt/top.h): split
  // once, by the SAH, so that a call pays for its rays at the top levels, not for every triangle.
  // 0: nothing is kept, every call is pure per-call DACRT.
  int top_triangles = 64;
  // A kept node reached by at most this many rays of a call sends each of them through the rest
  // of the kept top on its own (Traversal::walk), a BVH traversal one ray at a time: with few rays
  // a node's filtering and order cost more than the box tests they share. 0: never.
  int walk_rays = 0;

  static const std::set<std::string, std::less<>>& keys();
  // Reads every key of keys() from the options (filter_skip=paper or a number).
  static DacrtParams from(const Options& options, bool sampling);
};

// The most memory one dacrt or dacrt-naive call uses beyond its inputs and outputs, known before
// it starts: a 36-byte record per ray and a 20-byte record per triangle for each chunk (both kept
// from call to call), the kept top levels' nodes, and 64 KiB of bookkeeping, however many threads
// trace. Nothing is allocated per node.
uint64_t dacrt_memory_bound(uint64_t rays, uint64_t triangles, const DacrtParams& params = {});

}  // namespace dacrt
