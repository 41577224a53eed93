// The kept top levels of the DACRT tree (see top.h): built once by the SAH, in parallel.
#include "dacrt/tracer/dacrt/top.h"

#include <tbb/task_group.h>

namespace dacrt::kernel {

void TopLevels::build(const Kernel& k, TriangleRef* tris, uint32_t n, const Box& bounds,
                      const Box& centres) {
  nodes.assign(max_nodes(n, k.params), Node{});
  count_ = 0;
  levels_ = 0;
  static const RayBatch no_rays;
  Traversal t{k, nullptr, nullptr, nullptr, no_rays, nullptr, tris, nullptr, Pcg32(0), {}};
  if (!nodes.empty() && build_node(t, bounds, centres, 0, n, 0) < 0) count_ = 0;
  nodes.resize(count_);
  levels = nodes.empty() ? 0 : levels_.load();
}

int32_t TopLevels::build_node(Traversal& t, const Box& box, const Box& centres, uint32_t tb,
                              uint32_t te, int depth) {
  const DacrtParams& p = t.k.params;
  if (te - tb < uint32_t(p.top_triangles) || depth >= p.max_depth) return -1;
  Traversal::Split split = t.choose_split(box, centres, tb, te, 0, 0, /*by_area=*/true);
  if (!split.valid) return -1;
  const uint32_t index = count_.fetch_add(1);
  if (index >= nodes.size()) return -1;  // the bound is reached: the rest splits anew per call
  Traversal::Split::Child& a = split.children[0];
  Traversal::Split::Child& b = split.children[1];
  auto build_child = [&](Traversal& own, Traversal::Split::Child& c) {
    c.kept = build_node(own, c.box, c.centres, c.tb, c.te, depth + 1);
  };
  if (te - tb >= 65536) {  // large: the right child on another thread
    Traversal other{t.k,     nullptr, nullptr, nullptr,  t.batch,
                    nullptr, t.tris,  nullptr, Pcg32(0), {}};
    tbb::task_group group;
    group.run([&] { build_child(other, b); });
    build_child(t, a);
    group.wait();
  } else {
    build_child(t, a);
    build_child(t, b);
  }
  nodes[index] = {split, centres.longest_axis()};
  for (int seen = levels_.load(); seen < depth + 1;)  // levels_ = max(levels_, depth + 1)
    if (levels_.compare_exchange_weak(seen, depth + 1)) break;
  return int32_t(index);
}

}  // namespace dacrt::kernel
