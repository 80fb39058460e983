#include "pbd/constraints/strain_triangle.h"

#include <algorithm>
#include <cmath>

#include "pbd/constraints/particle_stencil.h"
#include "pbd/model/scene.h"

namespace pbd {
namespace {

using Matrix2x2 = Eigen::Matrix<Real, 2, 2>;
using Matrix3x2 = Eigen::Matrix<Real, 3, 2>;

Matrix3x2 deformationGradient(const std::array<Vector3, 3>& x, const Matrix2x2& restInverse) {
  Matrix3x2 edges;
  edges.col(0) = x[1] - x[0];
  edges.col(1) = x[2] - x[0];
  return edges * restInverse;
}

/// C and ∂C/∂f_x, ∂C/∂f_y of one component.
struct Partials {
  Real value = 0;
  Vector3 x = Vector3::Zero();
  Vector3 y = Vector3::Zero();
};

Partials partials(const Matrix3x2& f, const StrainTriangleConstraint& c,
                  StrainComponent component) {
  Partials p;
  const Vector3 fx = f.col(0), fy = f.col(1);
  switch (component) {
    case StrainComponent::Xx:
    case StrainComponent::Yy: {
      const bool alongX = component == StrainComponent::Xx;
      const Vector3 fa = alongX ? fx : fy;
      Vector3& g = alongX ? p.x : p.y;
      if (c.normalizeStretch) {
        const Real length = fa.norm();
        p.value = length - 1;
        if (length > 0) g = fa / length;
      } else {
        p.value = fa.squaredNorm() - 1;
        g = 2 * fa;
      }
      break;
    }
    case StrainComponent::Xy: {
      p.value = fx.dot(fy);
      if (c.normalizeShear) {
        const Real lx = fx.norm(), ly = fy.norm();
        if (!(lx > 0) || !(ly > 0)) return Partials{};
        p.value /= lx * ly;
        p.x = fy / (lx * ly) - p.value * fx / (lx * lx);
        p.y = fx / (lx * ly) - p.value * fy / (ly * ly);
      } else {
        p.x = fy;
        p.y = fx;
      }
      break;
    }
  }
  return p;
}

std::array<Vector3, 3> gradients(const Partials& p, const Matrix2x2& restInverse) {
  const Vector3 g1 = restInverse(0, 0) * p.x + restInverse(0, 1) * p.y;
  const Vector3 g2 = restInverse(1, 0) * p.x + restInverse(1, 1) * p.y;
  return {-g1 - g2, g1, g2};
}

Real stiffnessOf(const StrainTriangleConstraint& c, StrainComponent component) {
  switch (component) {
    case StrainComponent::Xx:
      return c.xxStiffness;
    case StrainComponent::Xy:
      return c.xyStiffness;
    case StrainComponent::Yy:
      return c.yyStiffness;
  }
  return 0;
}

}  // namespace

bool strainTriangleRest(const std::array<Vector3, 3>& rest, Matrix2x2& restInverse) {
  const Vector3 e1 = rest[1] - rest[0], e2 = rest[2] - rest[0];
  const Vector3 normal = e1.cross(e2);
  const Real normalLength = normal.norm(), edgeLength = e1.norm();
  if (!(normalLength > 0) || !(edgeLength > 0)) return false;
  const Vector3 xAxis = e1 / edgeLength;
  const Vector3 yAxis = (normal / normalLength).cross(xAxis);
  Matrix2x2 restEdges;
  restEdges << e1.dot(xAxis), e2.dot(xAxis), e1.dot(yAxis), e2.dot(yAxis);
  if (!(std::abs(restEdges.determinant()) > 0)) return false;
  restInverse = restEdges.inverse();
  return true;
}

Real strainTriangleValue(const std::array<Vector3, 3>& x, const StrainTriangleConstraint& c,
                         StrainComponent component) {
  return partials(deformationGradient(x, c.restInverse), c, component).value;
}

std::array<Vector3, 3> strainTriangleGradients(const std::array<Vector3, 3>& x,
                                               const StrainTriangleConstraint& c,
                                               StrainComponent component) {
  return gradients(partials(deformationGradient(x, c.restInverse), c, component), c.restInverse);
}

std::array<Vector3, 3> strainTrianglePbd(const std::array<Vector3, 3>& x,
                                         const std::array<Real, 3>& inverseMasses,
                                         const StrainTriangleConstraint& c) {
  std::array<Vector3, 3> correction = {Vector3::Zero(), Vector3::Zero(), Vector3::Zero()};
  for (StrainComponent component :
       {StrainComponent::Xx, StrainComponent::Xy, StrainComponent::Yy}) {
    const std::array<Vector3, 3> current = {x[0] + correction[0], x[1] + correction[1],
                                            x[2] + correction[2]};
    const Partials p = partials(deformationGradient(current, c.restInverse), c, component);
    const std::array<Vector3, 3> g = gradients(p, c.restInverse);
    Real weightedNorm = 0;
    for (std::size_t i = 0; i < 3; ++i)
      weightedNorm += inverseMasses[i] * g[i].squaredNorm();
    if (!(weightedNorm > 0)) continue;
    const Real s = stiffnessOf(c, component) * p.value / weightedNorm;
    for (std::size_t i = 0; i < 3; ++i)
      correction[i] -= s * inverseMasses[i] * g[i];
  }
  return correction;
}

bool seedStrainTriangleRest(const std::array<Vector3, 3>& rest, Matrix2x2& restInverse) {
  // PositionBasedDynamics::init_StrainTriangleConstraint on (x, z, 0) of each vertex.
  const Real a = rest[1].x() - rest[0].x(), b = rest[2].x() - rest[0].x();
  const Real c = rest[1].z() - rest[0].z(), d = rest[2].z() - rest[0].z();
  const Real det = a * d - b * c;
  if (std::abs(det) < kSeedFemCutoff) return false;
  const Real s = Real(1) / det;
  restInverse(0, 0) = d * s;
  restInverse(0, 1) = -b * s;
  restInverse(1, 0) = -c * s;
  restInverse(1, 1) = a * s;
  return true;
}

std::array<Vector3, 3> seedStrainTrianglePbd(const std::array<Vector3, 3>& x,
                                             const std::array<Real, 3>& inverseMasses,
                                             const StrainTriangleConstraint& c) {
  // PositionBasedDynamics::solve_StrainTriangleConstraint, operation by operation.
  const Matrix2x2& b = c.restInverse;
  const std::array<Vector3, 2> columns = {Vector3(b(0, 0), b(1, 0), 0),
                                          Vector3(b(0, 1), b(1, 1), 0)};
  std::array<Vector3, 3> corr = {Vector3::Zero(), Vector3::Zero(), Vector3::Zero()};
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j <= i; ++j) {
      std::array<Vector3, 3> r;
      for (int k = 0; k < 3; ++k)
        r[std::size_t(k)] = Vector3((x[1][k] + corr[1][k]) - (x[0][k] + corr[0][k]),
                                    (x[2][k] + corr[2][k]) - (x[0][k] + corr[0][k]), 0);
      const Vector3& ci = columns[std::size_t(i)];
      const Vector3& cj = columns[std::size_t(j)];
      const Vector3 fi(r[0].dot(ci), r[1].dot(ci), r[2].dot(ci));
      const Vector3 fj(r[0].dot(cj), r[1].dot(cj), r[2].dot(cj));
      Real sij = 0;
      for (std::size_t k = 0; k < 3; ++k)
        sij += r[k].dot(ci) * r[k].dot(cj);
      std::array<Vector3, 3> d;
      d[0] = Vector3::Zero();
      for (int k = 0; k < 2; ++k) {
        Vector3& dk = d[std::size_t(k) + 1];
        dk = fj * b(k, i);
        dk += fi * b(k, j);
        d[0] -= dk;
      }
      if (i != j && c.normalizeShear) {
        Real fi2 = 0, fj2 = 0;
        for (std::size_t k = 0; k < 3; ++k) {
          fi2 += r[k].dot(ci) * r[k].dot(ci);
          fj2 += r[k].dot(cj) * r[k].dot(cj);
        }
        const Real li = std::sqrt(fi2), lj = std::sqrt(fj2);
        d[0] = Vector3::Zero();
        const Real s = sij / (fi2 * li * fj2 * lj);
        for (int k = 0; k < 2; ++k) {
          Vector3& dk = d[std::size_t(k) + 1];
          dk /= li * lj;
          dk -= lj * lj * fi * b(k, i) * s;
          dk -= li * li * fj * b(k, j) * s;
          d[0] -= dk;
        }
        sij = sij / (li * lj);
      }
      Real lambda = inverseMasses[0] * d[0].squaredNorm() + inverseMasses[1] * d[1].squaredNorm() +
                    inverseMasses[2] * d[2].squaredNorm();
      if (lambda == 0) continue;
      if (i == j) {
        const Real k = i == 0 ? c.xxStiffness : c.yyStiffness;
        if (c.normalizeStretch) {
          const Real s = std::sqrt(sij);
          lambda = Real(2) * s * (s - Real(1)) / lambda * k;
        } else {
          lambda = (sij - Real(1)) / lambda * k;
        }
      } else {
        lambda = sij / lambda * c.xyStiffness;
      }
      for (std::size_t n = 0; n < 3; ++n)
        corr[n] -= lambda * inverseMasses[n] * d[n];
    }
  return corr;
}

