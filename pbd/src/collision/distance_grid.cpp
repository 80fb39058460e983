#include "pbd/collision/distance_grid.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace pbd {
namespace {

/// Catmull-Rom weights of the nodes −1, 0, 1, 2 at t ∈ [0, 1], and their derivatives.
void catmullRomWeights(Real t, Real weights[4], Real derivatives[4]) {
  const Real t2 = t * t, t3 = t2 * t;
  weights[0] = Real(0.5) * (-t3 + 2 * t2 - t);
  weights[1] = Real(0.5) * (3 * t3 - 5 * t2 + 2);
  weights[2] = Real(0.5) * (-3 * t3 + 4 * t2 + t);
  weights[3] = Real(0.5) * (t3 - t2);
  derivatives[0] = Real(0.5) * (-3 * t2 + 4 * t - 1);
  derivatives[1] = Real(0.5) * (9 * t2 - 10 * t);
  derivatives[2] = Real(0.5) * (-9 * t2 + 8 * t + 1);
  derivatives[3] = Real(0.5) * (3 * t2 - 2 * t);
}

/// The shared-node layout of the cubic Lagrange grid: corners, then the two nodes of every
/// lattice edge along x, along y, along z (each edge's node at 1/3 first).
struct LagrangeLayout {
  std::size_t nx, ny, nz;
  explicit LagrangeLayout(const Vector3i& cells)
      : nx(std::size_t(cells.x())), ny(std::size_t(cells.y())), nz(std::size_t(cells.z())) {}
  std::size_t corners() const { return (nx + 1) * (ny + 1) * (nz + 1); }
  /// Edges along `axis`: the lattice has n_axis cells along it and n + 1 nodes across it.
  std::size_t edges(int axis) const {
    return (axis == 0 ? nx : nx + 1) * (axis == 1 ? ny : ny + 1) * (axis == 2 ? nz : nz + 1);
  }
  std::size_t total() const { return corners() + 2 * (edges(0) + edges(1) + edges(2)); }
  /// The lattice point (i, j, k) in a box of (ex, ey, ez) points, x fastest.
  static std::size_t linear(std::size_t i, std::size_t j, std::size_t k, std::size_t ex,
                            std::size_t ey) {
    return i + ex * (j + ey * k);
  }
  std::size_t corner(std::size_t i, std::size_t j, std::size_t k) const {
    return linear(i, j, k, nx + 1, ny + 1);
  }
  /// The node at 1/3 (side 0) or 2/3 (side 1) of the edge from lattice point (i, j, k) along
  /// `axis`.
  std::size_t edge(int axis, std::size_t i, std::size_t j, std::size_t k, int side) const {
    std::size_t offset = corners();
    for (int a = 0; a < axis; ++a)
      offset += 2 * edges(a);
    const std::size_t ex = axis == 0 ? nx : nx + 1, ey = axis == 1 ? ny : ny + 1;
    return offset + 2 * linear(i, j, k, ex, ey) + std::size_t(side);
  }
};

}  // namespace

const char* gridInterpolationName(GridInterpolation interpolation) {
  switch (interpolation) {
    case GridInterpolation::CubicLagrange:
      return "cubicLagrange";
    case GridInterpolation::CatmullRom:
      return "catmullRom";
  }
  return "?";
}

std::size_t DistanceGrid::nodeCount(const Vector3i& cells, GridInterpolation interpolation) {
  if (interpolation == GridInterpolation::CubicLagrange) return LagrangeLayout(cells).total();
  return std::size_t(cells.x() + 3) * std::size_t(cells.y() + 3) * std::size_t(cells.z() + 3);
}

std::size_t DistanceGrid::lagrangeCornerIndex(const Vector3i& cells, int i, int j, int k) {
  return LagrangeLayout(cells).corner(std::size_t(i), std::size_t(j), std::size_t(k));
}

std::size_t DistanceGrid::lagrangeEdgeIndex(const Vector3i& cells, int axis, int i, int j, int k,
                                            int side) {
  return LagrangeLayout(cells).edge(axis, std::size_t(i), std::size_t(j), std::size_t(k), side);
}

