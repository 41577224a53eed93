// embree: Intel Embree 3 as the yardstick for our DACRT kernel, configured for speed the way a
// renderer would use it: one device, one scene committed once at create(), one triangle geometry
// with its own vertex and index buffers (3 unshared vertices per triangle, so Embree's primID is
// our triangle index), rays traced in parallel blocks of rtcIntersect1M/rtcOccluded1M with
// flush-to-zero on and no per-ray allocation; primary batches carry the COHERENT context flag.
//
// Options: quality=low|medium|high (default medium), robust=0|1 (default 1), frames=rebuild|
// refit|new (default rebuild): how the next frame of an animation is followed (update()). rebuild
// writes the new positions into the vertex buffer and commits the scene again: a new BVH of the
// chosen quality on the same device and buffers. refit builds the scene as Embree advises for
// deforming meshes: a two-level scene (scene quality low, RTC_SCENE_FLAG_DYNAMIC) whose one
// triangle geometry has RTC_BUILD_QUALITY_REFIT, so that a commit after new vertices refits the
// geometry's BVH (its quality option is then ignored). new: a new backend each frame. Measured on the dragon
// (871k triangles, 2 threads, Embree 3.13.5 picking AVX-512; the machine was shared, so times are
// process CPU time / 2, medians of 5; primary = 1024² pinhole, bounce = 237k hemisphere rays from
// the primary hits, random = 500k rays in the box):
//                      build s     primary Mrays/s  bounce Mrays/s  random Mrays/s
//   robust=1 medium    0.28-0.33   20-23            2.7-3.3         3.3-3.9
//   robust=0 medium    0.24-0.34   19-28            3.1-4.3         3.7-4.7
//   robust=1 high      as medium (Embree builds no spatial splits in robust mode)
//   robust=0 high      1.2-1.5     17-22            2.7-3.6         4.0
//   robust=1 low       0.09-0.10   18-20            1.9-2.2         2.7
//   rtcIntersect1 per ray instead of rtcIntersect1M: primary 14-17, incoherent rays the same.
// A minimal Embree program (default flags, rtcIntersect1 in a parallel_for) measured in the same
// runs matched robust=0, so nothing is misconfigured: the gap to DESIGN.md's figures is the load
// (load average ~3 on the 2 cores throughout) and different rays.
// - RTC_SCENE_FLAG_ROBUST: costs ~15-25 % on incoherent rays, but it is what makes Embree a fair
//   stand-in for our watertight kernel: rays from inside a closed jittered sphere leak 118 of 200k
//   with it (all aimed exactly at corners; none of 75k aimed at edges) and 5812 without (2044 at
//   edges); and its hit test takes tnear <= t like ours (without it: tnear < t).
// - MEDIUM: HIGH brings nothing in robust mode and costs 4x the build without it; LOW builds 3x
//   faster but traces incoherent rays ~25 % slower.
//
// Semantics that differ from our kernel: Embree cannot look behind the origin (a negative tmin is
// clamped to 0), is not watertight at shared corners, culls rays that lie exactly in a box face
// along a zero direction component, and breaks ties in t by traversal order rather than by the
// lower triangle index. Invalid rays (NaN, inf, zero direction, tmin > tmax; see Ray::valid) never
// reach Embree.
#include <embree3/rtcore.h>
#include <pmmintrin.h>
#include <tbb/parallel_for.h>
#include <xmmintrin.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <string>

#include "dacrt/tracer/backend.h"
#include "dacrt/tracer/ray.h"

namespace dacrt {
namespace {

const char* error_name(RTCError code) {
  switch (code) {
    case RTC_ERROR_NONE:
      return "no error";
    case RTC_ERROR_UNKNOWN:
      return "unknown error";
    case RTC_ERROR_INVALID_ARGUMENT:
      return "invalid argument";
    case RTC_ERROR_INVALID_OPERATION:
      return "invalid operation";
    case RTC_ERROR_OUT_OF_MEMORY:
      return "out of memory";
    case RTC_ERROR_UNSUPPORTED_CPU:
      return "unsupported CPU";
    case RTC_ERROR_CANCELLED:
      return "cancelled";
  }
  return "error";
}

// Flush-to-zero and denormals-are-zero for the lifetime of one parallel task, as Embree recommends;
// the previous modes come back at the end, so other work on the same TBB worker (our exact kernel)
// keeps IEEE denormals.
class FlushDenormals {
 public:
  FlushDenormals() : ftz_(_MM_GET_FLUSH_ZERO_MODE()), daz_(_MM_GET_DENORMALS_ZERO_MODE()) {
    _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
    _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
  }
  ~FlushDenormals() {
    _MM_SET_FLUSH_ZERO_MODE(ftz_);
    _MM_SET_DENORMALS_ZERO_MODE(daz_);
  }
  FlushDenormals(const FlushDenormals&) = delete;
  FlushDenormals& operator=(const FlushDenormals&) = delete;

