#include "pbd/fluids/neighbour_search.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace pbd {
namespace {

using Cell = Eigen::Matrix<std::int64_t, 3, 1>;

/// Cell coordinates are clamped to ±2^40 so that a far-away (or non-finite) point still has a
/// well-defined cell; such points only share buckets with each other.
constexpr double kCellLimit = 1099511627776.0;  // 2^40

std::int64_t cellCoordinate(Real x, Real radius) {
  const double c = std::floor(double(x) / double(radius));
  if (!(c > -kCellLimit)) return -std::int64_t(kCellLimit);  // also NaN
  if (!(c < kCellLimit)) return std::int64_t(kCellLimit);
  return std::int64_t(c);
}

}  // namespace

NeighbourSearch::NeighbourSearch(Real radius, std::size_t maxPoints) : radius_(radius) {
  if (!(radius > 0)) throw std::invalid_argument("NeighbourSearch: the radius must be > 0");
  std::size_t buckets = 16;
  while (buckets < 2 * maxPoints)
    buckets *= 2;
  bucketMask_ = static_cast<std::uint32_t>(buckets - 1);
  pointBucket_.assign(maxPoints, 0);
  bucketStart_.assign(buckets + 1, 0);
  sortedIndex_.assign(maxPoints, -1);
  sortedPoints_.assign(maxPoints, Vector3::Zero());
}

Cell NeighbourSearch::cellOf(const Vector3& point) const {
  return Cell(cellCoordinate(point.x(), radius_), cellCoordinate(point.y(), radius_),
              cellCoordinate(point.z(), radius_));
}

std::uint32_t NeighbourSearch::bucketOf(const Cell& cell) const {
  // Teschner et al. 2003's three large primes, in 64-bit arithmetic (wrapping), then folded.
  const std::uint64_t h = (std::uint64_t(cell.x()) * 73856093ull) ^
                          (std::uint64_t(cell.y()) * 19349663ull) ^
                          (std::uint64_t(cell.z()) * 83492791ull);
  return static_cast<std::uint32_t>((h ^ (h >> 32)) & bucketMask_);
}

void NeighbourSearch::index(const Vector3* points, std::size_t count) {
  if (count > sortedIndex_.size())
    throw std::length_error("NeighbourSearch: " + std::to_string(count) +
                            " points exceed the capacity " + std::to_string(sortedIndex_.size()));
  count_ = count;
  std::fill(bucketStart_.begin(), bucketStart_.end(), 0u);
  for (std::size_t i = 0; i < count; ++i) {
    pointBucket_[i] = bucketOf(cellOf(points[i]));
    ++bucketStart_[pointBucket_[i] + 1];
  }
  for (std::size_t b = 1; b < bucketStart_.size(); ++b)
    bucketStart_[b] += bucketStart_[b - 1];
  // Stable placement: bucketStart_[b] advances while filling and is restored afterwards.
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint32_t slot = bucketStart_[pointBucket_[i]]++;
    sortedIndex_[slot] = static_cast<int>(i);
    sortedPoints_[slot] = points[i];
  }
  for (std::size_t b = bucketStart_.size() - 1; b > 0; --b)
    bucketStart_[b] = bucketStart_[b - 1];
  bucketStart_[0] = 0;
}

void NeighbourSearch::query(const Vector3* queries, std::size_t queryCount, bool skipSameIndex,
                            NeighbourLists& out) const {
  if (queryCount > out.counts.size())
    throw std::length_error("NeighbourSearch: the lists have room for " +
                            std::to_string(out.counts.size()) + " queries, not " +
                            std::to_string(queryCount));
  const Real radiusSquared = radius_ * radius_;
  const int capacity = static_cast<int>(out.capacity);
  out.dropped = 0;
  for (std::size_t q = 0; q < queryCount; ++q) {
    const Vector3& x = queries[q];
    const Cell centre = cellOf(x);
    std::uint32_t visited[27];
    int visitedCount = 0;
    int* list = out.indices.data() + q * out.capacity;
    int n = 0;
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const std::uint32_t bucket = bucketOf(centre + Cell(dx, dy, dz));
          if (std::find(visited, visited + visitedCount, bucket) != visited + visitedCount)
            continue;
          visited[visitedCount++] = bucket;
          for (std::uint32_t s = bucketStart_[bucket]; s < bucketStart_[bucket + 1]; ++s) {
            const int j = sortedIndex_[s];
            if (skipSameIndex && j == static_cast<int>(q)) continue;
            if (!((sortedPoints_[s] - x).squaredNorm() < radiusSquared)) continue;
            // Insertion into the sorted list; when full, the largest index falls out.
            int position = n;
            while (position > 0 && list[position - 1] > j)
              --position;
            if (n == capacity) {
              ++out.dropped;
              if (position == capacity) continue;
              --n;
            }
            for (int m = n; m > position; --m)
              list[m] = list[m - 1];
            list[position] = j;
            ++n;
          }
        }
    out.counts[q] = n;
  }
}

}  // namespace pbd