Vector3 DistanceGrid::nodePosition(const Vector3& domainMin, const Vector3& spacing,
                                   const Vector3i& cells, GridInterpolation interpolation,
                                   std::size_t index) {
  if (interpolation == GridInterpolation::CatmullRom) {
    const std::size_t ex = std::size_t(cells.x() + 3), ey = std::size_t(cells.y() + 3);
    const Vector3 lattice(Real(int(index % ex) - 1), Real(int(index / ex % ey) - 1),
                          Real(int(index / (ex * ey)) - 1));
    return domainMin + lattice.cwiseProduct(spacing);
  }
  const LagrangeLayout layout(cells);
  std::size_t ex = layout.nx + 1, ey = layout.ny + 1;
  int axis = -1, side = 0;
  if (index >= layout.corners()) {
    index -= layout.corners();
    for (axis = 0; axis < 3 && index >= 2 * layout.edges(axis); ++axis)
      index -= 2 * layout.edges(axis);
    side = int(index % 2);
    index /= 2;
    ex = axis == 0 ? layout.nx : layout.nx + 1;
    ey = axis == 1 ? layout.ny : layout.ny + 1;
  }
  const Vector3 lattice(Real(index % ex), Real(index / ex % ey), Real(index / (ex * ey)));
  Vector3 position = domainMin + spacing.cwiseProduct(lattice);
  if (axis >= 0) position(axis) += Real(1 + side) / 3 * spacing(axis);
  return position;
}

DistanceGrid::DistanceGrid(const Vector3& domainMin, const Vector3& domainMax,
                           const Vector3i& cells, GridInterpolation interpolation,
                           std::vector<Real> nodes)
    : min_(domainMin),
      max_(domainMax),
      cells_(cells),
      interpolation_(interpolation),
      nodes_(std::move(nodes)) {
  if ((cells.array() < 1).any())
    throw std::invalid_argument("DistanceGrid: every axis needs at least one cell");
  if (!((domainMax - domainMin).array() > 0).all())
    throw std::invalid_argument("DistanceGrid: the domain must have a positive extent");
  if (nodes_.size() != nodeCount(cells, interpolation))
    throw std::invalid_argument("DistanceGrid: wrong number of node values for the layout");
  spacing_ = (max_ - min_).cwiseQuotient(cells_.cast<Real>());
}

DistanceSample DistanceGrid::interpolateCatmullRom(const Vector3& point) const {
  int base[3];
  Real weights[3][4], derivatives[3][4];
  for (int axis = 0; axis < 3; ++axis) {
    const Real u = (point(axis) - min_(axis)) / spacing_(axis);
    const int cell = std::min(static_cast<int>(std::floor(u)), cells_(axis) - 1);
    base[axis] = std::max(cell, 0);
    catmullRomWeights(u - Real(base[axis]), weights[axis], derivatives[axis]);
  }
  DistanceSample result;
  for (int c = 0; c < 4; ++c) {
    for (int b = 0; b < 4; ++b) {
      const Real wyz = weights[1][b] * weights[2][c];
      const Real dyWz = derivatives[1][b] * weights[2][c];
      const Real wyDz = weights[1][b] * derivatives[2][c];
      for (int a = 0; a < 4; ++a) {
        const Real f = catmullRomNode(base[0] + a - 1, base[1] + b - 1, base[2] + c - 1);
        result.distance += weights[0][a] * wyz * f;
        result.gradient.x() += derivatives[0][a] * wyz * f;
        result.gradient.y() += weights[0][a] * dyWz * f;
        result.gradient.z() += weights[0][a] * wyDz * f;
      }
    }
  }
  result.gradient = result.gradient.cwiseQuotient(spacing_);
  return result;
}

