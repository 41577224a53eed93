// Traversal: one walk of the DACRT recursion over a range of ray records and a range of triangle
// records, both partitioned in place (traversal.cpp: nodes, leaves, filtering, forks; split.cpp:
// the split choice). It allocates nothing, so a call's memory is known before it starts.
#pragma once

#include <array>
#include <cstdint>

#include "dacrt/tracer/dacrt/records.h"
#include "dacrt/tracer/ray_batch.h"
#include "dacrt/tracer/stats.h"
#include "dacrt/tracer/triangle.h"
#include "dacrt/util/random.h"

namespace dacrt {
class HitFilter;
struct TriangleBlock;
}  // namespace dacrt

namespace dacrt::kernel {

struct TopLevels;

// What every traversal of one backend shares: the geometry, the options, the scene's magnitude
// (for the box tests' pad).
struct Kernel {
  const Geometry& geometry;
  const DacrtParams& params;
  float magnitude;
};

// choose_split's scratch. choose_split returns before the recursion goes on and never waits for
// other tasks, so one set per thread serves every node of every traversal (and keeps recursion
// frames small).
struct SplitScratch {
  struct Bin {
    Box box, centres;
    uint32_t count = 0;
  };
  // Per candidate split: sampled rays that hit the left / right box, and that enter it first.
  struct Counts {
    std::array<uint32_t, 256> left, right, left_first, right_first;  // sample_splits zeroes them
  };
  std::array<Bin, 256> bins{};
  std::array<Box, 256> left_box{}, right_box{};
  std::array<uint32_t, 256> left_n{}, right_n{};
  Counts counts{};
};

// A traversal of a subtree: a range of ray records and a range of triangle records, both
// partitioned in place. Allocates nothing, so a call's memory is known before it starts. Large
// nodes run their second child as a parallel task on its own Traversal (see fork).
struct Traversal {
  const Kernel& k;
  RayRef* rays;                 // the call's live rays
  HitBatch* hits;               // closest-hit mode; null for occlusion
  uint8_t* occluded;            // occlusion mode; null for closest hit
  const RayBatch& batch;        // the call's rays, as given (for the hit filter)
  const HitFilter* hit_filter;  // null: every hit counts
  TriangleRef* tris;            // every triangle
  const TopLevels* top;         // the kept top of the tree (null: every node splits anew)
  Pcg32 rng;
  Stats stats;

  struct Split {
    bool valid = false;  // false: no split beats a leaf
    struct Child {
      Box box;
      Box centres;  // of its triangles' boxes
      uint32_t tb, te;
      double alpha;       // fraction of sampled rays that hit the child's box; -1 if not sampled
      int32_t kept = -1;  // its node in the kept top levels, or -1: it splits anew (node())
    };
    std::array<Child, 2> children;  // in traversal order
  };

  void node(const Box& box, const Box& centres, uint32_t tb, uint32_t te, uint32_t rb, uint32_t re,
            int depth);
  void children(const Split& split, uint32_t rb, uint32_t re, int depth);
  void fork(const Split& split, uint32_t rb, uint32_t re, int depth);
  // A node of the kept top levels: its split is stored; this call's rays only choose the order of
  // its children and whether to filter for them (ray sampling on the two boxes).
  void kept_node(int32_t index, uint32_t rb, uint32_t re, int depth);
  // A kept node of at most walk_rays rays: each ray walks the kept subtree on its own, the nearer
  // child first, and the frontier nodes it reaches are entered with that ray alone.
  void walk(int32_t index, uint32_t r, int depth);
  void enter(const Split::Child& c, uint32_t rb, uint32_t re, int depth) {
    if (c.kept >= 0) return kept_node(c.kept, rb, re, depth);
    node(c.box, c.centres, c.tb, c.te, rb, re, depth);
  }
  // Sets the children's α and traversal order of a stored split from this call's rays.
  void order_kept(Split& split, int axis, uint32_t rb, uint32_t re);
  // A node of nr rays estimates α (above sample_threshold, or everywhere with small_nodes=all).
  bool samples_alpha(uint32_t nr) const;
  // The rays α is estimated from, moved to the front of [rb, re): a random subset of sample_size
  // above the threshold, else all of them. Returns how many.
  uint32_t alpha_samples(uint32_t rb, uint32_t re);
  void order_by_direction(uint32_t rb, uint32_t nr, int axis, uint32_t& first_l,
                          uint32_t& first_r) const;
  // by_area: by the SAH whatever the options (the kept top levels, which no rays choose).
  Split choose_split(const Box& box, const Box& centres, uint32_t tb, uint32_t te, uint32_t rb,
                     uint32_t re, bool by_area = false);
  bool skips_filter(const Split::Child& c);
  void leaf(uint32_t tb, uint32_t te, uint32_t rb, uint32_t re);
  // A hit the ray keeps: occlusion marks the ray and drops it from every later box test and leaf;
  // a closest hit replaces the ray's hit if it is closer() (nearest t, then the lower triangle).
  void occlude(RayRef& ref) {
    occluded[ref.id] = 1;
    ref.far = -inf;
  }
  void keep_if_closer(RayRef& ref, uint32_t tri, const TriangleHit& h) {
    const uint32_t i = ref.id;
    if (!closer(h.t, tri, ref.far, &hits->prim[i])) return;
    ref.far = h.t;
    hits->t[i] = h.t, hits->u[i] = h.u, hits->v[i] = h.v, hits->prim[i] = tri;
  }
  // leaf() for the rays [rb, re) and the triangles of blocks[0..nb), sixteen rays at a time
  // (grouped_leaf.cpp; AVX-512, no hit filter, at most 2^27 rays).
  void grouped_leaf(const TriangleBlock* blocks, int nb, uint32_t rb, uint32_t re);
  // The same, eight rays at a time with AVX2.
  void grouped_leaf_avx2(const TriangleBlock* blocks, int nb, uint32_t rb, uint32_t re);
  uint32_t filter(const Box& box, uint32_t rb, uint32_t re, bool hits_first = true);
  void sample_splits(const Box* left, const Box* right, int n, uint32_t rb, uint32_t samples,
                     SplitScratch::Counts& counts);
  uint32_t draw_samples(uint32_t rb, uint32_t re, uint32_t wanted);
};

}  // namespace dacrt::kernel