std::vector<StrainTriangleConstraint> strainTriangleConstraints(const Scene& scene) {
  std::vector<StrainTriangleConstraint> constraints;
  const SimulationSettings& settings = scene.simulation;
  if (settings.clothSimulationMethod != 3) return constraints;
  for (const TriangleModelDesc& model : scene.triangleModels) {
    for (const std::array<int, 3>& triangle : model.mesh.triangles) {
      StrainTriangleConstraint c;
      for (std::size_t i = 0; i < 3; ++i)
        c.particles[i] = model.firstParticle + triangle[i];
      std::array<Vector3, 3> rest;
      const bool anyDynamic = restPositions(scene, c.particles, rest);
      c.seedForm = femCutoffFor(settings) > 0;
      if (c.seedForm ? !seedStrainTriangleRest(rest, c.restInverse)
                     : !anyDynamic || !strainTriangleRest(rest, c.restInverse))
        continue;
      c.xxStiffness = settings.cloth_xxStiffness;
      c.yyStiffness = settings.cloth_yyStiffness;
      c.xyStiffness = settings.cloth_xyStiffness;
      c.normalizeStretch = settings.cloth_normalizeStretch;
      c.normalizeShear = settings.cloth_normalizeShear;
      constraints.push_back(c);
    }
  }
  return constraints;
}

void solveStrainTriangles(const std::vector<StrainTriangleConstraint>& constraints,
                          ParticleStates& particles, std::size_t begin, std::size_t end) {
  for (std::size_t k = begin, n = std::min(end, constraints.size()); k < n; ++k) {
    const StrainTriangleConstraint& c = constraints[k];
    std::array<Vector3, 3> x;
    std::array<Real, 3> w;
    gatherParticles(particles, c.particles, x, w);
    const std::array<Vector3, 3> d =
        c.seedForm ? seedStrainTrianglePbd(x, w, c) : strainTrianglePbd(x, w, c);
    applyCorrections(particles, c.particles, d);
  }
}

}  // namespace pbd
