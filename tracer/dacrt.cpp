// The DACRT kernel (see dacrt.h for what it is and where it comes from).
#include "tracer/dacrt.h"

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#define DACRT_X86 1
#endif
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <memory>
#include <mutex>
#include <numeric>

#include "tracer/backend.h"
#include "tracer/partition.h"
#include "tracer/triangle.h"
#include "tracer/triangle_block.h"
#include "util/random.h"

namespace dacrt {

const std::set<std::string, std::less<>>& DacrtParams::keys() {
  static const std::set<std::string, std::less<>> k = {
      "bins",           "leaf_rays",      "leaf_work",
      "leaf_triangles", "sample_size",    "sample_threshold",
      "filter_skip",    "cost_traversal", "cost_intersect",
      "seed",           "max_depth",      "max_leaf_triangles",
      "small_nodes",    "simd",           "task_rays",
      "chunks"};
  return k;
}

DacrtParams DacrtParams::from(const Options& o, bool sampling) {
  DacrtParams p;
  p.sampling = sampling;
  p.bins = o.get("bins", p.bins);
  p.leaf_rays = o.get("leaf_rays", p.leaf_rays);
  p.leaf_work = o.get("leaf_work", p.leaf_work);
  p.max_leaf_triangles = o.get("max_leaf_triangles", p.max_leaf_triangles);
  p.leaf_triangles = o.get("leaf_triangles", p.leaf_triangles);
  p.sample_size = o.get("sample_size", p.sample_size);
  p.sample_threshold = o.get("sample_threshold", p.sample_threshold);
  std::string skip = o.get("filter_skip", std::string("paper"));
  p.filter_skip_alpha = skip == "paper" ? -1.0 : o.get("filter_skip", 0.0);
  p.cost_traversal = o.get("cost_traversal", p.cost_traversal);
  p.cost_intersect = o.get("cost_intersect", p.cost_intersect);
  p.seed = uint64_t(o.get("seed", int(p.seed)));
  p.max_depth = o.get("max_depth", p.max_depth);
  p.task_rays = o.get("task_rays", p.task_rays);
  p.chunks = o.get("chunks", p.chunks);
  std::string small = o.get("small_nodes", std::string("sah"));
  if (small != "sah" && small != "all") throw Error("option small_nodes must be sah or all");
  p.small_nodes_sah = small == "sah";
  std::string simd = o.get("simd", std::string("auto"));
  if (simd != "auto" && simd != "avx2" && simd != "none")
    throw Error("option simd must be auto, avx2 or none");
  p.simd = simd == "auto" ? Simd::avx512 : simd == "avx2" ? Simd::avx2 : Simd::none;
  if (p.bins < 2 || p.bins > 256) throw Error("option bins must be in [2, 256]");
  if (p.leaf_rays < 1 || p.leaf_triangles < 1 || p.leaf_work < 1 || p.max_leaf_triangles < 1)
    throw Error("options leaf_rays, leaf_triangles, leaf_work and max_leaf_triangles must be >= 1");
  if (p.sample_size < 1 || p.sample_threshold < p.sample_size)
    throw Error("option sample_size must be >= 1 and <= sample_threshold");
  if (p.max_depth < 1) throw Error("option max_depth must be at least 1");
  if (p.task_rays < 1 || p.chunks < 1) throw Error("options task_rays and chunks must be >= 1");
  return p;
}

namespace {

constexpr float inf = std::numeric_limits<float>::infinity();
using Simd = DacrtParams::Simd;

// What binning and partitioning read of a triangle, in one 20-byte record, so that a node streams
// through a contiguous range of them instead of gathering from scattered arrays by index. The box
// is stored as its low corner and its extent in 8-bit steps of a power of two, rounded up: a
// slightly larger box (by at most 1/64 of the triangle's own size) is still a bounding box, so
// filtering stays conservative, and the record is half the size of a float box with a centroid.
struct TriangleRef {
  float lo[3];
  uint8_t ext[3];  // hi[a] = lo[a] + ext[a] · 2^exp, evaluated as in hi()
  int8_t exp;      // in [-126, 127]
  uint32_t id;     // index into Geometry

  float step() const { return std::bit_cast<float>(uint32_t(exp + 127) << 23); }
  float hi(int a, float step) const { return lo[a] + float(ext[a]) * step; }
  // The box centre along `a`: where binning puts the triangle.
  float center(int a, float step) const { return lo[a] + 0.5f * (float(ext[a]) * step); }