 private:
  unsigned ftz_, daz_;
};

// Rays per rtcIntersect1M/rtcOccluded1M call, and per parallel task at least.
constexpr size_t block = 256;

class Embree final : public Backend {
 public:
  Embree(const Geometry& g, const Options& options) {
    options.check_known("backend embree", {"quality", "robust", "frames"});
    frames_ = frames_option(options, "embree", Update::rebuild);
    const std::string quality = options.get("quality", std::string("medium"));
    RTCBuildQuality build_quality;
    if (quality == "low")
      build_quality = RTC_BUILD_QUALITY_LOW;
    else if (quality == "medium")
      build_quality = RTC_BUILD_QUALITY_MEDIUM;
    else if (quality == "high")
      build_quality = RTC_BUILD_QUALITY_HIGH;
    else
      throw Error("backend embree: option quality=" + quality + " is not low, medium or high");
    const int robust = options.get("robust", 1);
    if (robust != 0 && robust != 1)
      throw Error("backend embree: option robust=" + std::to_string(robust) + " is not 0 or 1");
    if (g.size() > std::numeric_limits<uint32_t>::max() / 3)
      throw Error("backend embree: " + std::to_string(g.size()) +
                  " triangles are more than 32-bit vertex indices can address");

    const auto start = std::chrono::steady_clock::now();
    device_ = rtcNewDevice("verbose=0");
    if (!device_)
      throw Error(std::string("backend embree: cannot create an Embree device (") +
                  error_name(rtcGetDeviceError(nullptr)) + ")");
    rtcSetDeviceErrorFunction(device_, on_error, this);
    rtcSetDeviceMemoryMonitorFunction(device_, on_memory, this);
    try {
      scene_ = rtcNewScene(device_);
      throw_if_error();
      // A context filter function applies a call's hit filter when it has one.
      const bool refit = frames_ == Update::refit;
      rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION |
                                   (robust ? RTC_SCENE_FLAG_ROBUST : RTC_SCENE_FLAG_NONE) |
                                   (refit ? RTC_SCENE_FLAG_DYNAMIC : RTC_SCENE_FLAG_NONE));
      if (refit) build_quality = RTC_BUILD_QUALITY_REFIT;
      rtcSetSceneBuildQuality(scene_, refit ? RTC_BUILD_QUALITY_LOW : build_quality);
      quality_ = build_quality;
      // Embree with zero primitives is fine, but a geometry with zero-sized buffers is not worth
      // the risk: an empty scene simply has no geometry.
      if (g.size() > 0) add_triangles(g, build_quality);
      rtcCommitScene(scene_);
      throw_if_error();
    } catch (...) {
      release();
      throw;
    }
    build_seconds_ =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  ~Embree() override { release(); }

  // Same count: the new corners into the vertex buffer, committed (Embree refits or rebuilds as
  // the geometry's quality says). Another count: the geometry replaced by a new one.
  Update update(const Geometry& g) override {
    if (frames_ == Update::none) return Update::none;
    Update how = frames_;
    if (g.size() > std::numeric_limits<uint32_t>::max() / 3)
      throw Error("backend embree: " + std::to_string(g.size()) +
                  " triangles are more than 32-bit vertex indices can address");
    if (g.size() == triangles_ && geometry_) {
      auto* vertices =
          static_cast<float*>(rtcGetGeometryBufferData(geometry_, RTC_BUFFER_TYPE_VERTEX, 0));
      write_vertices(g, vertices, nullptr);
      rtcUpdateGeometryBuffer(geometry_, RTC_BUFFER_TYPE_VERTEX, 0);
      rtcCommitGeometry(geometry_);
    } else {
      how = Update::build;
      if (geometry_) rtcDetachGeometry(scene_, 0);
      geometry_ = nullptr;
      triangles_ = 0;
      if (g.size() > 0) add_triangles(g, quality_);
    }
    rtcCommitScene(scene_);
    throw_if_error();
    rays_ = 0;
    peak_bytes_ = current_bytes_.load();
    return how;
  }
  Embree(const Embree&) = delete;
  Embree& operator=(const Embree&) = delete;

