#include "pbd/constraints/isometric_bending.h"

#include <algorithm>
#include <cmath>

#include "pbd/constraints/particle_stencil.h"
#include "pbd/model/scene.h"

namespace pbd {
namespace {

/// cot of the angle between a and b.
Real cotangent(const Vector3& a, const Vector3& b) {
  return a.dot(b) / a.cross(b).norm();
}

/// ∇_iC = scale K_i H and Σ w_i |∇_iC|².
struct Gradients {
  std::array<Vector3, 4> g;
  Real weightedNorm = 0;
};

Gradients gradients(const std::array<Vector3, 4>& x, const std::array<Real, 4>& inverseMasses,
                    const IsometricBendingConstraint& c) {
  Vector3 h = Vector3::Zero();
  for (std::size_t i = 0; i < 4; ++i)
    h += c.weights[i] * x[i];
  Gradients out;
  for (std::size_t i = 0; i < 4; ++i) {
    out.g[i] = c.scale * c.weights[i] * h;
    out.weightedNorm += inverseMasses[i] * out.g[i].squaredNorm();
  }
  return out;
}

/// The seed's init_IsometricBendingConstraint: Q = K ⊗ (coef K), coef = −3/(2 (A₀ + A₁)), with
/// its cotangents and areas (x₀, x₁ the edge).
Eigen::Matrix<Real, 4, 4> seedBendingMatrix(const std::array<Vector3, 4>& x) {
  const Vector3 e0 = x[1] - x[0];
  const Vector3 e1 = x[2] - x[0];
  const Vector3 e2 = x[3] - x[0];
  const Vector3 e3 = x[2] - x[1];
  const Vector3 e4 = x[3] - x[1];
  const Real c01 = cotangent(e0, e1);
  const Real c02 = cotangent(e0, e2);
  const Real c03 = cotangent(-e0, e3);
  const Real c04 = cotangent(-e0, e4);
  const Real a0 = Real(0.5) * (e0.cross(e1)).norm();
  const Real a1 = Real(0.5) * (e0.cross(e2)).norm();
  const Real coef = Real(-3) / (Real(2) * (a0 + a1));
  const Real k[4] = {c03 + c04, c01 + c02, -c01 - c03, -c02 - c04};
  const Real k2[4] = {coef * k[0], coef * k[1], coef * k[2], coef * k[3]};
  Eigen::Matrix<Real, 4, 4> q;
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < j; ++i)
      q(j, i) = q(i, j) = k[j] * k2[i];
    q(j, j) = k[j] * k2[j];
  }
  return q;
}

}  // namespace

bool isometricBendingStencil(const std::array<Vector3, 4>& rest, std::array<Real, 4>& weights,
                             Real& scale) {
  const Vector3 e0 = rest[1] - rest[0], e1 = rest[2] - rest[0], e2 = rest[3] - rest[0];
  const Vector3 e3 = rest[2] - rest[1], e4 = rest[3] - rest[1];
  const Real area0 = e0.cross(e1).norm() / 2, area1 = e0.cross(e2).norm() / 2;
  if (!(area0 > 0) || !(area1 > 0)) return false;
  const Real cotAlpha0 = cotangent(e0, e1), cotAlpha1 = cotangent(e0, e2);
  const Real cotBeta0 = cotangent(-e0, e3), cotBeta1 = cotangent(-e0, e4);
  weights = {cotBeta0 + cotBeta1, cotAlpha0 + cotAlpha1, -cotAlpha0 - cotBeta0,
             -cotAlpha1 - cotBeta1};
  scale = Real(3) / (area0 + area1);
  return true;
}

Real isometricBendingEnergy(const std::array<Vector3, 4>& x, const std::array<Real, 4>& weights,
                            Real scale) {
  Vector3 h = Vector3::Zero();
  for (std::size_t i = 0; i < 4; ++i)
    h += weights[i] * x[i];
  return scale * h.squaredNorm() / 2;
}

namespace {

/// The energy, its gradients and Σ w |∇C|² (static particles skipped) as the seed's
/// solve_IsometricBendingConstraint (PBD and XPBD) computes them, operation by operation.
struct SeedBendingTerms {
  Real energy = 0;
  std::array<Vector3, 4> g = {Vector3::Zero(), Vector3::Zero(), Vector3::Zero(), Vector3::Zero()};
  Real sum = 0;
};

SeedBendingTerms seedBendingTerms(const std::array<Vector3, 4>& x,
                                  const std::array<Real, 4>& inverseMasses,
                                  const IsometricBendingConstraint& c) {
  SeedBendingTerms t;
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < 4; ++j)
      t.energy += c.seedQ(j, k) * x[std::size_t(k)].dot(x[std::size_t(j)]);
  t.energy *= Real(0.5);
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < 4; ++j)
      t.g[std::size_t(j)] += c.seedQ(j, k) * x[std::size_t(k)];
  for (std::size_t j = 0; j < 4; ++j)
    if (inverseMasses[j] != 0) t.sum += inverseMasses[j] * t.g[j].squaredNorm();
  return t;
}

}  // namespace

