#include "pbd/collision/broad_phase.h"

#include <algorithm>

namespace pbd {

SweepAndPrune::SweepAndPrune(std::size_t objectCount, std::size_t pairCapacity)
    : order_(objectCount), capacity_(pairCapacity) {
  for (std::size_t i = 0; i < objectCount; ++i)
    order_[i] = static_cast<int>(i);
  pairs_.reserve(pairCapacity);
}

std::size_t SweepAndPrune::findPairs(const std::vector<Aabb>& boxes) {
  auto before = [&boxes](int a, int b) {
    const Real ka = boxes[std::size_t(a)].min.x(), kb = boxes[std::size_t(b)].min.x();
    return ka < kb || (ka == kb && a < b);
  };
  // Insertion sort from the previous order (std::sort could allocate in some libraries; this
  // never does, and is linear on nearly sorted input).
  for (std::size_t i = 1; i < order_.size(); ++i) {
    const int moving = order_[i];
    std::size_t j = i;
    for (; j > 0 && before(moving, order_[j - 1]); --j)
      order_[j] = order_[j - 1];
    order_[j] = moving;
  }
  pairs_.clear();
  std::size_t dropped = 0;
  for (std::size_t i = 0; i < order_.size(); ++i) {
    const Aabb& a = boxes[std::size_t(order_[i])];
    if (!a.active) continue;
    for (std::size_t j = i + 1; j < order_.size(); ++j) {
      const Aabb& b = boxes[std::size_t(order_[j])];
      if (b.min.x() > a.max.x()) break;
      if (!b.active || !a.overlaps(b)) continue;
      if (pairs_.size() == capacity_) {
        ++dropped;
        continue;
      }
      pairs_.emplace_back(std::min(order_[i], order_[j]), std::max(order_[i], order_[j]));
    }
  }
  // Canonical order. The sweep emits pairs in x order, far from (a, b) order: an insertion sort
  // here was O(P²) (a quarter of a 256-sphere pile's step). std::sort is O(P log P) and never
  // allocates (libstdc++'s introsort works in place); the pairs are distinct, so the order is
  // the same whatever the algorithm.
  std::sort(pairs_.begin(), pairs_.end());
  return dropped;
}

}  // namespace pbd
