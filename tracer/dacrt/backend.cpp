// The dacrt and dacrt-naive backends: a call's ray records, the triangle records kept from call
// to call, the cut of large batches into chunks, and the statistics (the recursion itself is in
// traversal.cpp and split.cpp).
#include "dacrt/tracer/backend.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>

#include <chrono>
#include <cstring>
#include <memory>
#include <mutex>
#include <set>
#include <string>

#include "dacrt/tracer/dacrt/dacrt.h"
#include "dacrt/tracer/dacrt/top.h"
#include "dacrt/tracer/dacrt/traversal.h"

namespace dacrt {
namespace {

using namespace kernel;

class Dacrt final : public Backend {
 public:
  Dacrt(const Geometry& g, const Options& options, bool sampling)
      : geometry_(&g),
        params_(DacrtParams::from(options, sampling)),
        frames_(frames_option(options, sampling ? "dacrt" : "dacrt-naive", Update::refit)) {
    std::set<std::string, std::less<>> keys = DacrtParams::keys();
    keys.insert("frames");
    options.check_known(sampling ? "backend dacrt" : "backend dacrt-naive", keys);
    auto start = std::chrono::steady_clock::now();
    build(g);
    build_seconds_ =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  // A frame's new positions. `rebuild` (and `build`, for a new triangle count) is the
  // constructor's build on the memory the backend has; `refit` keeps the kept top's splits: each
  // record is encoded again in place (the ranges the top's children own hold the same triangles
  // in whatever order earlier calls left them), and the top's boxes are recomputed from the
  // records, bottom-up (TopLevels::refit). Either way the backend starts again as a new one
  // would: statistics, the calls' random streams.
  Update update(const Geometry& g) override {
    if (frames_ == Update::none) return Update::none;
    std::lock_guard lock(buffer_mutex_);
    // (`g` may be the object the backend has, re-made: the count it had is the records'.)
    const Update how = g.size() != triangles_.front().refs.size() ? Update::build : frames_;
    geometry_ = &g;
    if (how == Update::refit) {
      Triangles& first = triangles_.front();
      // The second chunk's records are copied from the first's after: until then, scratch.
      bounds_ = first.reencode(g, triangles_.size() > 1 ? triangles_[1].refs : scratch_);
      kernel_ = std::make_unique<Kernel>(Kernel{g, params_, bounds_.magnitude()});
      if (!top_.nodes.empty()) top_.refit(first.refs.data());
    } else {
      build(g);
    }
    for (size_t c = 1; c < triangles_.size(); ++c) triangles_[c] = triangles_.front();
    calls_ = 0;
    std::lock_guard stats_lock(stats_mutex_);
    stats_ = {};
    return how;
  }

  void do_intersect(const RayBatch& rays, HitBatch& hits, const HitFilter* filter) override {
    hits.resize(rays.size());  // every ray's miss is written by trace's first pass
    trace(rays, &hits, nullptr, filter);
  }

  void do_occluded(const RayBatch& rays, std::span<uint8_t> occluded,
                   const HitFilter* filter) override {
    trace(rays, nullptr, occluded.data(), filter);  // which writes every ray's 0 first
  }

  Stats stats() const override {
    std::lock_guard lock(stats_mutex_);
    Stats s = stats_;
    s.build_seconds = build_seconds_;
    return s;
  }

  const Geometry* geometry_;
  const DacrtParams params_;
  const Update frames_;

 private:
  // The bounds, the first chunk's triangle records, and the kept top levels on them, before any
  // copy is made, so that every chunk's copy has their order (below them each call reorders
  // within their ranges). This is the backend's build: what every call finds ready.
  void build(const Geometry& g) {
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
    kernel_ = std::make_unique<Kernel>(Kernel{g, params_, bounds_.magnitude()});
    Triangles& first = triangles_.empty() ? triangles_.emplace_back() : triangles_.front();
    first.encode(g);
    top_.nodes.clear();
    if (params_.top_triangles > 0 && !bounds_.empty())
      top_.build(*kernel_, first.refs.data(), uint32_t(g.size()), bounds_, first.centres);
  }

  void trace(const RayBatch& batch, HitBatch* hits, uint8_t* occluded, const HitFilter* filter) {
    const size_t n = batch.size();
    // Records for the live rays, in batch order; the rest never enter the recursion. Built in one
    // parallel pass, which also sets every ray's answer to a miss: each block writes its live rays
    // from its own start, and only if some rays were not live are the blocks moved together after
    // (rare: NaN or empty rays).
    auto live = [&](size_t i) {
      return Ray::valid(batch.origin(i), batch.direction(i), batch.tmin[i], batch.tmax[i]);
    };
    constexpr size_t block = 16384;
    const size_t blocks = (n + block - 1) / block;
    // The ray and triangle records are kept from call to call (no page faults, nothing zeroed,
    // triangles encoded once); a call that finds them in use by a concurrent one makes its own.
    std::unique_lock buffer_lock(buffer_mutex_, std::try_to_lock);
    const bool own_buffers = buffer_lock.owns_lock();
    Array<RayRef> own_rays;
    std::vector<Triangles> own_triangles;
    RayRef* refs;
    std::vector<Triangles>* triangles = &own_triangles;
    if (own_buffers) {
      if (ray_buffer_.size() < n) {
        ray_buffer_ = {};  // freed before the larger one is allocated
        ray_buffer_.resize(n);
      }
      refs = ray_buffer_.data();
      triangles = &triangles_;
    } else {
      own_rays.resize(n);
      refs = own_rays.data();
    }
    std::vector<size_t> live_in(blocks, 0);
    tbb::parallel_for(size_t(0), blocks, [&](size_t b) {
      size_t out = b * block;
      const size_t end = std::min(n, (b + 1) * block);
      if (hits) {
        std::fill(hits->prim.begin() + b * block, hits->prim.begin() + end, HitBatch::miss);
        std::copy(batch.tmax.begin() + b * block, batch.tmax.begin() + end,
                  hits->t.begin() + b * block);
        std::fill(hits->u.begin() + b * block, hits->u.begin() + end, 0.f);
        std::fill(hits->v.begin() + b * block, hits->v.begin() + end, 0.f);
      } else {
        std::fill(occluded + b * block, occluded + end, uint8_t(0));
      }
      for (size_t i = b * block; i < end; ++i) {
        if (!live(i)) continue;
        refs[out++] = {batch.origin(i), batch.direction(i), batch.tmin[i], batch.tmax[i],
                       uint32_t(i)};
      }
      live_in[b] = out - b * block;
    });
    size_t count = 0;
    for (size_t b = 0; b < blocks; ++b) {
      if (count != b * block)
        std::memmove(refs + count, refs + b * block, live_in[b] * sizeof(RayRef));
      count += live_in[b];
    }
    // Large batches are cut into chunks that trace at once, each with its own triangle records:
    // right from the root every thread has work. Inside a chunk, large nodes hand subtrees to
    // other threads (Traversal::fork), which also evens out chunks that take unequal time.
    const size_t threads = size_t(std::max(1, tbb::this_task_arena::max_concurrency()));
    const size_t chunks =
        std::min({threads, size_t(params_.chunks), std::max<size_t>(1, count / params_.task_rays)});
    // A concurrent call cannot copy the kept records (the call that owns them is reordering
    // them), so it encodes its own, which have no kept top.
    if (triangles->empty()) triangles->emplace_back().encode(*geometry_);
    const TopLevels* top = own_buffers && !top_.nodes.empty() ? &top_ : nullptr;
    while (triangles->size() < chunks) triangles->push_back(triangles->front());
    const uint64_t call = calls_++;
    Stats total;
    std::mutex total_mutex;
    tbb::parallel_for(size_t(0), chunks, [&](size_t c) {
      const uint32_t rb = uint32_t(count * c / chunks), re = uint32_t(count * (c + 1) / chunks);
      Triangles& own = (*triangles)[c];
      Traversal t{*kernel_,
                  refs,
                  hits,
                  occluded,
                  batch,
                  filter,
                  own.refs.data(),
                  top,
                  Pcg32(hash(params_.seed, call, c)),
                  {}};
      if (top && rb < re)
        t.kept_node(0, rb, re, 0);
      else if (!bounds_.empty() && rb < re)
        t.node(bounds_, own.centres, 0, uint32_t(geometry_->size()), rb, re, 0);
      std::lock_guard lock(total_mutex);
      total += t.stats;
    });
    total.rays = n;
    uint64_t bytes = (own_buffers ? ray_buffer_.size() : own_rays.size()) * sizeof(RayRef) +
                     triangles->size() * geometry_->size() * sizeof(TriangleRef) +
                     (top ? top_.nodes.capacity() * sizeof(TopLevels::Node) : 0);
    std::lock_guard lock(stats_mutex_);
    stats_ += total;
    stats_.peak_bytes = std::max(stats_.peak_bytes, bytes);
  }

  struct Triangles {
    Array<TriangleRef> refs;  // every triangle, in any order
    Box centres;              // of their boxes

    // Each triangle's record, in index order, and the box of their centres.
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
    // The same records for moved triangles (the same count), each where the one for its triangle
    // was: encoded in index order into `scratch` (the geometry read in order), then gathered.
    // Returns the box of the triangles' corners.
    Box reencode(const Geometry& g, Array<TriangleRef>& scratch) {
      scratch.resize(g.size());
      auto unite = [](Box x, const Box& y) {
        x.extend(y);
        return x;
      };
      const Box corners = tbb::parallel_reduce(
          tbb::blocked_range<uint32_t>(0, uint32_t(g.size()), 16384), Box(),
          [&](const auto& range, Box box) {
            for (uint32_t i = range.begin(); i != range.end(); ++i) {
              scratch[i] = TriangleRef::encode(g, i);
              for (int c = 0; c < 3; ++c) box.extend(g.vertex(i, c));
            }
            return box;
          },
          unite);
      centres = tbb::parallel_reduce(
          tbb::blocked_range<uint32_t>(0, uint32_t(g.size()), 16384), Box(),
          [&](const auto& range, Box box) {
            constexpr uint32_t ahead = 16;  // random reads: several in flight at once
            for (uint32_t i = range.begin(); i != range.end(); ++i) {
              if (i + ahead < range.end()) __builtin_prefetch(&scratch[refs[i + ahead].id]);
              const TriangleRef& r = refs[i] = scratch[refs[i].id];
              const float step = r.step();
              box.extend(glm::vec3(r.center(0, step), r.center(1, step), r.center(2, step)));
            }
            return box;
          },
          unite);
      return corners;
    }
  };
  std::mutex buffer_mutex_;           // held by the call that uses the records below
  std::vector<Triangles> triangles_;  // one per chunk
  Array<RayRef> ray_buffer_;          // on huge pages where they are advised (ray_batch.h)
  TopLevels top_;                     // built with the first records
  // update()'s, when there is one chunk only (with two, the second's records serve; either way
  // no more than the `chunks` copies dacrt_memory_bound counts, unless chunks=1).
  Array<TriangleRef> scratch_;
  Box bounds_;
  std::unique_ptr<Kernel> kernel_;
  double build_seconds_ = 0.0;
  std::atomic<uint64_t> calls_{0};  // numbers each call's random stream
  mutable std::mutex stats_mutex_;
  Stats stats_;
};

}  // namespace

uint64_t dacrt_memory_bound(uint64_t rays, uint64_t triangles, const DacrtParams& params) {
  // Bookkeeping: the per-block ray counts (one size_t per 16384 rays), the chunks' record
  // vectors, and an allowance for the task scheduler's own allocations (measured: a few hundred
  // bytes per call).
  const uint64_t bookkeeping = 8 * (rays / 16384 + 2) + 65536;
  return rays * sizeof(RayRef) + uint64_t(params.chunks) * triangles * sizeof(TriangleRef) +
         TopLevels::max_nodes(triangles, params) * sizeof(TopLevels::Node) + bookkeeping;
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
