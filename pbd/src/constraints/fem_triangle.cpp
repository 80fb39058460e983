#include "pbd/constraints/fem_triangle.h"
#include "pbd/constraints/particle_stencil.h"

#include <cmath>

#include "pbd/model/scene.h"

namespace pbd {
namespace {

using Matrix2x2 = Eigen::Matrix<Real, 2, 2>;
using Matrix3x2 = Eigen::Matrix<Real, 3, 2>;

/// F = [x₁ − x₀, x₂ − x₀] B.
Matrix3x2 deformationGradient(const std::array<Vector3, 3>& x, const Matrix2x2& restInverse) {
  Matrix3x2 edges;
  edges.col(0) = x[1] - x[0];
  edges.col(1) = x[2] - x[0];
  return edges * restInverse;
}

Matrix2x2 greenStrain(const Matrix3x2& f) {
  return (f.transpose() * f - Matrix2x2::Identity()) / 2;
}

/// S = ∂ψ/∂E.
Matrix2x2 secondPiolaKirchhoff(const Matrix2x2& e, const OrthotropicStiffness& k) {
  Matrix2x2 s;
  s(0, 0) = k.xx * e(0, 0) + k.xy * e(1, 1);
  s(1, 1) = k.xy * e(0, 0) + k.yy * e(1, 1);
  s(0, 1) = s(1, 0) = k.shear * e(0, 1);
  return s;
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

bool femTriangleRest(const std::array<Vector3, 3>& rest, Real& area, Matrix2x2& restInverse) {
  const Vector3 e1 = rest[1] - rest[0], e2 = rest[2] - rest[0];
  const Vector3 normal = e1.cross(e2);
  const Real normalLength = normal.norm(), edgeLength = e1.norm();
  if (!(normalLength > 0) || !(edgeLength > 0)) return false;
  const Vector3 yAxis = e1 / edgeLength;
  const Vector3 xAxis = (normal / normalLength).cross(yAxis);
  Matrix2x2 restEdges;
  restEdges << e1.dot(xAxis), e2.dot(xAxis), e1.dot(yAxis), e2.dot(yAxis);
  const Real determinant = restEdges.determinant();
  if (!(std::abs(determinant) > 0)) return false;
  area = normalLength / 2;
  restInverse = restEdges.inverse();
  return true;
}

Matrix2x2 femTriangleStrain(const std::array<Vector3, 3>& x, const FemTriangleConstraint& c) {
  return greenStrain(deformationGradient(x, c.restInverse));
}

Real femTriangleEnergy(const std::array<Vector3, 3>& x, const FemTriangleConstraint& c) {
  const Matrix2x2 e = femTriangleStrain(x, c);
  const Matrix2x2 s = secondPiolaKirchhoff(e, c.stiffness);
  return c.area * (e.cwiseProduct(s).sum()) / 2;
}

std::array<Vector3, 3> femTriangleGradients(const std::array<Vector3, 3>& x,
                                            const FemTriangleConstraint& c) {
  const Matrix3x2 f = deformationGradient(x, c.restInverse);
  const Matrix2x2 s = secondPiolaKirchhoff(greenStrain(f), c.stiffness);
  const Matrix3x2 h = c.area * f * s * c.restInverse.transpose();
  return {-h.col(0) - h.col(1), h.col(0), h.col(1)};
}

std::array<Vector3, 3> femTrianglePbd(const std::array<Vector3, 3>& x,
                                      const std::array<Real, 3>& inverseMasses,
                                      const FemTriangleConstraint& c) {
  std::array<Vector3, 3> correction = {Vector3::Zero(), Vector3::Zero(), Vector3::Zero()};
  const std::array<Vector3, 3> g = femTriangleGradients(x, c);
  Real weightedNorm = 0;
  for (std::size_t i = 0; i < 3; ++i) weightedNorm += inverseMasses[i] * g[i].squaredNorm();
  if (!(weightedNorm > 0)) return correction;
  const Real s = femTriangleEnergy(x, c) / weightedNorm;
  for (std::size_t i = 0; i < 3; ++i) correction[i] = -s * inverseMasses[i] * g[i];
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
      for (std::size_t i = 0; i < 3; ++i) c.particles[i] = model.firstParticle + triangle[i];
      std::array<Vector3, 3> rest;
      const bool anyDynamic = restPositions(scene, c.particles, rest);
      if (!anyDynamic || !femTriangleRest(rest, c.area, c.restInverse)) continue;
      c.stiffness = stiffness;
      constraints.push_back(c);
    }
  }
  return constraints;
}

void solveFemTriangles(const std::vector<FemTriangleConstraint>& constraints,
                       ParticleStates& particles) {
  for (const FemTriangleConstraint& c : constraints) {
    std::array<Vector3, 3> x;
    std::array<Real, 3> w;
    gatherParticles(particles, c.particles, x, w);
    const std::array<Vector3, 3> d = femTrianglePbd(x, w, c);
    applyCorrections(particles, c.particles, d);
  }
}

}  // namespace pbd
