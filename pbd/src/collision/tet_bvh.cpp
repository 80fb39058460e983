#include "pbd/collision/tet_bvh.h"

#include <algorithm>

namespace pbd {
namespace {

Vector3 centroid(const std::array<int, 4>& tet, const Vector3* positions) {
  return Real(0.25) *
         (positions[tet[0]] + positions[tet[1]] + positions[tet[2]] + positions[tet[3]]);
}

}  // namespace

TetBvh::TetBvh(const std::vector<std::array<int, 4>>& tets, const Vector3* positions,
               int maxLeafSize) {
  const int n = static_cast<int>(tets.size());
  if (n == 0) return;
  std::vector<Vector3> centres;
  centres.reserve(tets.size());
  for (const std::array<int, 4>& tet : tets)
    centres.push_back(centroid(tet, positions));
  order_.resize(tets.size());
  for (int i = 0; i < n; ++i)
    order_[std::size_t(i)] = i;
  struct Pending {
    int node, first, count, depth;
  };
  nodes_.emplace_back();
  std::vector<Pending> pending{{0, 0, n, 0}};
  while (!pending.empty()) {
    const Pending p = pending.back();
    pending.pop_back();
    nodes_[std::size_t(p.node)].firstTet = p.first;
    nodes_[std::size_t(p.node)].tetCount = p.count;
    if (p.count <= maxLeafSize || p.depth + 1 >= kMaxDepth) continue;
    Eigen::AlignedBox<Real, 3> box;
    box.setEmpty();
    for (int i = p.first; i < p.first + p.count; ++i)
      box.extend(centres[std::size_t(order_[std::size_t(i)])]);
    Eigen::Index axis;
    box.sizes().maxCoeff(&axis);
    const auto begin = order_.begin() + p.first;
    std::nth_element(begin, begin + p.count / 2, begin + p.count, [&](int a, int b) {
      const Real ca = centres[std::size_t(a)](axis), cb = centres[std::size_t(b)](axis);
      return ca < cb || (ca == cb && a < b);
    });
    const int child = static_cast<int>(nodes_.size());
    nodes_[std::size_t(p.node)].child = child;
    nodes_.emplace_back();
    nodes_.emplace_back();
    pending.push_back({child, p.first, p.count / 2, p.depth + 1});
    pending.push_back({child + 1, p.first + p.count / 2, p.count - p.count / 2, p.depth + 1});
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
