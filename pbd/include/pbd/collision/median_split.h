// The topology shared by the point and tet hierarchies (point_bvh.h, tet_bvh.h): a binary tree
// over items given by their centres, each node's items split at the median of their centres
// along the widest axis of their box. Ties are broken by the item's index, so the tree depends
// only on the centres, not on the standard library's nth_element.
#pragma once

#include <vector>

#include "pbd/math/types.h"

namespace pbd {

/// A node: its range [first, first + count) of the item order and its left child (the right
/// one is child + 1); −1 for a leaf.
struct MedianSplitNode {
  int first = 0, count = 0;
  int child = -1;
};

/// Builds the tree over `centres`: a node of more than `maxLeafSize` items, at depth below
/// `maxDepth − 1`, gets two children with the lower and upper half of its items. Fills `order`
/// (the items permuted so that every node's items are contiguous) and `nodes` (the root first,
/// children in pairs). Empty outputs for no items.
void buildMedianSplit(const std::vector<Vector3>& centres, int maxLeafSize, int maxDepth,
                      std::vector<int>& order, std::vector<MedianSplitNode>& nodes);

}  // namespace pbd
