#include "pbd/constraints/fem_tet.h"
#include "pbd/constraints/particle_stencil.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>

#include "pbd/model/scene.h"

namespace pbd {

LameParameters lameParameters(Real youngsModulus, Real poissonRatio) {
  LameParameters l;
  l.mu = youngsModulus / (2 * (1 + poissonRatio));
  l.lambda = youngsModulus * poissonRatio / ((1 + poissonRatio) * (1 - 2 * poissonRatio));
  return l;
}

namespace {

/// D = [x₁ − x₀, x₂ − x₀, x₃ − x₀].
Matrix3 edgeMatrix(const std::array<Vector3, 4>& x) {
  Matrix3 d;
  d.col(0) = x[1] - x[0];
  d.col(1) = x[2] - x[0];
  d.col(2) = x[3] - x[0];
  return d;
}

/// F̂ = U Σ̂ Vᵀ: F with U, V rotations and every singular value clamped to
/// ≥ kFemInversionMinimumSingularValue (the smallest one carries the sign of det F before).
Matrix3 clampedDeformationGradient(const Matrix3& f) {
  const Eigen::JacobiSVD<Matrix3> svd(f, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Matrix3 u = svd.matrixU();
  Matrix3 v = svd.matrixV();
  Vector3 sigma = svd.singularValues();  // descending, ≥ 0
  // Make U and V rotations; each reflection removed flips the smallest singular value.
  if (u.determinant() < 0) {
    u.col(2) = -u.col(2);
    sigma(2) = -sigma(2);
  }
  if (v.determinant() < 0) {
    v.col(2) = -v.col(2);
    sigma(2) = -sigma(2);
  }
  for (int i = 0; i < 3; ++i)
    sigma(i) = std::max(sigma(i), kFemInversionMinimumSingularValue);
  return u * sigma.asDiagonal() * v.transpose();
}

}  // namespace

bool femTetRestState(const std::array<Vector3, 4>& rest, Matrix3& inverseRestMatrix,
                     Real& restVolume) {
  const Matrix3 d = edgeMatrix(rest);
  const Real det = d.determinant();
  const Real scale = d.col(0).norm() * d.col(1).norm() * d.col(2).norm();
  // The determinant's round-off is a few ε of the product of the edge lengths.
  if (!(std::abs(det) > 100 * kEpsilon * scale)) return false;
  inverseRestMatrix = d.inverse();
  restVolume = std::abs(det) / 6;
  return true;
}

Matrix3 femDeformationGradient(const std::array<Vector3, 4>& x, const Matrix3& inverseRestMatrix) {
  return edgeMatrix(x) * inverseRestMatrix;
}

FemTetEnergy femTetEnergy(const std::array<Vector3, 4>& x, const FemTetConstraint& c) {
  FemTetEnergy out;
  Matrix3 f = femDeformationGradient(x, c.inverseRestMatrix);
  out.inverted = !(f.determinant() > 0);
  if (out.inverted) f = clampedDeformationGradient(f);
  const LameParameters lame = lameParameters(c.youngsModulus, c.poissonRatio);
  const Matrix3 strain = (f.transpose() * f - Matrix3::Identity()) / 2;
  const Real trace = strain.trace();
  out.energy =
      c.restVolume * (lame.mu * strain.cwiseAbs2().sum() + lame.lambda * trace * trace / 2);
  const Matrix3 piola = f * (2 * lame.mu * strain + lame.lambda * trace * Matrix3::Identity());
  const Matrix3 h = c.restVolume * piola * c.inverseRestMatrix.transpose();
  for (int i = 0; i < 3; ++i)
    out.gradients[std::size_t(i) + 1] = h.col(i);
  out.gradients[0] = -(out.gradients[1] + out.gradients[2] + out.gradients[3]);
  return out;
}

namespace {

/// Σ w_i |g_i|².
Real weightedGradientNorm(const std::array<Vector3, 4>& gradients,
                          const std::array<Real, 4>& inverseMasses) {
  Real sum = 0;
  for (std::size_t i = 0; i < 4; ++i)
    sum += inverseMasses[i] * gradients[i].squaredNorm();
  return sum;
}

}  // namespace

FemTetCorrection femTetPbd(const std::array<Vector3, 4>& x,
                           const std::array<Real, 4>& inverseMasses, const FemTetConstraint& c) {
  FemTetCorrection out;
  const FemTetEnergy e = femTetEnergy(x, c);
  const Real denominator = weightedGradientNorm(e.gradients, inverseMasses);
  // At rest U and ∇U vanish together: nothing to do (and no direction).
  if (!(denominator > kEpsilon * kEpsilon)) return out;
  const Real s = e.energy / denominator;
  for (std::size_t i = 0; i < 4; ++i)
    out.positions[i] = -s * inverseMasses[i] * e.gradients[i];
  return out;
}

FemTetCorrection femTetXpbd(const std::array<Vector3, 4>& x,
                            const std::array<Real, 4>& inverseMasses, const FemTetConstraint& c,
                            Real substepSize) {
  FemTetCorrection out;
  if (!(c.youngsModulus > 0)) return out;
  const FemTetEnergy e = femTetEnergy(x, c);
  // g = ∇U/E = ∇U′ and C = √(2U′): ∇C = g/C.
  std::array<Vector3, 4> g;
  for (std::size_t i = 0; i < 4; ++i)
    g[i] = e.gradients[i] / c.youngsModulus;
  const Real constraint = std::sqrt(2 * std::max(e.energy, Real(0)) / c.youngsModulus);
  const Real compliance = Real(1) / (c.youngsModulus * substepSize * substepSize);  // α̃
  const Real denominator =
      weightedGradientNorm(g, inverseMasses) + compliance * constraint * constraint;
  if (!(denominator > 0)) return out;
  const Real numerator = -constraint - compliance * c.multiplier;  // −C − α̃ λ
  out.multiplier = constraint * constraint * numerator / denominator;
  const Real scale = constraint * numerator / denominator;
  for (std::size_t i = 0; i < 4; ++i)
    out.positions[i] = scale * inverseMasses[i] * g[i];
  return out;
}

std::vector<FemTetConstraint> solidFemConstraints(const Scene& scene) {
  std::vector<FemTetConstraint> constraints;
  const int method = scene.simulation.solidSimulationMethod;
  if (method != 2 && method != 3) return constraints;
  const Real poissonRatio = scene.simulation.solid_poissonRatio;
  // The seed's solve rejects ν outside [0, 0.49] (and ν = ½ has no λ_L): no constraints.
  if (!(poissonRatio >= 0 && poissonRatio <= Real(0.49))) return constraints;
  for (const TetModelDesc& model : scene.tetModels)
    for (const auto& tet : model.mesh.tetrahedra) {
      FemTetConstraint c;
      for (std::size_t i = 0; i < 4; ++i) c.particles[i] = model.firstParticle + int(tet[i]);
      std::array<Vector3, 4> rest;
      const bool anyDynamic = restPositions(scene, c.particles, rest);
      if (!anyDynamic || !femTetRestState(rest, c.inverseRestMatrix, c.restVolume)) continue;
      c.youngsModulus = solidStiffnessFor(scene.simulation);
      c.poissonRatio = poissonRatio;
      c.xpbd = method == 3;
      constraints.push_back(c);
    }
  return constraints;
}

void solveFemTets(std::vector<FemTetConstraint>& constraints, ParticleStates& particles,
                  Real substepSize, bool firstIteration) {
  for (FemTetConstraint& c : constraints) {
    std::array<Vector3, 4> x;
    std::array<Real, 4> w;
    gatherParticles(particles, c.particles, x, w);
    FemTetCorrection d;
    if (c.xpbd) {
      if (firstIteration) c.multiplier = 0;
      d = femTetXpbd(x, w, c, substepSize);
      c.multiplier += d.multiplier;
    } else {
      d = femTetPbd(x, w, c);
    }
    applyCorrections(particles, c.particles, d.positions);
  }
}

}  // namespace pbd
