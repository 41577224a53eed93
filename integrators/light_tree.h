// LightTree: next-event estimation's choice of emitter by how much each may light a given point
// (Conty Estevez & Kulla 2018, "Importance Sampling of Many Lights with Adaptive Tree
// Splitting", as pbrt-v4's BVHLightSampler does it, without the splitting): a binary tree over
// the emitters, each node bounding its emitters' positions (a box), their power and the directions
// they emit into (a cone of normals widened by their emission's spread). From a shading point, a
// node's importance bounds what its emitters can send there: power × the cosine at the emitter
// of the least angle between its cone and the point × the cosine at the point towards the box
// (with a normal) / squared distance. The descent picks a child in proportion to the two
// children's importance, one leaf (one emitter) in the end.
//
// The pick is exact in the alias table's way (util/alias_table.h): the uniform's 24 bits are an
// integer k in [0, R) with R = 2²⁴ (or the units the caller gives the tree), and each node hands
// its children whole parts of R, in proportion to their importance (at least one unit each for
// both when both are positive and R allows; none to a child of importance 0; half each when both
// are 0). A leaf's probability is the part it ends with over 2²⁴, and pmf() walks the same nodes
// with the same arithmetic, so it is the probability sample() realises, bit for bit.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

namespace dacrt {

// How next-event estimation chooses an emitter (integrators/lights.h, --light-sampler).
enum class LightPicking : uint8_t {
  automatic,  // the tree from LightSampler::tree_threshold emitters on, unless next-event
              // estimation samples an environment too (LightSampling); else power
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
  int depth() const { return depth_; }

  // The entry picked by k in [0, range) from `at`, and its probability in units (range being
  // all of the tree's): the part of [0, range) that picks it.
  struct Pick {
    uint32_t entry, units;
  };
  Pick sample(uint32_t k, uint32_t range, const LightContext& at) const;
  // The units of [0, range) that pick `entry` from `at` (sample's, exactly; 0 if none does).
  uint32_t units(uint32_t entry, uint32_t range, const LightContext& at) const;

  // The importance of an emitter's or a node's bounds from `at` (see the top): ≥ 0, 0 when it
  // cannot light it.
  static float importance(const Bounds& b, const LightContext& at);

 private:
  // A node's bounds as importance() reads them: the ball around its box, the cone's sine too.
  struct Node {
    glm::vec3 centre;
    float radius2;
    glm::vec3 w;
    float power, cos_o, sin_o, cos_e;
    uint32_t child;  // an inner node's second child (its first is the next node), a leaf's entry
    bool leaf, two_sided;
  };
  static Node node(const Bounds& b);
  static float importance(const Node& b, const LightContext& at);
  uint32_t build(std::vector<uint32_t>& order, size_t first, size_t last,
                 std::span<const Bounds> emitters, int depth);
  // The part of `range` the first child gets, given both children's importance.
  static uint32_t first_part(float a, float b, uint32_t range);

  std::vector<Node> nodes_;
  std::vector<uint32_t> parent_;  // by node (the root's is itself)
  std::vector<uint32_t> leaf_;    // by entry: its leaf node
  int depth_ = 0;                 // of the deepest leaf
};

}  // namespace dacrt