  void do_intersect(const RayBatch& rays, HitBatch& hits, const HitFilter* filter) override {
    hits.resize(rays.size());
    in_blocks(rays, filter, [&](RTCIntersectContext& context, size_t first, size_t last) {
      alignas(64) RTCRayHit rh[block];
      uint32_t index[block];
      unsigned m = 0;
      for (size_t i = first; i < last; ++i) {
        hits.prim[i] = HitBatch::miss;
        hits.t[i] = rays.tmax[i];
        hits.u[i] = hits.v[i] = 0.f;
        float tnear;
        if (!live(rays, i, tnear)) continue;
        RTCRayHit& r = rh[m];
        set_ray(r.ray, rays, i, tnear);
        r.hit.geomID = r.hit.primID = RTC_INVALID_GEOMETRY_ID;
        r.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        index[m++] = uint32_t(i - first);
      }
      if (m == 0) return;
      rtcIntersect1M(scene_, &context, rh, m, sizeof(RTCRayHit));
      for (unsigned k = 0; k < m; ++k) {
        if (rh[k].hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
        const size_t i = first + index[k];
        hits.prim[i] = rh[k].hit.primID;
        hits.t[i] = rh[k].ray.tfar;
        hits.u[i] = rh[k].hit.u;
        hits.v[i] = rh[k].hit.v;
      }
    });
  }

  void do_occluded(const RayBatch& rays, std::span<uint8_t> occluded,
                   const HitFilter* filter) override {
    in_blocks(rays, filter, [&](RTCIntersectContext& context, size_t first, size_t last) {
      alignas(64) RTCRay ray[block];
      uint32_t index[block];
      unsigned m = 0;
      for (size_t i = first; i < last; ++i) {
        occluded[i] = 0;
        float tnear;
        if (!live(rays, i, tnear)) continue;
        set_ray(ray[m], rays, i, tnear);
        index[m++] = uint32_t(i - first);
      }
      if (m == 0) return;
      rtcOccluded1M(scene_, &context, ray, m, sizeof(RTCRay));
      for (unsigned k = 0; k < m; ++k)
        occluded[first + index[k]] = ray[k].tfar == -std::numeric_limits<float>::infinity();
    });
  }

  Stats stats() const override {
    Stats s;
    s.rays = rays_;
    s.build_seconds = build_seconds_;
    s.peak_bytes = uint64_t(std::max<int64_t>(peak_bytes_, 0));
    return s;
  }

 private:
  // Calls body(context, first, last) for blocks of at most `block` rays of the batch, in parallel,
  // each task with denormals flushed and one intersect context (COHERENT for primary batches).
  template <typename Body>
  void in_blocks(const RayBatch& rays, const HitFilter* filter, const Body& body) {
    const size_t n = rays.size();
    const bool coherent = rays.type == RayType::primary;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, block), [&](const auto& range) {
      FlushDenormals flush;
      FilterContext context;
      rtcInitIntersectContext(&context);
      if (coherent) context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
      if (filter) context.filter = filter_hits;
      context.hit_filter = filter;
      context.rays = &rays;
      for (size_t first = range.begin(); first < range.end(); first += block)
        body(context, first, std::min(first + block, range.end()));
    });
    throw_if_error();
    rays_ += n;
  }

