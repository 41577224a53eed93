// The recursion: a node splits (split.cpp) or is a leaf; children are entered in the chosen order,
// each with the rays that reach its box (filtered), or with all of them when filtering cannot pay.
#include "dacrt/tracer/dacrt/traversal.h"

#include <tbb/task_group.h>

#include <atomic>

#include "dacrt/tracer/backend.h"
#include "dacrt/tracer/dacrt/box_simd.h"
#include "dacrt/tracer/dacrt/top.h"
#include "dacrt/tracer/partition.h"
#include "dacrt/tracer/triangle.h"
#include "dacrt/tracer/triangle_block.h"

namespace dacrt::kernel {

void Traversal::leaf(uint32_t tb, uint32_t te, uint32_t rb, uint32_t re) {
  ++stats.leaves;
  stats.leaf_rays += re - rb;
  const Geometry& g = k.geometry;
  // Records a hit of ray `ref` on triangle `tri` (already accepted by the triangle test) unless
  // the hit filter turns it down.
  auto record = [&](RayRef& ref, uint32_t tri, const TriangleHit& h) {
    if (rejected(hit_filter, batch, ref.id, tri, h.u, h.v)) return;
    if (occluded)
      occlude(ref);
    else
      keep_if_closer(ref, tri, h);
  };
  if (k.params.simd < Simd::avx2 || !avx2_available()) {
    for (uint32_t r = rb; r < re; ++r) {
      RayRef& ref = rays[r];
      if (!(ref.far >= ref.tmin)) continue;  // occluded already
      // The same shear as every other backend's, so t is bit for bit theirs.
      const Ray ray = Ray::shear(ref.o, ref.d);
      for (uint32_t j = tb; j < te && ref.far >= ref.tmin; ++j) {
        const uint32_t tri = tris[j].id;
        ++stats.triangle_tests;
        TriangleHit h;
        if (intersect_triangle(ray, g.vertex(tri, 0), g.vertex(tri, 1), g.vertex(tri, 2), ref.tmin,
                               ref.far, h))
          record(ref, tri, h);
      }
    }
    return;
  }
  // Up to 64 triangles at a time in blocks of sixteen, loaded once for all the leaf's rays, and
  // tested sixteen lanes per instruction with AVX-512 (else eight with AVX2): one ray against a
  // block, or, in a leaf of many rays (group_rays), sixteen (eight) rays against one triangle.
  const bool wide = k.params.simd >= Simd::avx512 && avx512_available();
  // (grouped_leaf addresses its rays by 32-bit offsets: at most 2^27 records.)
  const bool grouped = !hit_filter && k.params.group_rays > 0 &&
                       re - rb >= uint32_t(k.params.group_rays) && re - rb <= (1u << 27);
  constexpr uint32_t group = 64, lanes = TriangleBlock::lanes;
  std::array<TriangleBlock, group / lanes> blocks;
  for (uint32_t g0 = tb; g0 < te; g0 += group) {
    const uint32_t g1 = std::min(te, g0 + group);
    // Every triangle the blocks read, requested at once: a leaf's triangles are scattered over the
    // geometry, and each triangle's loads waiting on the cache misses before them were most of a
    // leaf's time. (A triangle's 36 bytes span one cache line or two.)
    for (uint32_t j = g0; j < g1; ++j) {
      const char* corners = reinterpret_cast<const char*>(&g.corners[tris[j].id]);
      __builtin_prefetch(corners);
      __builtin_prefetch(corners + sizeof(Geometry::Corners) - 1);
    }
    int nb = 0;
    for (uint32_t j = g0; j < g1; j += lanes, ++nb) {
      uint32_t ids[lanes];
      const int count = int(std::min(lanes, g1 - j));
      for (int l = 0; l < count; ++l) ids[l] = tris[j + l].id;
      blocks[nb].load(g, ids, count);
    }
    if (grouped) {
      if (wide)
        grouped_leaf(blocks.data(), nb, rb, re);
      else
        grouped_leaf_avx2(blocks.data(), nb, rb, re);
      continue;
    }
    for (uint32_t r = rb; r < re; ++r) {
      RayRef& ref = rays[r];
      if (!(ref.far >= ref.tmin)) continue;
      const Ray ray = Ray::shear(ref.o, ref.d);
      for (int b = 0; b < nb && ref.far >= ref.tmin; ++b) {
        const TriangleBlock& block = blocks[b];
        stats.triangle_tests += block.n;
        // The vector test's lanes, then each candidate in lane order (the tie rule makes the
        // order irrelevant for the answer): sure lanes have their t, u and v bit for bit, exact
        // ones only need t in double, the rest take the scalar test.
        BlockHits bh;
        if (wide)
          block_hits_avx512(block, ray, ref.tmin, ref.far, bh);
        else
          block_hits_avx2(block, ray, ref.tmin, ref.far, bh);
        const uint32_t sure = bh.sure, exact = bh.exact,
                       candidates = bh.sure | bh.exact | bh.unsure;
        for (uint32_t m = candidates; m && ref.far >= ref.tmin; m &= m - 1) {
          const int l = std::countr_zero(m);
          const uint32_t tri = block.id[l];
          TriangleHit h;
          if (sure >> l & 1u) {
            if (!(bh.t[l] <= ref.far)) continue;  // a hit found since is nearer
            h = {bh.t[l], bh.e1[l] / bh.det[l], bh.e2[l] / bh.det[l]};
            record(ref, tri, h);
          } else if (exact >> l & 1u) {
            if (exact_lane_hit(bh, l, ray, g.vertex(tri, 0), g.vertex(tri, 1), g.vertex(tri, 2),
                               ref.tmin, ref.far, h))
              record(ref, tri, h);
          } else if (intersect_triangle(ray, g.vertex(tri, 0), g.vertex(tri, 1), g.vertex(tri, 2),
                                        ref.tmin, ref.far, h)) {
            record(ref, tri, h);
          }
        }
      }
    }
  }
}

// Moves the rays of [rb, re) that may touch `box` to the front (with hits_first false: those that
// cannot); returns the end of them.
__attribute__((noinline)) uint32_t Traversal::filter(const Box& box, uint32_t rb, uint32_t re,
                                                     bool hits_first) {
  stats.box_tests += re - rb;
  const float m = k.magnitude;
  RayRef* mid;
#ifdef DACRT_X86
  auto partition = [&](auto mask) {
    return block_partition(rays + rb, rays + re, [&](const RayRef* p, int n) {
      const uint64_t hit = mask(p, n, box, m);
      return hits_first ? hit : ~hit & (~uint64_t(0) >> (64 - n));
    });
  };
  if (k.params.simd >= Simd::avx512 && avx512_available())
    mid = partition(box_mask_avx512);
  else if (k.params.simd >= Simd::avx2 && avx2_available())
    mid = partition(box_mask_avx2);
  else
#endif
    mid = block_partition_by(rays + rb, rays + re,
                             [&](const RayRef& r) { return r.hits(box, m) == hits_first; });
  return uint32_t(mid - rays);
}

void Traversal::node(const Box& box, const Box& centres, uint32_t tb, uint32_t te, uint32_t rb,
                     uint32_t re, int depth) {
  const DacrtParams& p = k.params;
  const uint32_t nt = te - tb, nr = re - rb;
  if (nt <= uint32_t(p.leaf_triangles) || depth >= p.max_depth ||
      (nr <= uint32_t(p.leaf_rays) && uint64_t(nr) * nt <= uint64_t(p.leaf_work)))
    return leaf(tb, te, rb, re);
  const Split split = choose_split(box, centres, tb, te, rb, re);
  if (!split.valid) return leaf(tb, te, rb, re);
  ++stats.nodes;
  children(split, rb, re, depth);
}

// The children of a split in their order, each with the rays that reach its box (or all of them
// when filtering cannot pay); large nodes as parallel tasks (fork).
void Traversal::children(const Split& split, uint32_t rb, uint32_t re, int depth) {
  if (re - rb >= uint32_t(k.params.task_rays)) return fork(split, rb, re, depth);
  for (const Split::Child& c : split.children) {
    uint32_t end = re;
    if (skips_filter(c))
      ++stats.filter_skips;
    else
      end = filter(c.box, rb, re);
    if (end > rb) enter(c, rb, end, depth + 1);
  }
}

void Traversal::kept_node(int32_t index, uint32_t rb, uint32_t re, int depth) {
  if (re - rb <= uint32_t(k.params.walk_rays) && top->levels <= TopLevels::max_walk_depth) {
    for (uint32_t r = rb; r < re; ++r) walk(index, r, depth);
    return;
  }
  const TopLevels::Node& kept = top->nodes[size_t(index)];
  Split split = kept.split;
  order_kept(split, kept.axis, rb, re);
  ++stats.nodes, ++stats.kept_nodes;
  children(split, rb, re, depth);
}

namespace {

// What a walking ray needs at every node: its record, the inverse direction and pad of the box
// test (Ray::box_hits), computed once.
struct Walker {
  RayRef& ref;
  glm::vec3 inv;
  float pad;
  // Ray::box_hits against the ray's current far, and where the ray enters the box.
  bool enters(const Box& box, float& near) const {
    float n = ref.tmin, f = ref.far;
    for (int a = 0; a < 3; ++a) {
      const float x = (box.lo[a] - pad - ref.o[a]) * inv[a];
      const float y = (box.hi[a] + pad - ref.o[a]) * inv[a];
      n = std::max(n, std::min(x, y));
      f = std::min(f, std::max(x, y));
    }
    near = n;
    return n <= f;
  }
};

}  // namespace

// Below a few rays a node's filtering costs more per ray than the tests it saves (two
// partitions, vector box tests of mostly empty lanes, the sampled order): the rays leave the
// batch's recursion and walk the kept tree one at a time, as a BVH traversal would, the child the
// ray enters first before the other. The second child is tested again after the first with the
// ray's closest hit so far, as filtering tests it after the first child in children(). The same
// conservative box test and the same leaves: the same hits.
void Traversal::walk(int32_t index, uint32_t r, int depth) {
  RayRef& ref = rays[r];
  Walker w{ref, Ray::inverse(ref.d), Ray::pad_for(ref.o, k.magnitude)};
  struct Entry {
    const Split::Child* child;
    float near;
    int depth;
  };
  // The children put aside for later, at most one per level of the kept tree.
  Entry stack[TopLevels::max_walk_depth];
  int size = 0;
  const Split::Child* next = nullptr;
  for (;;) {
    if (!next) {
      const TopLevels::Node& n = top->nodes[size_t(index)];
      ++stats.nodes, ++stats.kept_nodes;
      stats.box_tests += 2;
      const Split::Child &a = n.split.children[0], &b = n.split.children[1];
      float near_a, near_b;
      const bool in_a = w.enters(a.box, near_a), in_b = w.enters(b.box, near_b);
      ++depth;
      if (in_a && in_b) {
        const bool b_first = near_b < near_a;
        stack[size++] = {b_first ? &a : &b, b_first ? near_a : near_b, depth};
        next = b_first ? &b : &a;
      } else if (in_a || in_b) {
        next = in_a ? &a : &b;
      }
    }
    if (next) {
      const Split::Child& c = *next;
      next = nullptr;
      if (c.kept >= 0) {
        index = c.kept;
        continue;
      }
      enter(c, r, r + 1, depth);
    }
    // The next child put aside that the ray still reaches with its closest hit so far (an
    // occluded ray's far is -inf: it reaches none).
    while (size > 0 && !(stack[size - 1].near <= ref.far)) --size;
    if (size == 0) return;
    const Entry& e = stack[--size];
    next = e.child, depth = e.depth;
  }
}

// A large node's children as two tasks. The triangle ranges are disjoint, but a ray may need both
// children, and the second, B, must see the closest hit the first, A, found. So the rays are
// partitioned [rb, b_only) neither box, [b_only, a_begin) only B's, [a_begin, re) A's. A traverses
// its rays here while a task traverses B with the rays only B needs; when both are done, the rays
// of A that still reach B's box (with their new closest hits) traverse B too. If the task only
// starts once A is done (nobody stole it), it traverses B once with all its rays, as one thread
// would: the same box tests, in the same order, as the sequential loop in node().
void Traversal::fork(const Split& split, uint32_t rb, uint32_t re, int depth) {
  const Split::Child &a = split.children[0], &b = split.children[1];
  const bool skip_a = skips_filter(a), skip_b = skips_filter(b);
  stats.filter_skips += skip_a + skip_b;
  // Moves the rays of [from, to) that miss the child to the front and returns their end; a child
  // that skips filtering takes every ray.
  auto misses = [&](const Split::Child& c, bool skip, uint32_t from, uint32_t to) {
    return skip ? from : filter(c.box, from, to, false);
  };
  const uint32_t a_begin = misses(a, skip_a, rb, re);
  const uint32_t b_only = misses(b, skip_b, rb, a_begin);
  // B after A: the rays of [first, from) and those of [from, re) that still reach B's box.
  auto after_a = [&](Traversal& t, uint32_t first, uint32_t from) {
    const uint32_t end = skip_b ? re : t.filter(b.box, from, re);
    if (end > first) t.enter(b, first, end, depth + 1);
  };
  if (b_only == a_begin || a_begin == re) {  // nothing to run beside A
    if (re > a_begin) enter(a, a_begin, re, depth + 1);
    return after_a(*this, b_only, a_begin);
  }
  Traversal task{k, rays, hits, occluded, batch, hit_filter, tris, top, Pcg32(rng.next()), {}};
  std::atomic<bool> a_done{false};
  bool beside = false;  // the task ran while A was running
  tbb::task_group group;
  group.run([&] {
    if (a_done.load(std::memory_order_acquire)) return after_a(task, b_only, a_begin);
    beside = true;
    ++task.stats.tasks;
    task.enter(b, b_only, a_begin, depth + 1);
  });
  enter(a, a_begin, re, depth + 1);
  a_done.store(true, std::memory_order_release);
  group.wait();
  stats += task.stats;
  if (beside) after_a(*this, a_begin, a_begin);
}

}  // namespace dacrt::kernel
