// Backend: a ray-query engine over one Geometry. It answers whole batches: the closest hit of every
// ray (intersect) or whether anything lies on each ray's [tmin, tmax] (occluded). Backends register
// themselves by name with one static Backend::Registration line and are created by name.
// Names: dacrt (default: divide-and-conquer with ray sampling), dacrt-naive (the same kernel
// without sampling), brute (the oracle), embree (Embree 3, the yardstick; when built with it).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "dacrt/tracer/geometry.h"
#include "dacrt/tracer/options.h"
#include "dacrt/tracer/ray_batch.h"
#include "dacrt/tracer/stats.h"

namespace dacrt {

// A hit filter lets the renderer see through parts of triangles (alpha-masked and alpha-blended
// materials, the "any-hit" test): a hit on a triangle whose `tests` flag is set counts only if
// accept() says so. Backends ask before the hit can end or shorten the ray, so closest hits and
// occlusion both pass rejected points. accept() must be thread-safe and a function of (ray,
// triangle, u, v) alone: a backend may test the same triangle more than once for one ray.
class HitFilter {
 public:
  explicit HitFilter(std::vector<uint8_t> tested) : tested_(std::move(tested)) {}
  virtual ~HitFilter() = default;
  bool tests(uint32_t tri) const { return tested_[tri] != 0; }
  // Ray `ray` of `rays` meets triangle `tri` at barycentrics (u, v): does it stop there?
  virtual bool accept(const RayBatch& rays, uint32_t ray, uint32_t tri, float u, float v) const = 0;

 private:
  std::vector<uint8_t> tested_;  // per triangle
};

class Backend {
 public:
  virtual ~Backend() = default;

  // The geometry must outlive the backend. Throws Error for an unknown name or bad options.
  static std::unique_ptr<Backend> create(std::string_view name, const Geometry& geometry,
                                         const Options& options = {});
  static std::vector<std::string> names();

  // Fills `hits` (resized to the batch) with the closest hit in [tmin, tmax]; ties in t go to the
  // lower triangle index, so every backend of ours gives the same answer bit for bit. With a
  // filter, only hits it accepts count (null: every hit).
  void intersect(const RayBatch& rays, HitBatch& hits, const HitFilter* filter = nullptr) {
    do_intersect(rays, hits, filter);
  }
  // occluded[i] = 1 if any triangle is hit in [tmin, tmax] (and accepted by the filter), else 0.
  // `occluded.size()` >= rays.
  void occluded(const RayBatch& rays, std::span<uint8_t> occluded,
                const HitFilter* filter = nullptr) {
    do_occluded(rays, occluded, filter);
  }
  virtual Stats stats() const = 0;

  // How a backend follows the next frame of an animation (update()).
  enum class Update {
    refit,    // its structure kept, its boxes recomputed for the new positions
    rebuild,  // its structure built anew for the new positions, on the memory it has
    build,    // as rebuild, because the triangle count changed (a refit cannot follow that)
    none,     // it does not follow (option frames=new): the caller creates a new backend
  };
  // The triangles moved: from now on the backend answers for `geometry` (which must outlive it;
  // the object it was created with, re-made in place, or another), whose triangle count may
  // differ. Answers are the same bit for bit as a new backend's on `geometry` (ties go to the
  // lower triangle index whatever the structure); statistics and the random streams start again.
  // Not concurrent with intersect() or occluded(). The default follows nothing.
  virtual Update update(const Geometry& geometry) {
    (void)geometry;
    return Update::none;
  }
  // The option every backend takes, frames=refit|rebuild|new (`fallback` when not given): how
  // update() follows a frame. Throws Error naming `backend` for another value.
  static Update frames_option(const Options& options, std::string_view backend, Update fallback);

  using Factory = std::function<std::unique_ptr<Backend>(const Geometry&, const Options&)>;
  struct Registration {
    Registration(std::string name, Factory factory);
  };

 protected:
  virtual void do_intersect(const RayBatch& rays, HitBatch& hits, const HitFilter* filter) = 0;
  virtual void do_occluded(const RayBatch& rays, std::span<uint8_t> occluded,
                           const HitFilter* filter) = 0;
};

// True if `filter` (maybe null) turns down ray i's hit on `tri` at (u, v).
const char* to_string(Backend::Update how);

inline bool rejected(const HitFilter* filter, const RayBatch& rays, uint32_t i, uint32_t tri,
                     float u, float v) {
  return filter && filter->tests(tri) && !filter->accept(rays, i, tri, u, v);
}

}  // namespace dacrt
