// Fixed-radius neighbour search for SPH / PBF particles: a spatial hash of a uniform grid.
//
// Cells are cubes of edge `radius`, so every neighbour of a point lies in the 3 × 3 × 3 block
// of cells around it. A cell's integer coordinates are hashed into a table of 2^k buckets
// (2^k ≥ 2 × the point capacity); `index` sorts the points into the buckets by a counting sort
// (O(N + buckets), stable, so each bucket lists its points in increasing index). `query` visits
// the distinct buckets of the 27 cells (two cells may share a bucket: each bucket is visited
// once) and keeps the points strictly closer than `radius`; hash collisions only add candidates
// that the distance test rejects. Cost O(N · neighbours), not O(N²).
//
// Order: each neighbour list is sorted by increasing point index, whatever the hashing, so the
// result equals a brute-force search exactly (tests/pbd/test_fluids.cpp).
//
// Memory: every buffer is sized by the constructor (point capacity, query capacity, neighbours
// per query); `index` and `query` allocate nothing. Capacity decision: a list holds at most
// `maxNeighbours` entries; when more points are in range, the list keeps the lowest indices
// (deterministic) and `NeighbourLists::dropped` counts the points left out, so that callers and
// tests can see the clamp. For PBF at the seed's settings (support 4r, rest spacing ≈ 1.86r)
// an interior particle of a lattice at rest density has 32 neighbours, so a capacity of 128 is
// reached only at about four times the rest density (docs/methods.md, "Fluids").
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "pbd/math/types.h"

namespace pbd {

/// Neighbour lists of a set of query points with a fixed capacity per query.
struct NeighbourLists {
  std::size_t capacity = 0;  ///< entries per query
  std::vector<int> indices;  ///< query q's neighbours at [q · capacity, q · capacity + count[q])
  std::vector<int> counts;   ///< per query
  std::size_t dropped = 0;   ///< neighbours left out by the capacity in the last query()

  NeighbourLists() = default;
  NeighbourLists(std::size_t queryCapacity, std::size_t neighbourCapacity)
      : capacity(neighbourCapacity),
        indices(queryCapacity * neighbourCapacity, -1),
        counts(queryCapacity, 0) {}

  const int* begin(std::size_t query) const { return indices.data() + query * capacity; }
  int count(std::size_t query) const { return counts[query]; }
};

class NeighbourSearch {
 public:
  NeighbourSearch() = default;
  /// `radius` > 0 (the kernel support), room for `maxPoints` indexed points.
  NeighbourSearch(Real radius, std::size_t maxPoints);

  Real radius() const { return radius_; }
  std::size_t size() const { return count_; }

  /// Sorts `count` ≤ maxPoints points into the grid (a copy is kept for the queries); throws
  /// std::length_error when count exceeds the capacity (a build-time mistake, never a step's).
  void index(const Vector3* points, std::size_t count);

  /// For each of `queryCount` points, the indexed points strictly closer than radius, in
  /// increasing index. With `skipSameIndex` (the queries are the indexed points themselves)
  /// query q does not list point q. `out` must have been built with room for queryCount queries.
  void query(const Vector3* queries, std::size_t queryCount, bool skipSameIndex,
             NeighbourLists& out) const;

 private:
  std::uint32_t bucketOf(const Eigen::Matrix<std::int64_t, 3, 1>& cell) const;
  Eigen::Matrix<std::int64_t, 3, 1> cellOf(const Vector3& point) const;

  Real radius_ = 1;
  std::size_t count_ = 0;
  std::uint32_t bucketMask_ = 0;
  std::vector<std::uint32_t> pointBucket_;  ///< per input point
  std::vector<std::uint32_t> bucketStart_;  ///< buckets + 1 offsets into sorted arrays
  std::vector<int> sortedIndex_;            ///< input indices, bucket by bucket
  std::vector<Vector3> sortedPoints_;       ///< the points in that order
};

}  // namespace pbd