DistanceSample DistanceGrid::interpolateCubicLagrange(const Vector3& point) const {
  const LagrangeLayout layout(cells_);
  std::size_t cell[3];
  Vector3 xi, scale;  // local coordinate in [−1, 1]³ and dξ/dx
  for (int axis = 0; axis < 3; ++axis) {
    // The cell and ξ are computed as Discregrid computes them (the cell index from the inverse
    // cell size, the cell's upper corner as lower corner + size), so that a point on a cell
    // face, where the gradient jumps, falls into the same cell as in the seed.
    const Real u = (point(axis) - min_(axis)) * (1 / spacing_(axis));
    const int index = std::max(0, std::min(static_cast<int>(u), cells_(axis) - 1));
    cell[axis] = std::size_t(index);
    const Real low = min_(axis) + Real(index) * spacing_(axis);
    const Real high = low + spacing_(axis);
    scale(axis) = 2 / (high - low);
    xi(axis) = scale(axis) * point(axis) - (high + low) / (high - low);
  }
  DistanceSample result;
  Vector3 gradient = Vector3::Zero();  // with respect to ξ
  // Corners.
  const Real radial = 9 * xi.squaredNorm() - 19;
  for (int corner = 0; corner < 8; ++corner) {
    Vector3 sign, linear;
    for (int axis = 0; axis < 3; ++axis) {
      sign(axis) = (corner >> axis & 1) ? Real(1) : Real(-1);
      linear(axis) = 1 + sign(axis) * xi(axis);
    }
    const Real f = nodes_[layout.corner(cell[0] + std::size_t(corner & 1),
                                        cell[1] + std::size_t(corner >> 1 & 1),
                                        cell[2] + std::size_t(corner >> 2 & 1))];
    const Real product = linear.prod();
    result.distance += product * radial / 64 * f;
    gradient.x() += (sign.x() * linear.y() * linear.z() * radial + product * 18 * xi.x()) / 64 * f;
    gradient.y() += (sign.y() * linear.x() * linear.z() * radial + product * 18 * xi.y()) / 64 * f;
    gradient.z() += (sign.z() * linear.x() * linear.y() * radial + product * 18 * xi.z()) / 64 * f;
  }
  // Edge nodes: along axis e at ξ_e = ∓1/3, on the sides (s_b, s_c) of the other two axes.
  for (int e = 0; e < 3; ++e) {
    const int b = (e + 1) % 3, c = (e + 2) % 3;
    const Real t = xi(e), bubble = 1 - t * t;
    for (int side = 0; side < 2; ++side) {
      const Real s = side == 0 ? Real(-1) : Real(1);
      const Real along = Real(9) / 64 * bubble * (1 + 3 * s * t);
      const Real alongDerivative = Real(9) / 64 * (-2 * t * (1 + 3 * s * t) + 3 * s * bubble);
      for (int across = 0; across < 4; ++across) {
        const int sideB = across & 1, sideC = across >> 1 & 1;
        const Real sb = sideB ? Real(1) : Real(-1), sc = sideC ? Real(1) : Real(-1);
        const Real lb = 1 + sb * xi(b), lc = 1 + sc * xi(c);
        std::size_t lattice[3];
        lattice[e] = cell[e];
        lattice[b] = cell[b] + std::size_t(sideB);
        lattice[c] = cell[c] + std::size_t(sideC);
        const Real f = nodes_[layout.edge(e, lattice[0], lattice[1], lattice[2], side)];
        result.distance += along * lb * lc * f;
        gradient(e) += alongDerivative * lb * lc * f;
        gradient(b) += along * sb * lc * f;
        gradient(c) += along * lb * sc * f;
      }
    }
  }
  result.gradient = gradient.cwiseProduct(scale);
  return result;
}

DistanceSample DistanceGrid::evaluate(const Vector3& point) const {
  const Vector3 inside = point.cwiseMax(min_).cwiseMin(max_);
  DistanceSample sample = interpolation_ == GridInterpolation::CubicLagrange
                              ? interpolateCubicLagrange(inside)
                              : interpolateCatmullRom(inside);
  const Vector3 outside = point - inside;
  const Real gap = outside.norm();
  if (gap > 0) {
    sample.distance += gap;
    sample.gradient = outside / gap;
  }
  return sample;
}

}  // namespace pbd