  void add_triangles(const Geometry& g, RTCBuildQuality quality) {
    const size_t n = g.size();
    RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    throw_if_error();
    rtcSetGeometryBuildQuality(geometry, quality);
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3 * n));
    auto* indices = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), n));
    if (!vertices || !indices) {
      rtcReleaseGeometry(geometry);
      throw_if_error();
      throw Error("backend embree: cannot allocate the triangle buffers");
    }
    write_vertices(g, vertices, indices);
    rtcCommitGeometry(geometry);
    rtcAttachGeometryByID(scene_, geometry, 0);
    rtcReleaseGeometry(geometry);  // the scene holds it now
    throw_if_error();
    geometry_ = geometry, triangles_ = n;
  }

  // 3 unshared vertices per triangle; and their indices, when `indices` is not null.
  static void write_vertices(const Geometry& g, float* vertices, uint32_t* indices) {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, g.size(), 4096), [&](const auto& range) {
      for (size_t tri = range.begin(); tri != range.end(); ++tri)
        for (int corner = 0; corner < 3; ++corner) {
          const size_t vertex = 3 * tri + size_t(corner);
          for (int axis = 0; axis < 3; ++axis)
            vertices[3 * vertex + size_t(axis)] = g.corners[tri][size_t(corner)][axis];
          if (indices) indices[vertex] = uint32_t(vertex);
        }
    });
  }

  // Whether ray i goes to Embree at all, and its tnear. Embree must never see NaN or inf in the
  // origin, direction or tnear, and its ray segment starts at 0 or later. Nor an origin or
  // direction component beyond its FLT_LARGE (1.844e18): its RayK::valid() asserts on them (a
  // scene scaled by 1e19, tests/stress_test.cpp), so such rays miss here.
  static bool live(const RayBatch& rays, size_t i, float& tnear) {
    if (!Ray::valid(rays.origin(i), rays.direction(i), rays.tmin[i], rays.tmax[i])) return false;
    const glm::vec3 o = glm::abs(rays.origin(i)), d = glm::abs(rays.direction(i));
    if (std::max({o.x, o.y, o.z, d.x, d.y, d.z}) > 1.844e18f) return false;
    tnear = std::max(rays.tmin[i], 0.f);
    return std::isfinite(tnear) && tnear <= rays.tmax[i];
  }

  // The intersect context, with what the hit filter needs.
  struct FilterContext : RTCIntersectContext {
    const HitFilter* hit_filter;
    const RayBatch* rays;
  };
  // Embree's barycentrics are ours ((1 − u − v)·p0 + u·p1 + v·p2); ray.id is the batch index.
  static void filter_hits(const RTCFilterFunctionNArguments* args) {
    const auto* c = static_cast<const FilterContext*>(args->context);
    for (unsigned j = 0; j < args->N; ++j)
      if (args->valid[j] &&
          rejected(c->hit_filter, *c->rays, RTCRayN_id(args->ray, args->N, j),
                   RTCHitN_primID(args->hit, args->N, j), RTCHitN_u(args->hit, args->N, j),
                   RTCHitN_v(args->hit, args->N, j)))
        args->valid[j] = 0;
  }

  static void set_ray(RTCRay& r, const RayBatch& rays, size_t i, float tnear) {
    r.org_x = rays.ox[i], r.org_y = rays.oy[i], r.org_z = rays.oz[i];
    r.dir_x = rays.dx[i], r.dir_y = rays.dy[i], r.dir_z = rays.dz[i];
    r.tnear = tnear;
    r.tfar = rays.tmax[i];
    r.time = 0.f;
    r.mask = ~0u;
    r.id = uint32_t(i);
    r.flags = 0;
  }

  // Embree reports errors through this callback; throwing across its C API (and out of its TBB
  // tasks) is not safe, so the first error is kept and thrown as dacrt::Error when the call
  // returns to us.
  static void on_error(void* self, RTCError code, const char* message) {
    auto* e = static_cast<Embree*>(self);
    std::lock_guard lock(e->error_mutex_);
    if (!e->error_.empty()) return;
    e->error_ = std::string("backend embree: Embree error: ") + error_name(code);
    if (message && *message) e->error_ += std::string(": ") + message;
    e->error_ = one_line(std::move(e->error_));
    e->has_error_ = true;
  }

  void throw_if_error() {
    if (!has_error_) return;
    std::lock_guard lock(error_mutex_);
    std::string message = std::move(error_);
    error_.clear();
    has_error_ = false;
    throw Error(message);
  }

  // Every allocation and release of the device (bytes < 0 for releases): the peak is the
  // acceleration structure, the buffers and the builder's temporary memory.
  static bool on_memory(void* self, ssize_t bytes, bool /*post*/) {
    auto* e = static_cast<Embree*>(self);
    const int64_t now = e->current_bytes_ += int64_t(bytes);
    int64_t peak = e->peak_bytes_.load(std::memory_order_relaxed);
    while (now > peak && !e->peak_bytes_.compare_exchange_weak(peak, now)) {
    }
    return true;
  }

  void release() {
    if (scene_) rtcReleaseScene(scene_);
    if (device_) rtcReleaseDevice(device_);
    scene_ = nullptr;
    device_ = nullptr;
  }

  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  RTCGeometry geometry_ = nullptr;  // the scene's one triangle geometry (held by the scene)
  size_t triangles_ = 0;            // in it
  Update frames_ = Update::rebuild;
  RTCBuildQuality quality_ = RTC_BUILD_QUALITY_MEDIUM;  // the geometry's
  double build_seconds_ = 0.0;
  std::atomic<uint64_t> rays_{0};
  std::atomic<int64_t> current_bytes_{0}, peak_bytes_{0};
  std::mutex error_mutex_;
  std::string error_;
  std::atomic<bool> has_error_{false};
};

const Backend::Registration registration{
    "embree", [](const Geometry& g, const Options& o) { return std::make_unique<Embree>(g, o); }};

}  // namespace
}  // namespace dacrt