  static TriangleRef encode(const Geometry& g, uint32_t i) {
    TriangleRef r;
    r.id = i;
    float hi[3], extent = 0.f;
    for (int a = 0; a < 3; ++a) {
      float p0 = g.p[0][a][i], p1 = g.p[1][a][i], p2 = g.p[2][a][i];
      r.lo[a] = std::min({p0, p1, p2});
      hi[a] = std::max({p0, p1, p2});
      extent = std::max(extent, hi[a] - r.lo[a]);
    }
    if (!std::isfinite(extent)) {  // never hits; any box that does not lose it will do
      r.exp = 127;
      r.ext[0] = r.ext[1] = r.ext[2] = 255;
      return r;
    }
    // extent < 2^k; a step of 2^(k-7) needs at most 128 steps (plus a few for rounding), and no
    // fewer than 64 for the longest side. Each count is the fewest steps that reach hi in float
    // arithmetic exactly as hi() evaluates it.
    const int k = int(std::bit_cast<uint32_t>(extent) >> 23) - 126;
    r.exp = int8_t(std::max(-126, k - 7));
    const float step = r.step();
    const float inv_step = std::bit_cast<float>(uint32_t(127 - r.exp) << 23);  // exact
    for (int a = 0; a < 3; ++a) {
      const float steps = (hi[a] - r.lo[a]) * inv_step;
      int q = int(steps);
      q += float(q) < steps;
      r.ext[a] = uint8_t(std::min(q, 255));
      while (r.hi(a, step) < hi[a] && r.ext[a] < 255) ++r.ext[a];
    }
    return r;
  }
};
static_assert(sizeof(TriangleRef) == 20);

// A ray as the recursion sees it, in one 36-byte record that moves with the ray as ranges are
// partitioned: filtering, sampling and leaves never gather from the batch's arrays. The box test's
// inverse direction and pad are recomputed (Ray::inverse, Ray::pad_for) rather than stored: a
// smaller record is less memory to stream at every level, and the vector box test divides eight
// rays at once.
struct RayRef {
  glm::vec3 o, d;  // as in the batch
  float tmin;
  float far;    // running tmax: the closest hit so far, or -inf once occluded
  uint32_t id;  // index into the batch

  bool hits(const Box& box, float magnitude) const {
    return Ray::box_hits(o, Ray::inverse(d), Ray::pad_for(o, magnitude), box, tmin, far);
  }
};
static_assert(sizeof(RayRef) == 36);

class Dacrt;

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
  const Dacrt& k;
  RayRef* rays;                 // the call's live rays
  HitBatch* hits;               // closest-hit mode; null for occlusion
  uint8_t* occluded;            // occlusion mode; null for closest hit
  const RayBatch& batch;        // the call's rays, as given (for the hit filter)
  const HitFilter* hit_filter;  // null: every hit counts
  TriangleRef* tris;            // every triangle
  Pcg32 rng;
  Stats stats;

  struct Split {
    bool valid = false;  // false: no split beats a leaf
    struct Child {
      Box box;
      Box centres;  // of its triangles' boxes
      uint32_t tb, te;
      double alpha;  // fraction of sampled rays that hit the child's box; -1 if not sampled
    };
    std::array<Child, 2> children;  // in traversal order
  };

