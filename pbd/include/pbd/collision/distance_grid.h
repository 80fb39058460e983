// A signed distance field sampled on a regular grid and interpolated with tricubic
// Catmull-Rom splines, so that the field and its gradient are continuous (C¹).
//
// The domain [min, max] is split into n_x × n_y × n_z cells of size Δ = (max − min) ⊘ n. The
// grid stores the nodes 0 … n_k of every axis plus one ghost layer on each side (−1 and
// n_k + 1), all sampled from the exact function, so every cell has its full 4-node stencil.
// In a cell with local coordinate t ∈ [0, 1] along an axis, the Catmull-Rom weights of the
// nodes −1, 0, 1, 2 are
//   w₋₁ = (−t³ + 2t² − t)/2,  w₀ = (3t³ − 5t² + 2)/2,  w₁ = (−3t³ + 4t² + t)/2,  w₂ = (t³ − t²)/2,
// and the interpolant is the tensor product φ(x) = Σ w_i(t_x) w_j(t_y) w_k(t_z) φ_ijk, its
// gradient the same sum with one weight differentiated (and divided by Δ of that axis).
// Catmull-Rom reproduces quadratics exactly: the interpolation error is O(Δ³) for smooth
// fields, the gradient's O(Δ²) (Keys, "Cubic convolution interpolation for digital image
// processing", IEEE TASSP 29(6), 1981).
//
// Outside the domain, the value is the interpolant at the nearest domain point c plus |x − c|
// (an upper bound of the true distance, by the 1-Lipschitz property) and the gradient is
// (x − c)/|x − c|. Grids are padded well beyond the contact tolerance, so contacts never
// depend on this extension.
#pragma once

#include <utility>
#include <vector>

#include "pbd/collision/analytic_shapes.h"

namespace pbd {

class DistanceGrid {
 public:
  DistanceGrid() = default;
  /// `nodes` holds (n_x + 3)(n_y + 3)(n_z + 3) values, x fastest, ghost layers included.
  DistanceGrid(const Vector3& domainMin, const Vector3& domainMax, const Vector3i& cells,
               std::vector<Real> nodes);

  /// Samples `function(Vector3) → Real` at every node (ghost layers included).
  template <typename Function>
  static DistanceGrid sample(const Vector3& domainMin, const Vector3& domainMax,
                             const Vector3i& cells, Function&& function);

  Real value(const Vector3& point) const { return evaluate(point).distance; }
  DistanceSample evaluate(const Vector3& point) const;

  const Vector3& domainMin() const { return min_; }
  const Vector3& domainMax() const { return max_; }
  const Vector3i& cells() const { return cells_; }
  const std::vector<Real>& nodes() const { return nodes_; }
  /// The position of node (i, j, k), i ∈ [−1, n_x + 1] etc.
  Vector3 nodePosition(int i, int j, int k) const {
    return min_ + Vector3(Real(i), Real(j), Real(k)).cwiseProduct(spacing_);
  }
  static std::size_t nodeCount(const Vector3i& cells) {
    return std::size_t(cells.x() + 3) * std::size_t(cells.y() + 3) * std::size_t(cells.z() + 3);
  }

 private:
  Real node(int i, int j, int k) const {
    return nodes_[(std::size_t(k + 1) * std::size_t(cells_.y() + 3) + std::size_t(j + 1)) *
                      std::size_t(cells_.x() + 3) +
                  std::size_t(i + 1)];
  }
  DistanceSample interpolate(const Vector3& insidePoint) const;

  Vector3 min_ = Vector3::Zero(), max_ = Vector3::Zero(), spacing_ = Vector3::Ones();
  Vector3i cells_ = Vector3i::Zero();
  std::vector<Real> nodes_;
};

template <typename Function>
DistanceGrid DistanceGrid::sample(const Vector3& domainMin, const Vector3& domainMax,
                                  const Vector3i& cells, Function&& function) {
  std::vector<Real> nodes;
  nodes.reserve(nodeCount(cells));
  const Vector3 spacing = (domainMax - domainMin).cwiseQuotient(cells.cast<Real>());
  for (int k = -1; k <= cells.z() + 1; ++k)
    for (int j = -1; j <= cells.y() + 1; ++j)
      for (int i = -1; i <= cells.x() + 1; ++i)
        nodes.push_back(function(
            Vector3(domainMin + Vector3(Real(i), Real(j), Real(k)).cwiseProduct(spacing))));
  return DistanceGrid(domainMin, domainMax, cells, std::move(nodes));
}

}  // namespace pbd
