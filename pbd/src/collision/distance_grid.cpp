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

}  // namespace

DistanceGrid::DistanceGrid(const Vector3& domainMin, const Vector3& domainMax,
                           const Vector3i& cells, std::vector<Real> nodes)
    : min_(domainMin), max_(domainMax), cells_(cells), nodes_(std::move(nodes)) {
  if ((cells.array() < 1).any())
    throw std::invalid_argument("DistanceGrid: every axis needs at least one cell");
  if (!((domainMax - domainMin).array() > 0).all())
    throw std::invalid_argument("DistanceGrid: the domain must have a positive extent");
  if (nodes_.size() != nodeCount(cells))
    throw std::invalid_argument("DistanceGrid: expected (n+3)^3 node values");
  spacing_ = (max_ - min_).cwiseQuotient(cells_.cast<Real>());
}

DistanceSample DistanceGrid::interpolate(const Vector3& point) const {
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
        const Real f = node(base[0] + a - 1, base[1] + b - 1, base[2] + c - 1);
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

DistanceSample DistanceGrid::evaluate(const Vector3& point) const {
  const Vector3 inside = point.cwiseMax(min_).cwiseMin(max_);
  DistanceSample sample = interpolate(inside);
  const Vector3 outside = point - inside;
  const Real gap = outside.norm();
  if (gap > 0) {
    sample.distance += gap;
    sample.gradient = outside / gap;
  }
  return sample;
}

}  // namespace pbd
