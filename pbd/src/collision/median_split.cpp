#include "pbd/collision/median_split.h"

#include <algorithm>

namespace pbd {

void buildMedianSplit(const std::vector<Vector3>& centres, int maxLeafSize, int maxDepth,
                      std::vector<int>& order, std::vector<MedianSplitNode>& nodes) {
  order.clear();
  nodes.clear();
  const int n = static_cast<int>(centres.size());
  if (n == 0) return;
  order.resize(centres.size());
  for (int i = 0; i < n; ++i)
    order[std::size_t(i)] = i;
  struct Pending {
    int node, first, count, depth;
  };
  nodes.emplace_back();
  std::vector<Pending> pending{{0, 0, n, 0}};
  while (!pending.empty()) {
    const Pending p = pending.back();
    pending.pop_back();
    nodes[std::size_t(p.node)].first = p.first;
    nodes[std::size_t(p.node)].count = p.count;
    if (p.count <= maxLeafSize || p.depth + 1 >= maxDepth) continue;
    Eigen::AlignedBox<Real, 3> box;
    box.setEmpty();
    for (int i = p.first; i < p.first + p.count; ++i)
      box.extend(centres[std::size_t(order[std::size_t(i)])]);
    Eigen::Index axis;
    box.sizes().maxCoeff(&axis);
    const auto begin = order.begin() + p.first;
    std::nth_element(begin, begin + p.count / 2, begin + p.count, [&](int a, int b) {
      const Real ca = centres[std::size_t(a)](axis), cb = centres[std::size_t(b)](axis);
      return ca < cb || (ca == cb && a < b);
    });
    const int child = static_cast<int>(nodes.size());
    nodes[std::size_t(p.node)].child = child;  // index, not reference: emplace may reallocate
    nodes.emplace_back();
    nodes.emplace_back();
    pending.push_back({child, p.first, p.count / 2, p.depth + 1});
    pending.push_back({child + 1, p.first + p.count / 2, p.count - p.count / 2, p.depth + 1});
  }
}

}  // namespace pbd
