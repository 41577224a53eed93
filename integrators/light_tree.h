// LightTree: next-event estimation's choice of emitter by how much each may light a given point
// (Conty Estevez & Kulla 2018, "Importance Sampling of Many Lights with Adaptive Tree
// Splitting", as pbrt-v4's BVHLightSampler does it, without the splitting): a tree over the
// emitters, each node bounding its emitters' positions (a box), their power and the directions
// they emit into (a cone of normals widened by their emission's spread). From a shading point, a
// node's importance bounds what its emitters can send there: power × the cosine at the emitter
// of the least angle between its cone and the point × the cosine at the point towards the box
// (with a normal) / squared distance. The descent picks a child in proportion to the children's
// importance, one leaf (one emitter) in the end.
//
// The tree is built binary (pbrt-v4's surface area heuristic for lights), then collapsed so that
// a node has up to eight children (emitters or nodes) side by side: a pick evaluates eight
// children's importance at once (AVX2 where the CPU has it; lane by lane otherwise, with the
// same operations in the same order, so the same bits) and walks about a third of the binary
// tree's levels. (On 4000 lamps, tools/make_many_lights.py: 21 binary levels, 6 wide ones.)
//
// The pick is exact in the alias table's way (util/alias_table.h): the uniform's 24 bits are an
// integer k in [0, R) with R = 2²⁴ (or the units the caller gives the tree), and each node hands
// its children whole parts of R, in proportion to their importance (one unit each to those of
// positive importance first, when R allows; none to a child of importance 0; equal parts when
// all are 0). A leaf's probability is the part it ends with over 2²⁴, and units() walks the same
// nodes with the same arithmetic, so it is the probability sample() realises, bit for bit.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

namespace dacrt {

// How next-event estimation chooses an emitter (integrators/lights.h, --light-sampler).
enum class LightPicking : uint8_t {
  automatic,  // the tree from LightSampler::tree_threshold emitters on, else power
  tree,       // this tree
  power,      // an alias table by power, the same from every point
};

// Where the choice is made from: a point, and the normal of the side that receives light there
// (zero where both sides do: a transmissive surface).
struct LightContext {
  glm::vec3 p{0.f}, n{0.f};
};

class LightTree {
 public:
  // What the tree knows of one emitter.
  struct Bounds {
    glm::vec3 lo{0.f}, hi{0.f};  // of its points
    float power = 0.f;           // > 0
    glm::vec3 w{0.f, 0.f, 1.f};  // the axis of its normals (unit)
    float cos_o = 1.f;           // their spread around w: cos θo (−1: all directions)
    float cos_e = 0.f;           // how far from its normals it emits: cos θe (0: a hemisphere)
    bool two_sided = false;      // it emits around −w as much as around w
  };

  LightTree() = default;
  // One leaf per emitter: the entry its index in `emitters`.
  explicit LightTree(std::span<const Bounds> emitters);

  bool empty() const { return nodes_.empty(); }
  size_t size() const { return leaf_.size(); }
  // Levels below the root (0: the root's children are all leaves), and the nodes.
  int depth() const { return depth_; }
  size_t nodes() const { return nodes_.size(); }

  // The entry picked by k in [0, range) from `at`, and its probability in units (range being
  // all of the tree's, at most 2²⁴): the part of [0, range) that picks it.
  struct Pick {
    uint32_t entry, units;
  };
  Pick sample(uint32_t k, uint32_t range, const LightContext& at) const;
  // The units of [0, range) that pick `entry` from `at` (sample's, exactly; 0 if none does).
  uint32_t units(uint32_t entry, uint32_t range, const LightContext& at) const;

  // The importance of an emitter's or a node's bounds from `at` (see the top): ≥ 0, 0 when it
  // cannot light it.
  static float importance(const Bounds& b, const LightContext& at);

  // Eight children at once: whether this tree's picks use AVX2 (by default where the CPU has
  // it). Either way gives the same bits; tests compare the two.
  bool vectorised() const { return avx2_; }
  void set_vectorised(bool on);
  // The importance of node `node`'s children from `at`, by lane (0 past its children).
  static constexpr int width = 8;
  void child_importance(uint32_t node, const LightContext& at, float out[width]) const;

  // A node: its children's bounds as importance() reads them, side by side (the ball around
  // each one's box, its cone's sine too).
  struct alignas(32) Node {
    float cx[width], cy[width], cz[width], radius2[width];
    float wx[width], wy[width], wz[width];
    float power[width], cos_o[width], sin_o[width], cos_e[width];
    uint32_t sides[width];  // cos θw's bits are and-ed with it: the sign dropped if two-sided
    uint32_t child[width];  // a node, or an entry | leaf_bit
    uint32_t count;         // children, 1 to 8 (lanes past them emit nowhere: cos_e = 2)
  };
  static constexpr uint32_t leaf_bit = 0x80000000u;

 private:
  struct Binary;  // the binary tree of the build
  uint32_t build(std::vector<Binary>& out, std::vector<uint32_t>& order, size_t first,
                 size_t last, std::span<const Bounds> emitters, int depth);
  uint32_t collapse(const std::vector<Binary>& binary, uint32_t root, int depth);
  void importances(const Node& n, const LightContext& at, float out[width]) const;
  // The parts of `range` a node gives its children from `at`: child i gets [bound[i],
  // bound[i + 1]).
  void level(const Node& n, const LightContext& at, uint32_t range, uint32_t bound[width + 1]) const;

  std::vector<Node> nodes_;
  std::vector<uint32_t> up_;    // by node: its parent's index × 8 + its lane (the root's: 0)
  std::vector<uint32_t> leaf_;  // by entry: its node's index × 8 + its lane
  int depth_ = 0;
  bool avx2_ = false;
};

}  // namespace dacrt
