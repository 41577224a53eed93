// Wavefront: the loop every integrator runs, with stream regeneration. Up to
// RenderSettings::wavefront paths are alive at once; whenever paths end, new camera samples take
// their slots, so every iteration hands the backend full batches until the samples asked drain.
// Each iteration runs pbrt-v4's wavefront stages, each over whole queues:
//   camera rays (free slots) → intersect → first hits (AOVs) → the integrator's shading (which
//   ends paths, pushes shadow rays and bounce rays) → shadow rays → film.
// An integrator is the shading stage: it derives from Wavefront and implements shade().
//
// The image depends only on (seed, pixel, sample, dimension): it is the same bit for bit for any
// thread count and for every exact backend, and the same up to the order of the film's sums for
// any wavefront size.
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "dacrt/integrators/dimensions.h"
#include "dacrt/integrators/integrator.h"
#include "dacrt/integrators/light_sampling.h"
#include "dacrt/integrators/queues.h"
#include "dacrt/integrators/sampler.h"
#include "dacrt/materials/gltf_brdf.h"
#include "dacrt/scene/surface.h"
#include "dacrt/tracer/ray_batch.h"
#include "dacrt/util/random.h"

namespace dacrt {

class Wavefront : public Integrator {
 public:
  Wavefront(const Scene& scene, const Shot& shot, Backend& backend, const RenderSettings& settings);
  ~Wavefront() override;

  const RenderStats& stats() const override { return stats_; }
  SampleOrder sample_order(uint32_t first, uint32_t last, uint64_t pixels) const override;
  uint64_t render(Film& film, uint32_t first, uint32_t last, std::span<const uint32_t> only,
                  const std::atomic<bool>* stop, Progress& progress) override;

 protected:
  // The shading stage on one traced batch. It flags the paths that end in ended_ (their
  // radiance goes to the film), and adds shadow rays (with push_rays) and bounce rays.
  virtual void shade(const RayBatch& rays, const HitBatch& hits) = 0;

  // The live paths, by slot (RayBatch::path).
  struct Paths {
    Array<glm::vec3> throughput, radiance;
    Array<uint32_t> pixel, sample;
    Array<float> bsdf_pdf;  // solid-angle pdf of the direction the path's last ray took
    Array<uint32_t> depth;  // scattering events so far: the depth of the vertex it is at
    Array<FirstHit> first;  // what its camera ray saw (only when first_hits_)
    void resize(size_t n, bool first_hits);
  };

  // The path's number of `dim` at its current depth, from the settings' sampler.
  float random(uint32_t path, Dimension dim) const {
    return sampler_.number(paths_.pixel[path], paths_.sample[path], paths_.depth[path], dim);
  }
  // Both numbers of the pair that starts at `first` (bsdf_u, pixel_x…): random(path, first) and
  // random(path, first + 1), computed together.
  std::array<float, 2> random_pair(uint32_t path, Dimension first) const {
    return sampler_.pair(paths_.pixel[path], paths_.sample[path], paths_.depth[path], first);
  }

  // The numbers a vertex draws, for rays [first, first + lanes) of a batch (lanes ≤
  // sampler_lanes), all at once: out[k] for ray first + k, the dimensions `dims` (pairs by their
  // first) at its path's current depth. drawn(dims) is their mask, for VertexDraw.
  void draw(const RayBatch& rays, size_t first, size_t lanes, std::span<const Dimension> dims,
            VertexNumbers* out) const;
  // Asks the cache for the texels that shading the hits among rays [first, end) will read
  // (scene/surface.h: prefetch_surface): a batch's hits are shaded in ray order, a group of
  // sampler_lanes while the texels of a group further on arrive. Nothing in untextured scenes.
  void prefetch_textures(const HitBatch& hits, size_t first, size_t end) const;
  // Asks the cache for what hit_at reads of the hit triangles among rays [first, end): their
  // corners, material, normals, first texture coordinates and tangents, each a miss
  // per hit otherwise. Called a group before prefetch_textures (which reads the coordinates).
  void prefetch_triangles(const HitBatch& hits, size_t first, size_t end) const;
  static uint32_t drawn(std::span<const Dimension> dims) {
    uint32_t mask = 0;
    for (const Dimension d : dims) mask |= (dimension_slots[d].pair ? 3u : 1u) << d;
    return mask;
  }
  // One vertex's numbers: those drawn ahead, else the sampler's (the same numbers either way).
  struct VertexDraw {
    const Wavefront& w;
    uint32_t path, mask;
    const VertexNumbers& drawn;
    float operator()(Dimension dim) const {
      return mask >> dim & 1 ? drawn[dim] : w.random(path, dim);
    }
    std::array<float, 2> pair(Dimension first) const {
      return mask >> first & 1 ? std::array<float, 2>{drawn[first], drawn[first + 1]}
                               : w.random_pair(path, first);
    }
  };

