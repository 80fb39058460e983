#include "pbd/collision/point_bvh.h"

#include <algorithm>
#include <cmath>

namespace pbd {
namespace {

/// The sphere of a point range: bounding-box centre, farthest-point radius.
void fitSphere(PointBvh::Node& node, const std::vector<int>& order, const Vector3* points) {
  Eigen::AlignedBox<Real, 3> box;
  box.setEmpty();
  for (int i = node.firstPoint; i < node.firstPoint + node.pointCount; ++i)
    box.extend(points[order[std::size_t(i)]]);
  node.center = box.center();
  Real squared = 0;
  for (int i = node.firstPoint; i < node.firstPoint + node.pointCount; ++i)
    squared = std::max(squared, (points[order[std::size_t(i)]] - node.center).squaredNorm());
  node.radius = std::sqrt(squared);
}

}  // namespace

PointBvh::PointBvh(const std::vector<Vector3>& points, int maxLeafSize) {
  const int n = static_cast<int>(points.size());
  if (n == 0) return;
  order_.resize(points.size());
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
    Node& node = nodes_[std::size_t(p.node)];
    node.firstPoint = p.first;
    node.pointCount = p.count;
    if (p.count <= maxLeafSize || p.depth + 1 >= kMaxDepth) continue;
    Eigen::AlignedBox<Real, 3> box;
    box.setEmpty();
    for (int i = p.first; i < p.first + p.count; ++i)
      box.extend(points[std::size_t(order_[std::size_t(i)])]);
    Eigen::Index axis;
    box.sizes().maxCoeff(&axis);
    const auto begin = order_.begin() + p.first;
    std::nth_element(begin, begin + p.count / 2, begin + p.count, [&](int a, int b) {
      const Real pa = points[std::size_t(a)](axis), pb = points[std::size_t(b)](axis);
      return pa < pb || (pa == pb && a < b);
    });
    const int child = static_cast<int>(nodes_.size());
    nodes_[std::size_t(p.node)].child = child;  // `node` may dangle after the emplace below
    nodes_.emplace_back();
    nodes_.emplace_back();
    pending.push_back({child, p.first, p.count / 2, p.depth + 1});
    pending.push_back({child + 1, p.first + p.count / 2, p.count - p.count / 2, p.depth + 1});
  }
  refit(points.data());
}

void PointBvh::refit(const Vector3* points) {
  for (Node& node : nodes_)
    fitSphere(node, order_, points);
}

}  // namespace pbd
