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

#include "tracer/geometry.h"
#include "tracer/options.h"
#include "tracer/ray_batch.h"
#include "tracer/stats.h"

namespace dacrt {

class Backend {
 public:
  virtual ~Backend() = default;

  // The geometry must outlive the backend. Throws Error for an unknown name or bad options.
  static std::unique_ptr<Backend> create(std::string_view name, const Geometry& geometry,
                                         const Options& options = {});
  static std::vector<std::string> names();

  // Fills `hits` (resized to the batch) with the closest hit in [tmin, tmax]; ties in t go to the
  // lower triangle index, so every backend of ours gives the same answer bit for bit.
  virtual void intersect(const RayBatch& rays, HitBatch& hits) = 0;
  // occluded[i] = 1 if any triangle is hit in [tmin, tmax], else 0. `occluded.size()` >= rays.
  virtual void occluded(const RayBatch& rays, std::span<uint8_t> occluded) = 0;
  virtual Stats stats() const = 0;

  using Factory = std::function<std::unique_ptr<Backend>(const Geometry&, const Options&)>;
  struct Registration {
    Registration(std::string name, Factory factory);
  };
};

}  // namespace dacrt