  // A hit as shading sees it: the point, the normals on the side the ray arrived from (the
  // shading normal falls back to the geometric one where it faces away from the viewer), the
  // material there.
  struct Hit {
    glm::vec3 p, ng, ns;
    SurfacePoint surface;
    glm::vec3 p_error;  // p's error bound (spawn_point), for offset_ray_origin
  };
  Hit hit_at(const RayBatch& rays, const HitBatch& hits, uint32_t i) const;
  // The BRDF at hit h of triangle tri: made once per material for those that are the same
  // everywhere (no textures and no vertex colours), else from h's surface.
  GltfBrdf brdf_at(const Hit& h, uint32_t tri) const {
    const std::optional<GltfBrdf>& uniform = uniform_brdf_[scene_.geometry.material[tri]];
    if (uniform) return *uniform;
    const BrdfParams& p = h.surface.brdf;
    return p.clearcoat > 0.f || p.anisotropy > 0.f ? GltfBrdf(framed_params(h)) : GltfBrdf(p);
  }
  // h's BRDF parameters with the clearcoat normal and the anisotropy direction put in the
  // shading frame, Frame(h.ns).
  BrdfParams framed_params(const Hit& h) const;
  // What ray i saw (depth: along the camera's view axis).
  FirstHit first_hit_at(const RayBatch& rays, const HitBatch& hits, uint32_t i) const;

  // The indices of `rays` that missed (hit false) or hit (true), into queue_.
  void select_rays(const HitBatch& hits, size_t n, bool hit);

  // Shadow and bounce rays of the n queued rays: each shading task writes its ray (if any) into
  // scratch_shadow_[q] / scratch_next_[q] and sets has_shadow_[q] / has_next_[q]; push_rays then
  // appends them, in queue order, to shadow_ (with shadow_contribution_) and next_.
  // With queue null, slot q is ray q of `rays` (a stage over the whole batch).
  void scratch_rays(size_t n);
  void push_rays(const RayBatch& rays, const Array<uint32_t>* queue, float shadow_tmin = 0.f);

  const Scene& scene_;
  const Shot shot_;  // the camera, the image size, the lights and the environment
  Backend& backend_;
  const RenderSettings s_;
  const Sampler sampler_;  // s_'s sampler and seed
  RenderStats stats_;
  bool first_hits_;  // capture first-hit values: the film or the integrator needs them
  std::vector<std::optional<GltfBrdf>> uniform_brdf_;  // by material (brdf_at)
  bool textured_ = false;                               // some material reads a texture

  Paths paths_;
  Array<uint8_t> ended_;  // by slot: the path ended in this iteration
  RayBatch next_, shadow_;
  Array<uint32_t> queue_;  // the stage's ray indices
  Array<ShadowRay> scratch_shadow_, scratch_next_;
  Array<glm::vec3> shadow_contribution_;
  Array<uint8_t> has_shadow_, has_next_;

 private:
  class AlphaFilter;

  size_t camera_rays(uint64_t first_id, uint64_t end_id);
  void intersect_and_shade();
  void append(RayBatch& to, const RayBatch& from);
  void trace(const RayBatch& rays, HitBatch& hits, size_t camera);
  void first_hits(const RayBatch& rays, const HitBatch& hits);
  void shadow_rays();
  uint64_t to_film(Film& film);

  std::unique_ptr<AlphaFilter> alpha_;  // null when every material is opaque
  // The pixels render() samples, in sample_order()'s order: those `only` lists, or every pixel;
  // in textured scenes by tiles (tiled_: the image's; only_pixels_: those listed), else in rows
  // (empty: every pixel).
  std::vector<uint32_t> tiled_, only_pixels_;
  std::span<const uint32_t> call_pixels_;
  SampleOrder order_;      // the render call's
  uint64_t begin_id_ = 0;  // its first sample id
  Array<uint32_t> free_;                // slots without a path
  RayBatch camera_, bounce_;
  HitBatch hits_;
  std::vector<uint8_t> occluded_;  // a span for Backend::occluded
  glm::vec3 forward_;              // the camera's view axis, for depth
};

}  // namespace dacrt
