// A signed distance field sampled on a regular grid and interpolated in one of two ways
// (`Simulation.distanceGrid`, docs/contacts.md#grid-sdfs):
//
// Cubic Lagrange (the seed's: Discregrid's CubicLagrangeDiscreteGrid). Every cell is the
// 32-node serendipity cubic hexahedron: its 8 corners and two nodes on each of its 12 edges,
// at the thirds. With ξ = (ξ₁, ξ₂, ξ₃) ∈ [−1, 1]³ the cell's local coordinate and s = ±1 the
// node's side on an axis, the shape functions are (Zienkiewicz & Taylor, The Finite Element
// Method, vol. 1, §8.7, "serendipity" family)
//   corner (s₁, s₂, s₃):        N = (1/64) Π_a (1 + s_a ξ_a) · (9 |ξ|² − 19),
//   edge along axis e, at ξ_e = s/3, on the side (s_b, s_c) of the other axes b, c:
//                               N = (9/64) (1 − ξ_e²)(1 + 3 s ξ_e)(1 + s_b ξ_b)(1 + s_c ξ_c),
// and φ(x) = Σ N_n φ_n, ∇φ = Σ ∇_ξ N_n φ_n ⊙ 2/Δ. The element reproduces every cubic along
// the cell's edges and the complete cubic polynomials inside; φ is continuous across cells but
// its gradient is not (C⁰). Value error O(Δ⁴), gradient O(Δ³) for smooth fields.
// Nodes are shared between neighbouring cells: (n_x+1)(n_y+1)(n_z+1) corners, then two nodes per
// edge of the lattice along x, along y, along z.
//
// Catmull-Rom (pbdval's alternative). The grid stores the nodes 0 … n_k of every axis plus one
// ghost layer on each side (−1 and n_k + 1), all sampled from the exact function, so every cell
// has its full 4-node stencil. In a cell with local coordinate t ∈ [0, 1] along an axis, the
// weights of the nodes −1, 0, 1, 2 are
//   w₋₁ = (−t³ + 2t² − t)/2,  w₀ = (3t³ − 5t² + 2)/2,  w₁ = (−3t³ + 4t² + t)/2,  w₂ = (t³ − t²)/2,
// and the interpolant is the tensor product φ(x) = Σ w_i(t_x) w_j(t_y) w_k(t_z) φ_ijk, its
// gradient the same sum with one weight differentiated (and divided by Δ of that axis).
// It reproduces quadratics exactly and is C¹: value error O(Δ³), gradient O(Δ²) (Keys, "Cubic
// convolution interpolation for digital image processing", IEEE TASSP 29(6), 1981).
//
// The domain [min, max] is split into n_x × n_y × n_z cells of size Δ = (max − min) ⊘ n.
// Outside the domain, the value is the interpolant at the nearest domain point c plus |x − c|
// (an upper bound of the true distance, by the 1-Lipschitz property) and the gradient is
// (x − c)/|x − c|. (Discregrid answers "no value" there; grids are padded beyond the contact
// tolerance, so contacts do not depend on the difference.)
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "pbd/collision/analytic_shapes.h"
#include "pbd/collision/grid_interpolation.h"

namespace pbd {

class DistanceGrid {
 public:
  DistanceGrid() = default;
  /// `nodes` holds nodeCount(cells, interpolation) values in the order nodePosition gives.
  DistanceGrid(const Vector3& domainMin, const Vector3& domainMax, const Vector3i& cells,
               GridInterpolation interpolation, std::vector<Real> nodes);

  /// Samples `function(Vector3) → Real` at every node.
  template <typename Function>
  static DistanceGrid sample(const Vector3& domainMin, const Vector3& domainMax,
                             const Vector3i& cells, Function&& function,
                             GridInterpolation interpolation = GridInterpolation::CatmullRom);

  Real value(const Vector3& point) const { return evaluate(point).distance; }
  DistanceSample evaluate(const Vector3& point) const;

  const Vector3& domainMin() const { return min_; }
  const Vector3& domainMax() const { return max_; }
  const Vector3i& cells() const { return cells_; }
  GridInterpolation interpolation() const { return interpolation_; }
  const std::vector<Real>& nodes() const { return nodes_; }

  static std::size_t nodeCount(const Vector3i& cells, GridInterpolation interpolation);
  /// Cubic Lagrange layout: the index of the corner node at lattice point (i, j, k).
  static std::size_t lagrangeCornerIndex(const Vector3i& cells, int i, int j, int k);
  /// Cubic Lagrange layout: the index of the node at 1/3 (side 0) or 2/3 (side 1) of the lattice
  /// edge from (i, j, k) along `axis`.
  static std::size_t lagrangeEdgeIndex(const Vector3i& cells, int axis, int i, int j, int k,
                                       int side);
  /// The position of the node stored at `index`.
  static Vector3 nodePosition(const Vector3& domainMin, const Vector3& spacing,
                              const Vector3i& cells, GridInterpolation interpolation,
                              std::size_t index);

 private:
  DistanceSample interpolateCatmullRom(const Vector3& insidePoint) const;
  DistanceSample interpolateCubicLagrange(const Vector3& insidePoint) const;
  Real catmullRomNode(int i, int j, int k) const {
    return nodes_[(std::size_t(k + 1) * std::size_t(cells_.y() + 3) + std::size_t(j + 1)) *
                      std::size_t(cells_.x() + 3) +
                  std::size_t(i + 1)];
  }

  Vector3 min_ = Vector3::Zero(), max_ = Vector3::Zero(), spacing_ = Vector3::Ones();
  Vector3i cells_ = Vector3i::Zero();
  GridInterpolation interpolation_ = GridInterpolation::CatmullRom;
  std::vector<Real> nodes_;
};

template <typename Function>
DistanceGrid DistanceGrid::sample(const Vector3& domainMin, const Vector3& domainMax,
                                  const Vector3i& cells, Function&& function,
                                  GridInterpolation interpolation) {
  const std::size_t count = nodeCount(cells, interpolation);
  std::vector<Real> nodes;
  nodes.reserve(count);
  const Vector3 spacing = (domainMax - domainMin).cwiseQuotient(cells.cast<Real>());
  for (std::size_t index = 0; index < count; ++index)
    nodes.push_back(
        function(Vector3(nodePosition(domainMin, spacing, cells, interpolation, index))));
  return DistanceGrid(domainMin, domainMax, cells, interpolation, std::move(nodes));
}

}  // namespace pbd