  void node(const Box& box, const Box& centres, uint32_t tb, uint32_t te, uint32_t rb, uint32_t re,
            int depth);
  void fork(const Split& split, uint32_t rb, uint32_t re, int depth);
  Split choose_split(const Box& box, const Box& centres, uint32_t tb, uint32_t te, uint32_t rb,
                     uint32_t re);
  bool skips_filter(const Split::Child& c);
  void leaf(uint32_t tb, uint32_t te, uint32_t rb, uint32_t re);
  uint32_t filter(const Box& box, uint32_t rb, uint32_t re, bool hits_first = true);
  void sample_splits(const Box* left, const Box* right, int n, uint32_t rb, uint32_t samples,
                     SplitScratch::Counts& counts);
  uint32_t draw_samples(uint32_t rb, uint32_t re, uint32_t wanted);
};

class Dacrt final : public Backend {
 public:
  Dacrt(const Geometry& g, const Options& options, bool sampling)
      : geometry_(g), params_(DacrtParams::from(options, sampling)) {
    options.check_known(sampling ? "backend dacrt" : "backend dacrt-naive", DacrtParams::keys());
    auto start = std::chrono::steady_clock::now();
    bounds_ = tbb::parallel_reduce(
        tbb::blocked_range<size_t>(0, g.size(), 16384), Box(),
        [&](const auto& range, Box box) {
          for (size_t i = range.begin(); i != range.end(); ++i)
            for (int c = 0; c < 3; ++c) box.extend(g.vertex(i, c));
          return box;
        },
        [](Box a, const Box& b) {
          a.extend(b);
          return a;
        });
    magnitude_ = bounds_.magnitude();
    build_seconds_ =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  void do_intersect(const RayBatch& rays, HitBatch& hits, const HitFilter* filter) override {
    hits.resize(rays.size());
    for (size_t i = 0; i < rays.size(); ++i) {
      hits.prim[i] = HitBatch::miss;
      hits.t[i] = rays.tmax[i];
      hits.u[i] = hits.v[i] = 0.f;
    }
    trace(rays, &hits, nullptr, filter);
  }

  void do_occluded(const RayBatch& rays, std::span<uint8_t> occluded,
                   const HitFilter* filter) override {
    std::fill_n(occluded.begin(), rays.size(), uint8_t(0));
    trace(rays, nullptr, occluded.data(), filter);
  }

  Stats stats() const override {
    std::lock_guard lock(stats_mutex_);
    Stats s = stats_;
    s.build_seconds = build_seconds_;
    return s;
  }

  const Geometry& geometry_;
  const DacrtParams params_;

 public:
  float magnitude() const { return magnitude_; }

 private:
  void trace(const RayBatch& batch, HitBatch* hits, uint8_t* occluded, const HitFilter* filter) {
    const size_t n = batch.size();
    // Records for the live rays, in batch order; the rest never enter the recursion. Built in
    // parallel: live rays counted per block, then each block writes at its offset.
    auto live = [&](size_t i) {
      return Ray::valid(batch.origin(i), batch.direction(i), batch.tmin[i], batch.tmax[i]);
    };
    constexpr size_t block = 16384;
    const size_t blocks = (n + block - 1) / block;
    std::vector<size_t> offset(blocks + 1, 0);
    tbb::parallel_for(size_t(0), blocks, [&](size_t b) {
      for (size_t i = b * block; i < std::min(n, (b + 1) * block); ++i) offset[b + 1] += live(i);
    });
    std::partial_sum(offset.begin(), offset.end(), offset.begin());
    // The ray and triangle records are kept from call to call (no page faults, nothing zeroed,
    // triangles encoded once); a call that finds them in use by a concurrent one makes its own.
    const size_t count = offset[blocks];
    std::unique_lock buffer_lock(buffer_mutex_, std::try_to_lock);
    std::unique_ptr<RayRef[]> own_rays;
    std::vector<Triangles> own_triangles;
    RayRef* refs;
    std::vector<Triangles>* triangles = &own_triangles;
    if (buffer_lock.owns_lock()) {
      if (ray_capacity_ < count) ray_buffer_.reset(), ray_buffer_.reset(new RayRef[count]);
      ray_capacity_ = std::max(ray_capacity_, count);
      refs = ray_buffer_.get();
      triangles = &triangles_;
    } else {
      own_rays.reset(new RayRef[count]);
      refs = own_rays.get();
    }
    tbb::parallel_for(size_t(0), blocks, [&](size_t b) {
      size_t out = offset[b];
      for (size_t i = b * block; i < std::min(n, (b + 1) * block); ++i) {
        if (!live(i)) continue;
        const glm::vec3 d = batch.direction(i);
        refs[out++] = {batch.origin(i), d, batch.tmin[i], batch.tmax[i], uint32_t(i)};
      }
    });
    // Large batches are cut into chunks that trace at once, each with its own triangle records:
    // right from the root every thread has work. Inside a chunk, large nodes hand subtrees to
    // other threads (Traversal::fork), which also evens out chunks that take unequal time.
    const size_t threads = size_t(std::max(1, tbb::this_task_arena::max_concurrency()));
    const size_t chunks =
        std::min({threads, size_t(params_.chunks), std::max<size_t>(1, count / params_.task_rays)});
    if (triangles->empty()) triangles->emplace_back().encode(geometry_);
    while (triangles->size() < chunks) triangles->push_back(triangles->front());
    const uint64_t call = calls_++;
    Stats total;
    std::mutex total_mutex;
    tbb::parallel_for(size_t(0), chunks, [&](size_t c) {
      const uint32_t rb = uint32_t(count * c / chunks), re = uint32_t(count * (c + 1) / chunks);
      Triangles& own = (*triangles)[c];
      Traversal t{*this,
                  refs,
                  hits,
                  occluded,
                  batch,
                  filter,
                  own.refs.data(),
                  Pcg32(hash(params_.seed, call, c)),
                  {}};
      if (!bounds_.empty() && rb < re)
        t.node(bounds_, own.centres, 0, uint32_t(geometry_.size()), rb, re, 0);
      std::lock_guard lock(total_mutex);
      total += t.stats;
    });
    total.rays = n;
    uint64_t bytes = (buffer_lock.owns_lock() ? ray_capacity_ : count) * sizeof(RayRef) +
                     triangles->size() * geometry_.size() * sizeof(TriangleRef);
    std::lock_guard lock(stats_mutex_);
    stats_ += total;
    stats_.peak_bytes = std::max(stats_.peak_bytes, bytes);
  }

  struct Triangles {
    std::vector<TriangleRef> refs;  // every triangle, in any order
    Box centres;                    // of their boxes

    void encode(const Geometry& g) {
      refs.resize(g.size());
      centres = tbb::parallel_reduce(
          tbb::blocked_range<uint32_t>(0, uint32_t(g.size()), 16384), Box(),
          [&](const auto& range, Box box) {
            for (uint32_t i = range.begin(); i != range.end(); ++i) {
              const TriangleRef& r = refs[i] = TriangleRef::encode(g, i);
              const float step = r.step();
              box.extend(glm::vec3(r.center(0, step), r.center(1, step), r.center(2, step)));
            }
            return box;
          },
          [](Box x, const Box& y) {
            x.extend(y);
            return x;
          });
    }
  };
  std::mutex buffer_mutex_;           // held by the call that uses the records below
  std::vector<Triangles> triangles_;  // one per chunk
  std::unique_ptr<RayRef[]> ray_buffer_;
  size_t ray_capacity_ = 0;
  Box bounds_;
  float magnitude_ = 0.f;
  double build_seconds_ = 0.0;
  std::atomic<uint64_t> calls_{0};  // numbers each call's random stream
  mutable std::mutex stats_mutex_;
  Stats stats_;
};

void Traversal::leaf(uint32_t tb, uint32_t te, uint32_t rb, uint32_t re) {
  ++stats.leaves;
  const Geometry& g = k.geometry_;
  // Records a hit of ray `ref` on triangle `tri` (already accepted by the triangle test) unless
  // the hit filter turns it down.
  auto record = [&](RayRef& ref, uint32_t tri, const TriangleHit& h) {
    const uint32_t i = ref.id;
    if (rejected(hit_filter, batch, i, tri, h.u, h.v)) return;
    if (occluded) {
      occluded[i] = 1;
      ref.far = -inf;  // drops out of every later box test and leaf
    } else if (closer(h.t, tri, ref.far, hits->prim[i])) {
      ref.far = h.t;
      hits->t[i] = h.t, hits->u[i] = h.u, hits->v[i] = h.v, hits->prim[i] = tri;
    }
  };
  if (k.params_.simd < Simd::avx2 || !avx2_available()) {
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
  // Up to 64 triangles at a time in blocks of eight, loaded once for all the leaf's rays.
  constexpr uint32_t group = 64;
  std::array<TriangleBlock, group / 8> blocks;
  for (uint32_t g0 = tb; g0 < te; g0 += group) {
    const uint32_t g1 = std::min(te, g0 + group);
    int nb = 0;
    for (uint32_t j = g0; j < g1; j += 8, ++nb) {
      uint32_t ids[8];
      const int count = int(std::min(8u, g1 - j));
      for (int l = 0; l < count; ++l) ids[l] = tris[j + l].id;
      blocks[nb].load(g, ids, count);
    }
    for (uint32_t r = rb; r < re; ++r) {
      RayRef& ref = rays[r];
      if (!(ref.far >= ref.tmin)) continue;
      const Ray ray = Ray::shear(ref.o, ref.d);
      for (int b = 0; b < nb && ref.far >= ref.tmin; ++b) {
        const TriangleBlock& block = blocks[b];
        stats.triangle_tests += block.n;
        // Candidates, then the scalar test on each, in lane order (the tie rule makes the order
        // irrelevant for the answer).
        for (uint32_t m = block_candidates(block, ray, ref.tmin, ref.far); m && ref.far >= ref.tmin;
             m &= m - 1) {
          const int l = std::countr_zero(m);
          const uint32_t tri = block.id[l];
          TriangleHit h;
          if (intersect_triangle(ray, g.vertex(tri, 0), g.vertex(tri, 1), g.vertex(tri, 2),
                                 ref.tmin, ref.far, h))
            record(ref, tri, h);
        }
      }
    }
  }
}

#ifdef DACRT_X86
// Ray::box_hits for the records p[0..n), n <= 64, eight per AVX2 instruction: the same operations
// in the same order (_mm256_min_ps(b, a) is std::min(a, b) exactly, NaN and signed zeros
// included), so the mask is bit for bit the scalar test's. Bit i is p[i]; nothing past p[n - 1] is
// read.
__attribute__((target("avx2"))) uint64_t box_mask_avx2(const RayRef* p, int n, const Box& box,
                                                       float magnitude) {
  static_assert(sizeof(RayRef) == 9 * sizeof(float) && offsetof(RayRef, d) == 12 &&
                offsetof(RayRef, tmin) == 24 && offsetof(RayRef, far) == 28);
  const float* base = reinterpret_cast<const float*>(p);
  const __m256i stride = _mm256_setr_epi32(0, 9, 18, 27, 36, 45, 54, 63);
  __m256 lo[3], hi[3];
  for (int a = 0; a < 3; ++a) lo[a] = _mm256_set1_ps(box.lo[a]), hi[a] = _mm256_set1_ps(box.hi[a]);
  const __m256 sign = _mm256_set1_ps(-0.f), mag = _mm256_set1_ps(magnitude),
               scale = _mm256_set1_ps(0x1p-16f), tiny = _mm256_set1_ps(1e-30f),
               one = _mm256_set1_ps(1.f);
  const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  uint64_t mask = 0;
  for (int g = 0; 8 * g < n; ++g) {
    const float* r = base + 72 * g;
    // Lanes past the last record gather nothing (and give 0, a ray that hits nothing: dropped).
    const __m256 live = _mm256_castsi256_ps(_mm256_cmpgt_epi32(_mm256_set1_epi32(n - 8 * g), lane));
    __m256 o[3], inv[3];
    for (int a = 0; a < 3; ++a) {
      o[a] = _mm256_mask_i32gather_ps(_mm256_setzero_ps(), r + a, stride, live, 4);
      // Ray::inverse: 1/d, with |d| < 1e-30 replaced by ±1e-30
      const __m256 d = _mm256_mask_i32gather_ps(_mm256_setzero_ps(), r + 3 + a, stride, live, 4);
      const __m256 small = _mm256_cmp_ps(_mm256_andnot_ps(sign, d), tiny, _CMP_LT_OQ);
      const __m256 clamped = _mm256_or_ps(_mm256_and_ps(sign, d), tiny);
      inv[a] = _mm256_div_ps(one, _mm256_blendv_ps(d, clamped, small));
    }
    __m256 near = _mm256_mask_i32gather_ps(_mm256_setzero_ps(), r + 6, stride, live, 4),
           far = _mm256_mask_i32gather_ps(_mm256_setzero_ps(), r + 7, stride, live, 4);
    // Ray::pad_for: 2^-16 (max |o| + magnitude)
    const __m256 om =
        _mm256_max_ps(_mm256_max_ps(_mm256_andnot_ps(sign, o[0]), _mm256_andnot_ps(sign, o[1])),
                      _mm256_andnot_ps(sign, o[2]));
    const __m256 pad = _mm256_mul_ps(scale, _mm256_add_ps(om, mag));
    for (int a = 0; a < 3; ++a) {
      const __m256 ta = _mm256_mul_ps(_mm256_sub_ps(_mm256_sub_ps(lo[a], pad), o[a]), inv[a]);
      const __m256 tb = _mm256_mul_ps(_mm256_sub_ps(_mm256_add_ps(hi[a], pad), o[a]), inv[a]);
      near = _mm256_max_ps(_mm256_min_ps(tb, ta), near);  // std::max(near, std::min(ta, tb))
      far = _mm256_min_ps(_mm256_max_ps(tb, ta), far);    // std::min(far, std::max(ta, tb))
    }
    const __m256 hit = _mm256_and_ps(_mm256_cmp_ps(near, far, _CMP_LE_OQ), live);
    mask |= uint64_t(uint32_t(_mm256_movemask_ps(hit))) << (8 * g);
  }
  return mask;
}

// GCC 12's AVX-512 headers start masked intrinsics from _mm512_undefined_*(), which
// -Wmaybe-uninitialized reports once inlined (GCC bug 105593, fixed in GCC 13).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

// |x| for AVX512F, which has float logic only as integer logic.
__attribute__((target("avx512f"))) inline __m512 abs_avx512(__m512 x) {
  return _mm512_castsi512_ps(
      _mm512_andnot_epi32(_mm512_set1_epi32(int32_t(0x80000000u)), _mm512_castps_si512(x)));
}

// Field `field` of up to 16 records of 9 floats from r; lanes outside `live` read nothing, give 0.
__attribute__((target("avx512f"))) inline __m512 gather_avx512(const float* r, int field,
                                                               __mmask16 live) {
  const __m512i stride =
      _mm512_mullo_epi32(_mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15),
                         _mm512_set1_epi32(9));
  return _mm512_mask_i32gather_ps(_mm512_setzero_ps(), live, stride, r + field, 4);
}

// box_mask_avx2 sixteen rays per instruction.
__attribute__((target("avx512f"))) uint64_t box_mask_avx512(const RayRef* p, int n, const Box& box,
                                                            float magnitude) {
  const float* base = reinterpret_cast<const float*>(p);
  __m512 lo[3], hi[3];
  for (int a = 0; a < 3; ++a) lo[a] = _mm512_set1_ps(box.lo[a]), hi[a] = _mm512_set1_ps(box.hi[a]);
  const __m512i sign = _mm512_set1_epi32(int32_t(0x80000000u));
  const __m512 mag = _mm512_set1_ps(magnitude), scale = _mm512_set1_ps(0x1p-16f),
               tiny = _mm512_set1_ps(1e-30f), one = _mm512_set1_ps(1.f);
  uint64_t mask = 0;
  for (int g = 0; 16 * g < n; ++g) {
    const float* r = base + 144 * g;
    const int left = n - 16 * g;
    const __mmask16 live = left >= 16 ? __mmask16(0xffff) : __mmask16((1u << left) - 1u);
    __m512 o[3], inv[3];
    for (int a = 0; a < 3; ++a) {
      o[a] = gather_avx512(r, a, live);
      const __m512 d = gather_avx512(r, 3 + a, live);
      const __mmask16 small = _mm512_cmp_ps_mask(abs_avx512(d), tiny, _CMP_LT_OQ);
      const __m512 clamped = _mm512_castsi512_ps(_mm512_or_epi32(
          _mm512_and_epi32(sign, _mm512_castps_si512(d)), _mm512_castps_si512(tiny)));
      inv[a] = _mm512_div_ps(one, _mm512_mask_blend_ps(small, d, clamped));
    }
    __m512 near = gather_avx512(r, 6, live), far = gather_avx512(r, 7, live);
    const __m512 om =
        _mm512_max_ps(_mm512_max_ps(abs_avx512(o[0]), abs_avx512(o[1])), abs_avx512(o[2]));
    const __m512 pad = _mm512_mul_ps(scale, _mm512_add_ps(om, mag));
    for (int a = 0; a < 3; ++a) {
      const __m512 ta = _mm512_mul_ps(_mm512_sub_ps(_mm512_sub_ps(lo[a], pad), o[a]), inv[a]);
      const __m512 tb = _mm512_mul_ps(_mm512_sub_ps(_mm512_add_ps(hi[a], pad), o[a]), inv[a]);
      near = _mm512_max_ps(_mm512_min_ps(tb, ta), near);
      far = _mm512_min_ps(_mm512_max_ps(tb, ta), far);
    }
    mask |= uint64_t(_mm512_mask_cmp_ps_mask(live, near, far, _CMP_LE_OQ)) << (16 * g);
  }
  return mask;
}
#pragma GCC diagnostic pop
#endif

// Moves the rays of [rb, re) that may touch `box` to the front (with hits_first false: those that
// cannot); returns the end of them.
__attribute__((noinline)) uint32_t Traversal::filter(const Box& box, uint32_t rb, uint32_t re,
                                                     bool hits_first) {
  stats.box_tests += re - rb;
  const float m = k.magnitude();
  RayRef* mid;
#ifdef DACRT_X86
  auto partition = [&](auto mask) {
    return block_partition(rays + rb, rays + re, [&](const RayRef* p, int n) {
      const uint64_t hit = mask(p, n, box, m);
      return hits_first ? hit : ~hit & (~uint64_t(0) >> (64 - n));
    });
  };
  if (k.params_.simd >= Simd::avx512 && avx512_available())
    mid = partition(box_mask_avx512);
  else if (k.params_.simd >= Simd::avx2 && avx2_available())
    mid = partition(box_mask_avx2);
  else
#endif
    mid = block_partition_by(rays + rb, rays + re,
                             [&](const RayRef& r) { return r.hits(box, m) == hits_first; });
  return uint32_t(mid - rays);
}

// α estimation: every sampled ray against both boxes of each of the n candidate splits. The
// split loop is branch-free over structure-of-arrays boxes so that it vectorises; it is the same
// conservative slab test as Ray::box_hits.
void Traversal::sample_splits(const Box* left, const Box* right, int n, uint32_t rb,
                              uint32_t samples, SplitScratch::Counts& c) {
  constexpr int max_splits = 256;
  alignas(32) float l_lo[3][max_splits], l_hi[3][max_splits];
  alignas(32) float r_lo[3][max_splits], r_hi[3][max_splits];
  for (int s = 0; s < n; ++s) c.left[s] = c.right[s] = c.left_first[s] = c.right_first[s] = 0;
  for (int s = 0; s < n; ++s)
    for (int a = 0; a < 3; ++a) {
      l_lo[a][s] = left[s].lo[a], l_hi[a][s] = left[s].hi[a];
      r_lo[a][s] = right[s].lo[a], r_hi[a][s] = right[s].hi[a];
    }
  for (uint32_t i = 0; i < samples; ++i) {
    const RayRef& r = rays[rb + i];
    float o[3], inv[3];
    const glm::vec3 inv_d = Ray::inverse(r.d);
    for (int a = 0; a < 3; ++a) o[a] = r.o[a], inv[a] = inv_d[a];
    const float t0 = r.tmin, t1 = r.far, pad = Ray::pad_for(r.o, k.magnitude());
    for (int s = 0; s < n; ++s) {
      float ln = t0, lf = t1, rn = t0, rf = t1;
      for (int a = 0; a < 3; ++a) {
        // (lo - pad - o) * inv, as in Ray::box_hits: the box bound first, then the shift.
        float la = (l_lo[a][s] - pad - o[a]) * inv[a], lb = (l_hi[a][s] + pad - o[a]) * inv[a];
        float ra = (r_lo[a][s] - pad - o[a]) * inv[a], rbb = (r_hi[a][s] + pad - o[a]) * inv[a];
        ln = std::max(ln, std::min(la, lb)), lf = std::min(lf, std::max(la, lb));
        rn = std::max(rn, std::min(ra, rbb)), rf = std::min(rf, std::max(ra, rbb));
      }
      const uint32_t hl = ln <= lf, hr = rn <= rf;
      c.left[s] += hl, c.right[s] += hr;
      c.left_first[s] += hl & (!hr | (ln <= rn));
      c.right_first[s] += hr & (!hl | (rn < ln));
    }
  }
  stats.box_tests += uint64_t(samples) * 2 * n;
}

// Moves a uniform random subset of `wanted` rays of [rb, re) to its front (a partial Fisher-Yates
// shuffle: the order of a range is free) and returns how many it moved; all rays if there are no
// more than wanted.
uint32_t Traversal::draw_samples(uint32_t rb, uint32_t re, uint32_t wanted) {
  const uint32_t nr = re - rb;
  if (nr <= wanted) return nr;
  for (uint32_t s = 0; s < wanted; ++s) std::swap(rays[rb + s], rays[rb + s + rng.below(nr - s)]);
  return wanted;
}

// Bins the node's triangles, estimates α for every candidate split, and partitions the triangles
// by the cheapest one. Its large scratch arrays live only in this frame, never across the
// recursion, so deep trees cannot exhaust a worker thread's stack.
__attribute__((noinline)) Traversal::Split Traversal::choose_split(const Box& box,
                                                                   const Box& centres, uint32_t tb,
                                                                   uint32_t te, uint32_t rb,
                                                                   uint32_t re) {
  const DacrtParams& p = k.params_;
  const uint32_t nt = te - tb, nr = re - rb;
  static thread_local SplitScratch scratch;
  auto& [bins, left_box, right_box, left_n, right_n, counts] = scratch;
  using Bin = SplitScratch::Bin;
  // Binning on triangle box centres along the longest axis of the centres' box (Wald 2007). Each
  // bin also keeps its centres' box, so the children know theirs without another pass.
  const int axis = centres.longest_axis();
  const float lo = centres.lo[axis], extent = centres.hi[axis] - centres.lo[axis];
  const int K = p.bins;
  const float scale = float(K) / extent;
  if (!(extent > 0.f) || !std::isfinite(scale)) return {};  // one centre: make a leaf
  auto bin_of = [&](const TriangleRef& t) {
    return std::min(K - 1, int((t.center(axis, t.step()) - lo) * scale));
  };

  // Interleaved sets of bins, merged after: consecutive triangles in one bin would otherwise wait
  // on each other's updates. Boxes are 4-wide vectors (x, y, z, unused) so that a triangle's
  // decode and its four box updates are one instruction each; the values are exactly the scalar
  // TriangleRef::hi and center.
  using f4 = float __attribute__((vector_size(16)));
  using i4 = int32_t __attribute__((vector_size(16)));
  struct VBin {
    f4 lo, hi, clo, chi;
  };
  // Lane-wise std::min(b, a) / std::max(b, a): the values the scalar Box::extend would give.
  auto vmin = [](f4 a, f4 b) { return a < b ? a : b; };
  auto vmax = [](f4 a, f4 b) { return b < a ? a : b; };
  constexpr int sets = 4;
  VBin vbins[sets][256];
  uint32_t count[sets][256];
  for (int set = 0; set < sets; ++set)
    for (int b = 0; b < K; ++b) {
      vbins[set][b] = {f4{} + inf, f4{} - inf, f4{} + inf, f4{} - inf};
      count[set][b] = 0;
    }
  for (uint32_t j = tb; j < te; ++j) {
    const TriangleRef& t = tris[j];
    const f4 tlo = {t.lo[0], t.lo[1], t.lo[2], 0.f};
    const f4 d = __builtin_convertvector((i4{t.ext[0], t.ext[1], t.ext[2], 0}), f4) * t.step();
    const f4 thi = tlo + d, c = tlo + 0.5f * d;
    const int b = std::min(K - 1, int((c[axis] - lo) * scale));
    VBin& v = vbins[j % sets][b];
    ++count[j % sets][b];
    v.lo = vmin(tlo, v.lo), v.hi = vmax(thi, v.hi);
    v.clo = vmin(c, v.clo), v.chi = vmax(c, v.chi);
  }
  for (int b = 0; b < K; ++b) {
    VBin v = vbins[0][b];
    uint32_t n = count[0][b];
    for (int set = 1; set < sets; ++set) {
      const VBin& w = vbins[set][b];
      v.lo = vmin(w.lo, v.lo), v.hi = vmax(w.hi, v.hi);
      v.clo = vmin(w.clo, v.clo), v.chi = vmax(w.chi, v.chi);
      n += count[set][b];
    }
    Bin& out = bins[b];
    out.count = n;
    for (int a = 0; a < 3; ++a) {
      out.box.lo[a] = v.lo[a], out.box.hi[a] = v.hi[a];
      out.centres.lo[a] = v.clo[a], out.centres.hi[a] = v.chi[a];
    }
  }
  // Split s puts bins [0, s) left and [s, K) right.
  {
    Box acc;
    uint32_t n = 0;
    for (int s = 1; s < K; ++s) {
      acc.extend(bins[s - 1].box), n += bins[s - 1].count;
      left_box[s] = acc, left_n[s] = n;
    }
    acc = Box();
    n = 0;
    for (int s = K - 1; s >= 1; --s) {
      acc.extend(bins[s].box), n += bins[s].count;
      right_box[s] = acc, right_n[s] = n;
    }
  }

  // Ray sampling. Above the threshold (or everywhere with small_nodes=all): α of each side of
  // every candidate from a random subset of the rays, and the split by C = C_T + C_I (α_L N_L +
  // α_R N_R). Ties (all α equal, e.g. every sampled ray starts inside the node) go to the better
  // SAH cost, which also picks the split when a node too large for a leaf must split anyway.
  // Small nodes (and dacrt-naive) pick the split by the SAH's area ratios.
  const bool all_splits = p.sampling && (nr > uint32_t(p.sample_threshold) || !p.small_nodes_sah);
  uint32_t samples = 0;
  if (all_splits) {
    samples = nr > uint32_t(p.sample_threshold) ? draw_samples(rb, re, p.sample_size) : nr;
    sample_splits(&left_box[1], &right_box[1], K - 1, rb, samples, counts);
  }
  auto alpha_cost = [&](uint32_t hit_l, uint32_t hit_r, int split) {
    return p.cost_traversal + p.cost_intersect * (double(hit_l) / samples * left_n[split] +
                                                  double(hit_r) / samples * right_n[split]);
  };
  double best_cost = INFINITY, best_area_cost = INFINITY;
  int best = 0;
  const double parent_area = box.half_area();
  for (int split = 1; split < K; ++split) {
    if (!left_n[split] || !right_n[split]) continue;
    double area_l = parent_area > 0 ? left_box[split].half_area() / parent_area : 1.0;
    double area_r = parent_area > 0 ? right_box[split].half_area() / parent_area : 1.0;
    double area_cost =
        p.cost_traversal + p.cost_intersect * (area_l * left_n[split] + area_r * right_n[split]);
    double cost =
        all_splits ? alpha_cost(counts.left[split - 1], counts.right[split - 1], split) : area_cost;
    if (cost < best_cost || (cost == best_cost && area_cost < best_area_cost))
      best_cost = cost, best_area_cost = area_cost, best = split;
  }
  if (best == 0) return {};
  uint32_t hit_l = 0, hit_r = 0, first_l = 0, first_r = 0;
  if (all_splits) {
    hit_l = counts.left[best - 1], hit_r = counts.right[best - 1];
    first_l = counts.left_first[best - 1], first_r = counts.right_first[best - 1];
  } else if (p.sampling) {
    // Small node: no α (filtering both children is then as cheap as estimating it, and a skip
    // almost never pays for few triangles). Order by where the rays head along the split axis.
    const uint32_t n = std::min(nr, 16u);
    for (uint32_t i = 0; i < n; ++i) first_l += rays[rb + i].d[axis] >= 0.f;
    first_r = n - first_l;
  }
  const double leaf_cost = p.cost_intersect * nt;
  if (best_cost >= leaf_cost && nt <= uint32_t(p.max_leaf_triangles)) return {};

  TriangleRef* tri_mid = block_partition_by(tris + tb, tris + te,
                                            [&](const TriangleRef& t) { return bin_of(t) < best; });
  const uint32_t tm = uint32_t(tri_mid - tris);
  Box left_centres, right_centres;
  for (int b = 0; b < K; ++b) (b < best ? left_centres : right_centres).extend(bins[b].centres);
  Split split{
      true,
      {{{left_box[best], left_centres, tb, tm, all_splits ? double(hit_l) / samples : -1.0},
        {right_box[best], right_centres, tm, te, all_splits ? double(hit_r) / samples : -1.0}}}};
  // Traversal order: first the child that more sampled rays enter first.
  if (p.sampling && first_r > first_l) std::swap(split.children[0], split.children[1]);
  return split;
}

// Filtering costs one box test per ray; it pays only if enough rays miss the child.
bool Traversal::skips_filter(const Split::Child& c) {
  const DacrtParams& p = k.params_;
  const double threshold = p.filter_skip_alpha >= 0
                               ? p.filter_skip_alpha
                               : 1.0 - p.cost_traversal / (double(c.te - c.tb) * p.cost_intersect);
  return c.alpha >= 0.0 && c.alpha > threshold;
}

void Traversal::node(const Box& box, const Box& centres, uint32_t tb, uint32_t te, uint32_t rb,
                     uint32_t re, int depth) {
  const DacrtParams& p = k.params_;
  const uint32_t nt = te - tb, nr = re - rb;
  if (nt <= uint32_t(p.leaf_triangles) || depth >= p.max_depth ||
      (nr <= uint32_t(p.leaf_rays) && uint64_t(nr) * nt <= uint64_t(p.leaf_work)))
    return leaf(tb, te, rb, re);
  const Split split = choose_split(box, centres, tb, te, rb, re);
  if (!split.valid) return leaf(tb, te, rb, re);
  ++stats.nodes;
  if (nr >= uint32_t(p.task_rays)) return fork(split, rb, re, depth);
  for (const Split::Child& c : split.children) {
    uint32_t end = re;
    if (skips_filter(c))
      ++stats.filter_skips;
    else
      end = filter(c.box, rb, re);
    if (end > rb) node(c.box, c.centres, c.tb, c.te, rb, end, depth + 1);
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
    if (end > first) t.node(b.box, b.centres, b.tb, b.te, first, end, depth + 1);
  };
  if (b_only == a_begin || a_begin == re) {  // nothing to run beside A
    if (re > a_begin) node(a.box, a.centres, a.tb, a.te, a_begin, re, depth + 1);
    return after_a(*this, b_only, a_begin);
  }
  Traversal task{k, rays, hits, occluded, batch, hit_filter, tris, Pcg32(rng.next()), {}};
  std::atomic<bool> a_done{false};
  bool beside = false;  // the task ran while A was running
  tbb::task_group group;
  group.run([&] {
    if (a_done.load(std::memory_order_acquire)) return after_a(task, b_only, a_begin);
    beside = true;
    ++task.stats.tasks;
    task.node(b.box, b.centres, b.tb, b.te, b_only, a_begin, depth + 1);
  });
  node(a.box, a.centres, a.tb, a.te, a_begin, re, depth + 1);
  a_done.store(true, std::memory_order_release);
  group.wait();
  stats += task.stats;
  if (beside) after_a(*this, a_begin, a_begin);
}

}  // namespace

uint64_t dacrt_memory_bound(uint64_t rays, uint64_t triangles, const DacrtParams& params) {
  return rays * sizeof(RayRef) + uint64_t(params.chunks) * triangles * sizeof(TriangleRef);
}

namespace {

const Backend::Registration dacrt_registration{"dacrt", [](const Geometry& g, const Options& o) {
                                                 return std::make_unique<Dacrt>(g, o, true);
                                               }};
const Backend::Registration naive_registration{
    "dacrt-naive",
    [](const Geometry& g, const Options& o) { return std::make_unique<Dacrt>(g, o, false); }};

}  // namespace
}  // namespace dacrt
