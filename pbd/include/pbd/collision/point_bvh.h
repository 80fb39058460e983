// A bounding-sphere hierarchy over a point cloud: the vertex side of collision detection
// (the seed's PointCloudBSH, docs/seed.md#vertex-trees).
//
// Built top-down: a node's points are split at the median along the longest axis of their
// bounding box, down to at most `maxLeafSize` points (10, as in the seed). Each node's sphere
// is centred at its points' bounding-box centre with the radius of the farthest point (the
// seed uses Welzl's minimal enclosing spheres at the leaves: ours can be larger, which only
// enters more nodes, never misses a point). Rigid bodies build it once in their scene frame;
// deforming point sets (particle models) refit it from the current positions, keeping the tree's
// topology.
//
// Traversal is depth-first with a fixed-size stack: no allocation.
#pragma once

#include <array>
#include <vector>

#include "pbd/math/types.h"

namespace pbd {

class PointBvh {
 public:
  struct Node {
    Vector3 center = Vector3::Zero();
    Real radius = 0;
    int firstPoint = 0, pointCount = 0;  ///< range in order()
    int child = -1;                      ///< left child (right = child + 1); −1 for a leaf
  };
  static constexpr int kMaxDepth = 48;

  PointBvh() = default;
  explicit PointBvh(const std::vector<Vector3>& points, int maxLeafSize = 10);

  /// Recomputes every sphere from `points` (same count and indexing as at construction).
  void refit(const Vector3* points);

  /// Visits the hierarchy: `descend(const Node&)` decides whether to enter a node; for every
  /// point of an entered leaf, `visit(int pointIndex)` is called.
  template <typename Descend, typename Visit>
  void traverse(Descend&& descend, Visit&& visit) const;

  const std::vector<Node>& nodes() const { return nodes_; }
  /// Point indices, grouped by leaf.
  const std::vector<int>& order() const { return order_; }

 private:
  std::vector<Node> nodes_;
  std::vector<int> order_;
};

template <typename Descend, typename Visit>
void PointBvh::traverse(Descend&& descend, Visit&& visit) const {
  if (nodes_.empty()) return;
  std::array<int, kMaxDepth + 2> stack{};
  int top = 0;
  stack[0] = 0;
  while (top >= 0) {
    const Node& node = nodes_[std::size_t(stack[std::size_t(top--)])];
    if (!descend(node)) continue;
    if (node.child < 0) {
      for (int i = node.firstPoint; i < node.firstPoint + node.pointCount; ++i)
        visit(order_[std::size_t(i)]);
      continue;
    }
    stack[std::size_t(++top)] = node.child + 1;  // right after left
    stack[std::size_t(++top)] = node.child;
  }
}

}  // namespace pbd
