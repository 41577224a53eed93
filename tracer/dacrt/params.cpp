// DacrtParams: the kernel's options, read from --backend-option KEY=VALUE and checked.
#include "dacrt/tracer/backend.h"
#include "dacrt/tracer/dacrt/dacrt.h"

namespace dacrt {

const std::set<std::string, std::less<>>& DacrtParams::keys() {
  static const std::set<std::string, std::less<>> k = {
      "bins",           "leaf_rays",      "leaf_work",
      "leaf_triangles", "sample_size",    "sample_threshold",
      "filter_skip",    "cost_traversal", "cost_intersect",
      "seed",           "max_depth",      "max_leaf_triangles",
      "small_nodes",    "simd",           "task_rays",
      "chunks",         "top_triangles",  "leaf_lanes",
      "group_rays",     "walk_rays"};
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
  p.leaf_lanes = o.get("leaf_lanes", p.leaf_lanes);
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
  p.top_triangles = o.get("top_triangles", p.top_triangles);
  p.group_rays = o.get("group_rays", p.group_rays);
  p.walk_rays = o.get("walk_rays", p.walk_rays);
  if (p.walk_rays < 0) throw Error("option walk_rays must be >= 0 (0: never)");
  if (p.group_rays < 0) throw Error("option group_rays must be >= 0 (0: never)");
  if (p.top_triangles < 0) throw Error("option top_triangles must be >= 0 (0: keep no top levels)");
  std::string small = o.get("small_nodes", std::string("sah"));
  if (small != "sah" && small != "all") throw Error("option small_nodes must be sah or all");
  p.small_nodes_sah = small == "sah";
  std::string simd = o.get("simd", std::string("auto"));
  if (simd != "auto" && simd != "avx2" && simd != "none")
    throw Error("option simd must be auto, avx2 or none");
  p.simd = simd == "auto" ? Simd::avx512 : simd == "avx2" ? Simd::avx2 : Simd::none;
  if (p.bins < 2 || p.bins > 256) throw Error("option bins must be in [2, 256]");
  if (p.leaf_rays < 1 || p.leaf_triangles < 1 || p.leaf_work < 1 || p.max_leaf_triangles < 1 ||
      p.leaf_lanes < 1)
    throw Error(
        "options leaf_rays, leaf_triangles, leaf_work, max_leaf_triangles and leaf_lanes must be "
        ">= 1");
  if (p.sample_size < 1 || p.sample_threshold < p.sample_size)
    throw Error("option sample_size must be >= 1 and <= sample_threshold");
  if (p.max_depth < 1) throw Error("option max_depth must be at least 1");
  if (p.task_rays < 1 || p.chunks < 1) throw Error("options task_rays and chunks must be >= 1");
  return p;
}

}  // namespace dacrt
