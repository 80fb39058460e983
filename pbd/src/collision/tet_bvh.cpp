#include "pbd/collision/tet_bvh.h"

#include <algorithm>

#include "pbd/collision/median_split.h"

namespace pbd {
namespace {

Vector3 centroid(const std::array<int, 4>& tet, const Vector3* positions) {
  return Real(0.25) *
         (positions[tet[0]] + positions[tet[1]] + positions[tet[2]] + positions[tet[3]]);
}

}  // namespace

TetBvh::TetBvh(const std::vector<std::array<int, 4>>& tets, const Vector3* positions,
               int maxLeafSize) {
  if (tets.empty()) return;
  std::vector<Vector3> centres;
  centres.reserve(tets.size());
  for (const std::array<int, 4>& tet : tets)
    centres.push_back(centroid(tet, positions));
  std::vector<MedianSplitNode> tree;
  buildMedianSplit(centres, maxLeafSize, kMaxDepth, order_, tree);
  nodes_.resize(tree.size());
  for (std::size_t k = 0; k < tree.size(); ++k) {
    nodes_[k].firstTet = tree[k].first;
    nodes_[k].tetCount = tree[k].count;
    nodes_[k].child = tree[k].child;
  }
  refit(tets, positions);
}

void TetBvh::refit(const std::vector<std::array<int, 4>>& tets, const Vector3* positions) {
  for (std::size_t k = nodes_.size(); k-- > 0;) {
    Node& node = nodes_[k];
    node.box.setEmpty();
    if (node.child >= 0) {
      node.box.extend(nodes_[std::size_t(node.child)].box);
      node.box.extend(nodes_[std::size_t(node.child) + 1].box);
      continue;
    }
    for (int i = node.firstTet; i < node.firstTet + node.tetCount; ++i)
      for (int v : tets[std::size_t(order_[std::size_t(i)])])
        node.box.extend(positions[v]);
  }
}

}  // namespace pbd
