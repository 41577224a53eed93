// The kept top levels of the DACRT tree (see top.h): built once by the SAH, in parallel.
#include "dacrt/tracer/dacrt/top.h"

#include <tbb/parallel_for.h>
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

void TopLevels::refit(const TriangleRef* tris) {
  using Child = Traversal::Split::Child;
  // The children below the kept levels, from their records, in parallel (n records in all).
  tbb::parallel_for(tbb::blocked_range<size_t>(0, nodes.size(), 64), [&](const auto& range) {
    for (size_t i = range.begin(); i != range.end(); ++i)
      for (Child& c : nodes[i].split.children) {
        if (c.kept >= 0) continue;
        Box box, centres;
        for (uint32_t j = c.tb; j < c.te; ++j) {
          const TriangleRef& r = tris[j];
          const float step = r.step();
          glm::vec3 hi, centre;
          for (int a = 0; a < 3; ++a) hi[a] = r.hi(a, step), centre[a] = r.center(a, step);
          box.extend(glm::vec3(r.lo[0], r.lo[1], r.lo[2]));
          box.extend(hi);
          centres.extend(centre);
        }
        c.box = box, c.centres = centres;
      }
  });
  // A node's index is above its parent's (taken before its children are built): from the last,
  // every kept child is done before its parent.
  for (size_t i = nodes.size(); i-- > 0;) {
    Traversal::Split& split = nodes[i].split;
    for (Child& c : split.children) {
      if (c.kept < 0) continue;
      const Traversal::Split& below = nodes[size_t(c.kept)].split;
      c.box = below.children[0].box, c.centres = below.children[0].centres;
      c.box.extend(below.children[1].box), c.centres.extend(below.children[1].centres);
    }
    Box centres = split.children[0].centres;
    centres.extend(split.children[1].centres);
    const int axis = centres.longest_axis();
    nodes[i].axis = axis;
    if (split.children[0].centres.center()[axis] > split.children[1].centres.center()[axis])
      std::swap(split.children[0], split.children[1]);
  }
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
