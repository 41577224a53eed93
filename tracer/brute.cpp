// brute: every ray against every triangle. Slow by design; it is the oracle the other backends are
// tested against, so it stays as simple as the shared ray and triangle tests allow.
#include <tbb/parallel_for.h>

#include <atomic>

#include "dacrt/tracer/backend.h"
#include "dacrt/tracer/triangle.h"

namespace dacrt {
namespace {

class Brute final : public Backend {
 public:
  Brute(const Geometry& g, const Options& options)
      : frames_(frames_option(options, "brute", Update::rebuild)) {
    options.check_known("backend brute", {"frames"});
    copy(g);
  }

  // Nothing is built: refit and rebuild both copy the new corners.
  Update update(const Geometry& g) override {
    if (frames_ == Update::none) return Update::none;
    const bool same = 3 * g.size() == corners_.size();  // `g` may be geometry_, re-made
    copy(g);
    rays_ = 0;
    return same ? Update::rebuild : Update::build;
  }

  void do_intersect(const RayBatch& rays, HitBatch& hits, const HitFilter* filter) override {
    hits.resize(rays.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, rays.size(), 64), [&](auto range) {
      for (size_t i = range.begin(); i != range.end(); ++i) {
        hits.prim[i] = HitBatch::miss;
        hits.t[i] = rays.tmax[i];
        hits.u[i] = hits.v[i] = 0.f;
        if (!Ray::valid(rays.origin(i), rays.direction(i), rays.tmin[i], rays.tmax[i])) continue;
        Ray r = Ray::shear(rays, i);
        for (uint32_t tri = 0; tri < geometry_->size(); ++tri) {
          TriangleHit h;
          if (!intersect_triangle(r, corners_[3 * tri], corners_[3 * tri + 1],
                                  corners_[3 * tri + 2], rays.tmin[i], hits.t[i], h) ||
              !closer(h.t, tri, hits.t[i], &hits.prim[i]) ||
              rejected(filter, rays, uint32_t(i), tri, h.u, h.v))
            continue;
          hits.t[i] = h.t, hits.u[i] = h.u, hits.v[i] = h.v, hits.prim[i] = tri;
        }
      }
    });
    count(rays.size());
  }

  void do_occluded(const RayBatch& rays, std::span<uint8_t> occluded,
                   const HitFilter* filter) override {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, rays.size(), 64), [&](auto range) {
      for (size_t i = range.begin(); i != range.end(); ++i) {
        occluded[i] = 0;
        if (!Ray::valid(rays.origin(i), rays.direction(i), rays.tmin[i], rays.tmax[i])) continue;
        Ray r = Ray::shear(rays, i);
        for (uint32_t tri = 0; tri < geometry_->size() && !occluded[i]; ++tri) {
          TriangleHit h;
          occluded[i] = intersect_triangle(r, corners_[3 * tri], corners_[3 * tri + 1],
                                           corners_[3 * tri + 2], rays.tmin[i], rays.tmax[i], h) &&
                        !rejected(filter, rays, uint32_t(i), tri, h.u, h.v);
        }
      }
    });
    count(rays.size());
  }

  Stats stats() const override {
    Stats s;
    s.rays = rays_;
    s.triangle_tests = rays_ * geometry_->size();
    return s;
  }

 private:
  void count(size_t n) { rays_ += n; }
  void copy(const Geometry& g) {
    geometry_ = &g;
    corners_.resize(3 * g.size());
    for (size_t i = 0; i < g.size(); ++i)
      for (int c = 0; c < 3; ++c) corners_[3 * i + size_t(c)] = g.vertex(i, c);
  }

  const Update frames_;
  const Geometry* geometry_ = nullptr;
  std::vector<glm::vec3> corners_;  // the triangles' corners, contiguous: 3 per triangle
  std::atomic<uint64_t> rays_{0};
};

const Backend::Registration registration{
    "brute", [](const Geometry& g, const Options& o) { return std::make_unique<Brute>(g, o); }};

}  // namespace
}  // namespace dacrt
