#include "pbd/constraints/fem_tet.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>

#include "pbd/constraints/particle_stencil.h"
#include "pbd/model/scene.h"

namespace pbd {

// Every formula below is evaluated in the seed's operation order (init_FEMTetraConstraint,
// computeGreenStrainAndPiolaStress, computeGradCGreen, solve_FEMTetraConstraint and XPBD's),
// so that the `pbd` method reproduces the original's round-off and not only its mathematics.

LameParameters lameParameters(Real youngsModulus, Real poissonRatio) {
  LameParameters l;
  l.mu = youngsModulus / Real(2) / (Real(1) + poissonRatio);
  l.lambda =
      youngsModulus * poissonRatio / (Real(1) + poissonRatio) / (Real(1) - Real(2) * poissonRatio);
  return l;
}

namespace {

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

/// U and ∇U with the Lamé parameters `lame` (of E for U, of E = 1 for XPBD's U′ = U/E).
FemTetEnergy energyAndGradients(const std::array<Vector3, 4>& x, const FemTetConstraint& c,
                                const LameParameters& lame) {
  FemTetEnergy out;
  Matrix3 f = femDeformationGradient(x, c.inverseRestMatrix);
  out.inverted = !(f.determinant() > 0);
  if (out.inverted) f = clampedDeformationGradient(f);
  Matrix3 epsilon;
  epsilon(0, 0) = Real(0.5) * (f(0, 0) * f(0, 0) + f(1, 0) * f(1, 0) + f(2, 0) * f(2, 0) - Real(1));
  epsilon(1, 1) = Real(0.5) * (f(0, 1) * f(0, 1) + f(1, 1) * f(1, 1) + f(2, 1) * f(2, 1) - Real(1));
  epsilon(2, 2) = Real(0.5) * (f(0, 2) * f(0, 2) + f(1, 2) * f(1, 2) + f(2, 2) * f(2, 2) - Real(1));
  epsilon(0, 1) = Real(0.5) * (f(0, 0) * f(0, 1) + f(1, 0) * f(1, 1) + f(2, 0) * f(2, 1));
  epsilon(0, 2) = Real(0.5) * (f(0, 0) * f(0, 2) + f(1, 0) * f(1, 2) + f(2, 0) * f(2, 2));
  epsilon(1, 2) = Real(0.5) * (f(0, 1) * f(0, 2) + f(1, 1) * f(1, 2) + f(2, 1) * f(2, 2));
  epsilon(1, 0) = epsilon(0, 1);
  epsilon(2, 0) = epsilon(0, 2);
  epsilon(2, 1) = epsilon(1, 2);
  const Real trace = epsilon(0, 0) + epsilon(1, 1) + epsilon(2, 2);
  const Real lambdaTrace = lame.lambda * trace;
  Matrix3 sigma = epsilon * Real(2) * lame.mu;
  sigma(0, 0) += lambdaTrace;
  sigma(1, 1) += lambdaTrace;
  sigma(2, 2) += lambdaTrace;
  sigma = (f * sigma).eval();
  Real psi = 0;
  for (int j = 0; j < 3; ++j)
    for (int k = 0; k < 3; ++k)
      psi += epsilon(j, k) * epsilon(j, k);
  psi = lame.mu * psi + Real(0.5) * lame.lambda * trace * trace;
  out.energy = c.restVolume * psi;
  const Matrix3 restInverseTransposed = c.inverseRestMatrix.transpose();
  const Matrix3 h = sigma * restInverseTransposed * c.restVolume;
  for (int i = 0; i < 3; ++i)
    out.gradients[std::size_t(i)] = h.col(i);
  out.gradients[3] = -out.gradients[0] - out.gradients[1] - out.gradients[2];
  return out;
}

/// Σ w_i |g_i|², left to right.
Real weightedGradientNorm(const std::array<Vector3, 4>& gradients,
                          const std::array<Real, 4>& inverseMasses) {
  return inverseMasses[0] * gradients[0].squaredNorm() +
         inverseMasses[1] * gradients[1].squaredNorm() +
         inverseMasses[2] * gradients[2].squaredNorm() +
         inverseMasses[3] * gradients[3].squaredNorm();
}

}  // namespace

bool femTetRestState(const std::array<Vector3, 4>& rest, Matrix3& inverseRestMatrix,
                     Real& restVolume, Real minimumDeterminant) {
  Matrix3 d;
  d.col(0) = rest[0] - rest[3];
  d.col(1) = rest[1] - rest[3];
  d.col(2) = rest[2] - rest[3];
  const Real det = d.determinant();
  const Real scale = d.col(0).norm() * d.col(1).norm() * d.col(2).norm();
  // The determinant's round-off is a few ε of the product of the edge lengths; the seed's
  // builder also drops |det| ≤ 10⁻⁶ (minimumDeterminant, femCutoffFor).
  if (!(std::abs(det) > 100 * kEpsilon * scale) || !(std::abs(det) > minimumDeterminant))
    return false;
  inverseRestMatrix = d.inverse();
  restVolume = std::abs(Real(1.0 / 6.0) *
                        (rest[3] - rest[0]).dot((rest[2] - rest[0]).cross(rest[1] - rest[0])));
  return true;
}

Matrix3 femDeformationGradient(const std::array<Vector3, 4>& x, const Matrix3& b) {
  const Vector3 p14 = x[0] - x[3];
  const Vector3 p24 = x[1] - x[3];
  const Vector3 p34 = x[2] - x[3];
  Matrix3 f;
  for (int r = 0; r < 3; ++r)
    for (int col = 0; col < 3; ++col)
      f(r, col) = p14[r] * b(0, col) + p24[r] * b(1, col) + p34[r] * b(2, col);
  return f;
}

FemTetEnergy femTetEnergy(const std::array<Vector3, 4>& x, const FemTetConstraint& c) {
  return energyAndGradients(x, c, lameParameters(c.youngsModulus, c.poissonRatio));
}

FemTetCorrection femTetPbd(const std::array<Vector3, 4>& x,
                           const std::array<Real, 4>& inverseMasses, const FemTetConstraint& c) {
  FemTetCorrection out;
  const FemTetEnergy e = femTetEnergy(x, c);
  const Real denominator = weightedGradientNorm(e.gradients, inverseMasses);
  // At rest U and ∇U vanish together: nothing to do (and no direction). The seed also skips
  // every Σ w|∇U|² below its 10⁻⁶ (c.cutoff).
  if (!(denominator > kEpsilon * kEpsilon) || denominator < c.cutoff) return out;
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
  // U′ = U/E and g = ∇U′ with the Lamé parameters of E = 1; C = √(2U′): ∇C = g/C.
  const FemTetEnergy e = energyAndGradients(x, c, lameParameters(Real(1), c.poissonRatio));
  const Real constraint = std::sqrt(Real(2) * std::max(e.energy, Real(0)));
  const Real compliance = Real(1) / (c.youngsModulus * substepSize * substepSize);  // α̃
  Real denominator = weightedGradientNorm(e.gradients, inverseMasses);
  denominator += constraint * constraint * compliance;
  if (!(denominator > 0) || denominator < c.cutoff) return out;
  const Real numerator = -constraint - compliance * c.multiplier;  // −C − α̃ λ
  out.multiplier = constraint * constraint * numerator / denominator;
  const Real scale = constraint * numerator / denominator;
  for (std::size_t i = 0; i < 4; ++i)
    out.positions[i] = scale * inverseMasses[i] * e.gradients[i];
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
      for (std::size_t i = 0; i < 4; ++i)
        c.particles[i] = model.firstParticle + int(tet[i]);
      std::array<Vector3, 4> rest;
      const bool anyDynamic = restPositions(scene, c.particles, rest);
      if (!anyDynamic ||
          !femTetRestState(rest, c.inverseRestMatrix, c.restVolume, femCutoffFor(scene.simulation)))
        continue;
      c.cutoff = femCutoffFor(scene.simulation);
      c.youngsModulus = solidStiffnessFor(scene.simulation);
      c.poissonRatio = poissonRatio;
      c.xpbd = method == 3;
      constraints.push_back(c);
    }
  return constraints;
}

void solveFemTets(std::vector<FemTetConstraint>& constraints, ParticleStates& particles,
                  Real substepSize, bool firstIteration, std::size_t begin, std::size_t end) {
  for (std::size_t k = begin, n = std::min(end, constraints.size()); k < n; ++k) {
    FemTetConstraint& c = constraints[k];
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