BendingCorrection isometricBendingPbd(const std::array<Vector3, 4>& x,
                                      const std::array<Real, 4>& inverseMasses,
                                      const IsometricBendingConstraint& c) {
  BendingCorrection out;
  if (c.cutoff > 0) {
    // The seed's solve_IsometricBendingConstraint, operation by operation.
    const SeedBendingTerms t = seedBendingTerms(x, inverseMasses, c);
    const Real energy = t.energy, sum = t.sum;
    const std::array<Vector3, 4>& g = t.g;
    if (!(std::abs(sum) > c.cutoff)) return out;
    const Real s = energy / sum;
    for (std::size_t j = 0; j < 4; ++j)
      out.positions[j] = -c.stiffness * (s * inverseMasses[j]) * g[j];
    return out;
  }
  const Gradients g = gradients(x, inverseMasses, c);
  // At a flat state C and ∇C vanish together: nothing to do (and no direction).
  if (!(g.weightedNorm > kEpsilon * kEpsilon)) return out;
  const Real s = isometricBendingEnergy(x, c.weights, c.scale) / g.weightedNorm;
  for (std::size_t i = 0; i < 4; ++i)
    out.positions[i] = -c.stiffness * s * inverseMasses[i] * g.g[i];
  return out;
}

BendingCorrection isometricBendingXpbd(const std::array<Vector3, 4>& x,
                                       const std::array<Real, 4>& inverseMasses,
                                       const IsometricBendingConstraint& c, Real substepSize) {
  BendingCorrection out;
  if (!(c.stiffness > 0)) return out;
  if (c.cutoff > 0) {
    // The seed's XPBD::solve_IsometricBendingConstraint, operation by operation: α̃ added to
    // Σ w |∇C|², no correction when that sum is at most the cut-off.
    const SeedBendingTerms t = seedBendingTerms(x, inverseMasses, c);
    const Real compliance = Real(1) / (c.stiffness * substepSize * substepSize);  // α̃
    const Real sum = t.sum + compliance;
    if (!(std::abs(sum) > c.cutoff)) return out;
    out.multiplier = -(t.energy + compliance * c.multiplier) / sum;
    for (std::size_t j = 0; j < 4; ++j)
      out.positions[j] = (out.multiplier * inverseMasses[j]) * t.g[j];
    return out;
  }
  const Gradients g = gradients(x, inverseMasses, c);
  const Real compliance = Real(1) / (c.stiffness * substepSize * substepSize);  // α̃
  out.multiplier = (-isometricBendingEnergy(x, c.weights, c.scale) - compliance * c.multiplier) /
                   (g.weightedNorm + compliance);
  for (std::size_t i = 0; i < 4; ++i)
    out.positions[i] = out.multiplier * inverseMasses[i] * g.g[i];
  return out;
}

std::vector<IsometricBendingConstraint> clothBendingConstraints(const Scene& scene) {
  std::vector<IsometricBendingConstraint> constraints;
  const int cloth = scene.simulation.clothSimulationMethod;
  const int bending = scene.simulation.clothBendingMethod;
  if (cloth < 1 || cloth > 4 || (bending != 2 && bending != 3)) return constraints;
  for (const TriangleModelDesc& model : scene.triangleModels) {
    for (const EdgeStencil& stencil : interiorEdgeStencils(model.mesh)) {
      IsometricBendingConstraint c;
      const std::array<int, 4> local = {stencil.edge[0], stencil.edge[1], stencil.opposite[0],
                                        stencil.opposite[1]};
      for (std::size_t i = 0; i < 4; ++i)
        c.particles[i] = model.firstParticle + local[i];
      std::array<Vector3, 4> rest;
      const bool anyDynamic = restPositions(scene, c.particles, rest);
      if (!anyDynamic || !isometricBendingStencil(rest, c.weights, c.scale)) continue;
      c.xpbd = bending == 3;
      c.stiffness = clothBendingStiffnessFor(scene.simulation);
      c.cutoff = femCutoffFor(scene.simulation);
      c.seedQ = seedBendingMatrix(rest);
      constraints.push_back(c);
    }
  }
  return constraints;
}

void solveIsometricBending(std::vector<IsometricBendingConstraint>& constraints,
                           ParticleStates& particles, Real substepSize, bool firstIteration,
                           std::size_t begin, std::size_t end) {
  for (std::size_t k = begin, n = std::min(end, constraints.size()); k < n; ++k) {
    IsometricBendingConstraint& c = constraints[k];
    std::array<Vector3, 4> x;
    std::array<Real, 4> w;
    gatherParticles(particles, c.particles, x, w);
    BendingCorrection d;
    if (c.xpbd) {
      if (firstIteration) c.multiplier = 0;
      d = isometricBendingXpbd(x, w, c, substepSize);
      c.multiplier += d.multiplier;
    } else {
      d = isometricBendingPbd(x, w, c);
    }
    applyCorrections(particles, c.particles, d.positions);
  }
}

}  // namespace pbd
