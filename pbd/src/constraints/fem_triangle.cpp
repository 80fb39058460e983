#include "pbd/constraints/fem_triangle.h"

#include <algorithm>
#include <cmath>

#include "pbd/constraints/particle_stencil.h"
#include "pbd/model/scene.h"

namespace pbd {
namespace {

using Matrix2x2 = Eigen::Matrix<Real, 2, 2>;
using Matrix3x2 = Eigen::Matrix<Real, 3, 2>;

// Every formula below is evaluated in the seed's operation order (solve_FEMTriangleConstraint),
// so that the `pbd` method reproduces the original's round-off and not only its mathematics.

/// F = [x₀ − x₂, x₁ − x₂] B, element by element.
Matrix3x2 deformationGradient(const std::array<Vector3, 3>& x, const Matrix2x2& b) {
  const Vector3 p13 = x[0] - x[2];
  const Vector3 p23 = x[1] - x[2];
  Matrix3x2 f;
  for (int r = 0; r < 3; ++r) {
    f(r, 0) = p13[r] * b(0, 0) + p23[r] * b(1, 0);
    f(r, 1) = p13[r] * b(0, 1) + p23[r] * b(1, 1);
  }
  return f;
}

Matrix2x2 greenStrain(const Matrix3x2& f) {
  Matrix2x2 e;
  e(0, 0) = Real(0.5) * (f(0, 0) * f(0, 0) + f(1, 0) * f(1, 0) + f(2, 0) * f(2, 0) - Real(1));
  e(1, 1) = Real(0.5) * (f(0, 1) * f(0, 1) + f(1, 1) * f(1, 1) + f(2, 1) * f(2, 1) - Real(1));
  e(0, 1) = Real(0.5) * (f(0, 0) * f(0, 1) + f(1, 0) * f(1, 1) + f(2, 0) * f(2, 1));
  e(1, 0) = e(0, 1);
  return e;
}

/// S = ∂ψ/∂E.
Matrix2x2 secondPiolaKirchhoff(const Matrix2x2& e, const OrthotropicStiffness& k) {
  Matrix2x2 s;
  s(0, 0) = k.xx * e(0, 0) + k.xy * e(1, 1);
  s(1, 1) = k.xy * e(0, 0) + k.yy * e(1, 1);
  s(0, 1) = s(1, 0) = k.shear * e(0, 1);
  return s;
}

/// C = A ψ with ψ = ½ E : S summed row by row.
Real energyOf(const Matrix2x2& e, const Matrix2x2& s, Real area) {
  Real psi = 0;
  for (int j = 0; j < 2; ++j)
    for (int k = 0; k < 2; ++k)
      psi += e(j, k) * s(j, k);
  return area * (Real(0.5) * psi);
}

std::array<Vector3, 3> gradientsOf(const Matrix3x2& f, const Matrix2x2& s,
                                   const FemTriangleConstraint& c) {
  const Matrix3x2 piola = f * s;
  const Matrix3x2 h = c.area * piola * c.restInverse.transpose();
  const Vector3 g0 = h.col(0), g1 = h.col(1);
  return {g0, g1, -g0 - g1};
}

}  // namespace

OrthotropicStiffness orthotropicStiffness(Real youngsX, Real youngsY, Real shear, Real poissonXY,
                                          Real poissonYX) {
  const Real denominator = 1 - poissonXY * poissonYX;
  OrthotropicStiffness k;
  k.xx = youngsX / denominator;
  k.yy = youngsY / denominator;
  k.xy = (youngsX * poissonYX + youngsY * poissonXY) / (2 * denominator);
  k.shear = shear;
  return k;
}

bool femTriangleRest(const std::array<Vector3, 3>& rest, Real& area, Matrix2x2& restInverse,
                     Real minimumDeterminant) {
  const Vector3 normal = (rest[1] - rest[0]).cross(rest[2] - rest[0]);
  const Vector3 e1 = rest[1] - rest[0];
  const Real normalLength = normal.norm(), edgeLength = e1.norm();
  if (!(normalLength > 0) || !(edgeLength > 0)) return false;
  const Vector3 yAxis = e1 / edgeLength;
  Vector3 xAxis = normal.cross(yAxis);
  xAxis.normalize();
  // Material coordinates of the three vertices, then D_m = [X₀ − X₂, X₁ − X₂].
  std::array<Vector2, 3> p;
  for (std::size_t i = 0; i < 3; ++i)
    p[i] = Vector2(rest[i].dot(xAxis), rest[i].dot(yAxis));
  Matrix2x2 restEdges;
  restEdges(0, 0) = p[0][0] - p[2][0];
  restEdges(1, 0) = p[0][1] - p[2][1];
  restEdges(0, 1) = p[1][0] - p[2][0];
  restEdges(1, 1) = p[1][1] - p[2][1];
  const Real determinant = restEdges.determinant();
  if (!(std::abs(determinant) > minimumDeterminant) || !(std::abs(determinant) > 0)) return false;
  area = normalLength * Real(0.5);
  restInverse = restEdges.inverse();
  return true;
}

Matrix2x2 femTriangleStrain(const std::array<Vector3, 3>& x, const FemTriangleConstraint& c) {
  return greenStrain(deformationGradient(x, c.restInverse));
}

Real femTriangleEnergy(const std::array<Vector3, 3>& x, const FemTriangleConstraint& c) {
  const Matrix2x2 e = femTriangleStrain(x, c);
  return energyOf(e, secondPiolaKirchhoff(e, c.stiffness), c.area);
}

std::array<Vector3, 3> femTriangleGradients(const std::array<Vector3, 3>& x,
                                            const FemTriangleConstraint& c) {
  const Matrix3x2 f = deformationGradient(x, c.restInverse);
  return gradientsOf(f, secondPiolaKirchhoff(greenStrain(f), c.stiffness), c);
}

std::array<Vector3, 3> femTrianglePbd(const std::array<Vector3, 3>& x,
                                      const std::array<Real, 3>& inverseMasses,
                                      const FemTriangleConstraint& c) {
  std::array<Vector3, 3> correction = {Vector3::Zero(), Vector3::Zero(), Vector3::Zero()};
  const Matrix3x2 f = deformationGradient(x, c.restInverse);
  const Matrix2x2 e = greenStrain(f);
  const Matrix2x2 stress = secondPiolaKirchhoff(e, c.stiffness);
  const std::array<Vector3, 3> g = gradientsOf(f, stress, c);
  Real weightedNorm = inverseMasses[0] * g[0].squaredNorm();
  weightedNorm += inverseMasses[1] * g[1].squaredNorm();
  weightedNorm += inverseMasses[2] * g[2].squaredNorm();
  if (!(std::abs(weightedNorm) > c.cutoff) || !(weightedNorm > 0)) return correction;
  const Real s = energyOf(e, stress, c.area) / weightedNorm;
  for (std::size_t i = 0; i < 3; ++i)
    correction[i] = -(s * inverseMasses[i]) * g[i];
  return correction;
}

std::vector<FemTriangleConstraint> femTriangleConstraints(const Scene& scene) {
  std::vector<FemTriangleConstraint> constraints;
  const SimulationSettings& settings = scene.simulation;
  if (settings.clothSimulationMethod != 2) return constraints;
  const OrthotropicStiffness stiffness = orthotropicStiffness(
      settings.cloth_xxStiffness, settings.cloth_yyStiffness, settings.cloth_xyStiffness,
      settings.cloth_xyPoissonRatio, settings.cloth_yxPoissonRatio);
  for (const TriangleModelDesc& model : scene.triangleModels) {
    for (const std::array<int, 3>& triangle : model.mesh.triangles) {
      FemTriangleConstraint c;
      for (std::size_t i = 0; i < 3; ++i)
        c.particles[i] = model.firstParticle + triangle[i];
      std::array<Vector3, 3> rest;
      const bool anyDynamic = restPositions(scene, c.particles, rest);
      // The seed also drops a triangle whose |det D_m| is not above its 10⁻⁶
      // (init_FEMTriangleConstraint).
      if (!anyDynamic || !femTriangleRest(rest, c.area, c.restInverse, femCutoffFor(settings)))
        continue;
      c.stiffness = stiffness;
      c.cutoff = femCutoffFor(settings);
      constraints.push_back(c);
    }
  }
  return constraints;
}

void solveFemTriangles(const std::vector<FemTriangleConstraint>& constraints,
                       ParticleStates& particles, std::size_t begin, std::size_t end) {
  for (std::size_t k = begin, n = std::min(end, constraints.size()); k < n; ++k) {
    const FemTriangleConstraint& c = constraints[k];
    std::array<Vector3, 3> x;
    std::array<Real, 3> w;
    gatherParticles(particles, c.particles, x, w);
    const std::array<Vector3, 3> d = femTrianglePbd(x, w, c);
    applyCorrections(particles, c.particles, d);
  }
}

}  // namespace pbd
