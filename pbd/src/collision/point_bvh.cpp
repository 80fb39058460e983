#include "pbd/collision/point_bvh.h"

#include <algorithm>
#include <cmath>

#include "pbd/collision/median_split.h"

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
  std::vector<MedianSplitNode> tree;
  buildMedianSplit(points, maxLeafSize, kMaxDepth, order_, tree);
  nodes_.resize(tree.size());
  for (std::size_t k = 0; k < tree.size(); ++k) {
    nodes_[k].firstPoint = tree[k].first;
    nodes_[k].pointCount = tree[k].count;
    nodes_[k].child = tree[k].child;
  }
  refit(points.data());
}

void PointBvh::refit(const Vector3* points) {
  for (Node& node : nodes_)
    fitSphere(node, order_, points);
}

}  // namespace pbd
