// An axis-aligned bounding-box hierarchy over the tetrahedra of one tet model: the tet side of
// particle–tet collision detection (the seed's TetMeshBSH, docs/seed.md#vertex-trees).
//
// Built once, top-down over the tets' centroids at build time: a node's tets are split at the
// median centroid along the longest axis of their centroids' box, down to at most
// `maxLeafSize` tets (4). Every detection refits the boxes from the current positions, keeping
// the topology (children always follow their parent in `nodes()`, so one backward sweep refits
// leaves before their parents). The seed uses spheres; boxes of deforming tets are tighter and
// as cheap to refit. Point queries walk the tree with a fixed-size stack: nothing allocates
// after construction.
#pragma once

#include <array>
#include <vector>

#include "pbd/math/types.h"

namespace pbd {

class TetBvh {
 public:
  struct Node {
    Eigen::AlignedBox<Real, 3> box;
    int firstTet = 0, tetCount = 0;  ///< range in order()
    int child = -1;                  ///< left child (right = child + 1); −1 for a leaf
  };
  static constexpr int kMaxDepth = 48;

  TetBvh() = default;
  /// `tets` index into `positions` (the positions at build time).
  TetBvh(const std::vector<std::array<int, 4>>& tets, const Vector3* positions,
         int maxLeafSize = 4);

  /// Recomputes every box from `positions` (same indexing as at construction).
  void refit(const std::vector<std::array<int, 4>>& tets, const Vector3* positions);

  /// Calls `visit(int tet)` for every tet whose leaf box contains `point`, depth first, left
  /// before right (a fixed order).
  template <typename Visit>
  void tetsContaining(const Vector3& point, Visit&& visit) const;

  const std::vector<Node>& nodes() const { return nodes_; }
  const std::vector<int>& order() const { return order_; }

 private:
  std::vector<Node> nodes_;
  std::vector<int> order_;
};

template <typename Visit>
void TetBvh::tetsContaining(const Vector3& point, Visit&& visit) const {
  if (nodes_.empty()) return;
  std::array<int, kMaxDepth + 2> stack{};
  int top = 0;
  stack[0] = 0;
  while (top >= 0) {
    const Node& node = nodes_[std::size_t(stack[std::size_t(top--)])];
    if (!node.box.contains(point)) continue;
    if (node.child < 0) {
      for (int i = node.firstTet; i < node.firstTet + node.tetCount; ++i)
        visit(order_[std::size_t(i)]);
      continue;
    }
    stack[std::size_t(++top)] = node.child + 1;  // right after left
    stack[std::size_t(++top)] = node.child;
  }
}

}  // namespace pbd
