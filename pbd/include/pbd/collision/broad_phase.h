// Broad phase: sweep and prune over world-space axis-aligned boxes (Baraff 1992, "Dynamic
// simulation of non-penetrating rigid bodies", §6; Cohen et al., "I-COLLIDE", 1995).
//
// The boxes are kept sorted by their lower x bound with an insertion sort that starts from the
// previous step's order (nearly sorted between steps: O(N + swaps)); a sweep then tests each
// box against the following ones until their lower x bound passes its upper one, and checks y
// and z. Cost O(N + swaps + x-overlapping pairs) instead of the seed's O(N²) over all pairs.
// The pairs come out sorted by (a, b), a < b, whatever the sort order: results depend only on
// the boxes. Nothing allocates after construction.
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

#include "pbd/math/types.h"

namespace pbd {

struct Aabb {
  Vector3 min = Vector3::Zero();
  Vector3 max = Vector3::Zero();
  bool active = false;  ///< inactive boxes take no part in the broad phase

  bool overlaps(const Aabb& other) const {
    return (min.array() <= other.max.array()).all() && (other.min.array() <= max.array()).all();
  }
  /// Distance from `p` to the box (0 inside).
  Real exteriorDistance(const Vector3& p) const {
    return (min - p).cwiseMax(p - max).cwiseMax(Real(0)).norm();
  }
};

using ObjectPair = std::pair<int, int>;

class SweepAndPrune {
 public:
  SweepAndPrune() = default;
  /// For `objectCount` boxes; at most `pairCapacity` pairs are reported per call.
  SweepAndPrune(std::size_t objectCount, std::size_t pairCapacity);

  /// Fills `pairs()` with every overlapping pair of active boxes, sorted. Returns the number
  /// of pairs that did not fit into the capacity (they are dropped).
  std::size_t findPairs(const std::vector<Aabb>& boxes);
  const std::vector<ObjectPair>& pairs() const { return pairs_; }

 private:
  std::vector<int> order_;
  std::vector<ObjectPair> pairs_;
  std::size_t capacity_ = 0;
};

}  // namespace pbd
