#include "pbd/constraints/tet_volume.h"

#include <algorithm>
#include <cmath>

#include "pbd/constraints/particle_stencil.h"
#include "pbd/model/scene.h"

namespace pbd {

Real signedTetVolume(const std::array<Vector3, 4>& p) {
  return (p[1] - p[0]).cross(p[2] - p[0]).dot(p[3] - p[0]) / Real(6);
}

std::array<Vector3, 4> tetVolumeGradients(const std::array<Vector3, 4>& p) {
  std::array<Vector3, 4> g;
  g[1] = (p[2] - p[0]).cross(p[3] - p[0]) / Real(6);
  g[2] = (p[3] - p[0]).cross(p[1] - p[0]) / Real(6);
  g[3] = (p[1] - p[0]).cross(p[2] - p[0]) / Real(6);
  g[0] = -(g[1] + g[2] + g[3]);
  return g;
}

namespace {

/// Σ w_i |∇_iC|².
Real weightedGradientNorm(const std::array<Vector3, 4>& gradients,
                          const std::array<Real, 4>& inverseMasses) {
  Real sum = 0;
  for (std::size_t i = 0; i < 4; ++i)
    sum += inverseMasses[i] * gradients[i].squaredNorm();
  return sum;
}

}  // namespace

TetVolumeCorrection tetVolumePbd(const std::array<Vector3, 4>& p,
                                 const std::array<Real, 4>& inverseMasses, Real restVolume,
                                 Real stiffness) {
  TetVolumeCorrection c;
  const std::array<Vector3, 4> gradients = tetVolumeGradients(p);
  const Real denominator = weightedGradientNorm(gradients, inverseMasses);
  if (!(denominator > 0)) return c;
  const Real s = (signedTetVolume(p) - restVolume) / denominator;
  for (std::size_t i = 0; i < 4; ++i)
    c.positions[i] = -stiffness * s * inverseMasses[i] * gradients[i];
  return c;
}

TetVolumeCorrection tetVolumeXpbd(const std::array<Vector3, 4>& p,
                                  const std::array<Real, 4>& inverseMasses, Real restVolume,
                                  Real stiffness, Real substepSize, Real multiplier) {
  TetVolumeCorrection c;
  if (!(stiffness > 0)) return c;
  const std::array<Vector3, 4> gradients = tetVolumeGradients(p);
  const Real denominator = weightedGradientNorm(gradients, inverseMasses);
  if (!(denominator > 0)) return c;
  const Real compliance = Real(1) / (stiffness * substepSize * substepSize);  // α̃
  c.multiplier =
      (-(signedTetVolume(p) - restVolume) - compliance * multiplier) / (denominator + compliance);
  for (std::size_t i = 0; i < 4; ++i)
    c.positions[i] = c.multiplier * inverseMasses[i] * gradients[i];
  return c;
}

Real seedRestTetVolume(const std::array<Vector3, 4>& p) {
  return std::abs(Real(1.0 / 6.0) * (p[3] - p[0]).dot((p[2] - p[0]).cross(p[1] - p[0])));
}

namespace {

/// V, the gradients 6 ∇V and Σ w |6 ∇V|² as the seed's solve_VolumeConstraint (PBD and XPBD)
/// computes them, operation by operation.
struct SeedVolumeTerms {
  Real volume = 0;
  std::array<Vector3, 4> g;
  Real sum = 0;
};

SeedVolumeTerms seedVolumeTerms(const std::array<Vector3, 4>& p,
                                const std::array<Real, 4>& inverseMasses) {
  SeedVolumeTerms t;
  t.volume = Real(1.0 / 6.0) * (p[1] - p[0]).cross(p[2] - p[0]).dot(p[3] - p[0]);
  t.g[0] = (p[1] - p[2]).cross(p[3] - p[2]);
  t.g[1] = (p[2] - p[0]).cross(p[3] - p[0]);
  t.g[2] = (p[0] - p[1]).cross(p[3] - p[1]);
  t.g[3] = (p[1] - p[0]).cross(p[2] - p[0]);
  t.sum = inverseMasses[0] * t.g[0].squaredNorm() + inverseMasses[1] * t.g[1].squaredNorm() +
          inverseMasses[2] * t.g[2].squaredNorm() + inverseMasses[3] * t.g[3].squaredNorm();
  return t;
}

}  // namespace

TetVolumeCorrection seedTetVolumePbd(const std::array<Vector3, 4>& p,
                                     const std::array<Real, 4>& inverseMasses, Real restVolume,
                                     Real stiffness, Real cutoff) {
  TetVolumeCorrection c;
  if (stiffness == 0) return c;
  const SeedVolumeTerms t = seedVolumeTerms(p, inverseMasses);
  if (std::abs(t.sum) < cutoff) return c;
  const Real s = stiffness * (t.volume - restVolume) / t.sum;
  for (std::size_t i = 0; i < 4; ++i)
    c.positions[i] = -s * inverseMasses[i] * t.g[i];
  return c;
}

TetVolumeCorrection seedTetVolumeXpbd(const std::array<Vector3, 4>& p,
                                      const std::array<Real, 4>& inverseMasses, Real restVolume,
                                      Real stiffness, Real substepSize, Real multiplier,
                                      Real cutoff) {
  TetVolumeCorrection c;
  if (!(stiffness > 0)) return c;
  const SeedVolumeTerms t = seedVolumeTerms(p, inverseMasses);
  const Real compliance = Real(1) / (stiffness * substepSize * substepSize);  // α̃
  const Real k = t.sum + compliance;
  if (std::abs(k) < cutoff) return c;
  const Real constraint = t.volume - restVolume;
  c.multiplier = -(constraint + compliance * multiplier) / k;
  for (std::size_t i = 0; i < 4; ++i)
    c.positions[i] = c.multiplier * inverseMasses[i] * t.g[i];
  return c;
}

std::vector<TetVolumeConstraint> solidVolumeConstraints(const Scene& scene) {
  std::vector<TetVolumeConstraint> constraints;
  const int method = scene.simulation.solidSimulationMethod;
  if (method != 1 && method != 6) return constraints;
  for (const TetModelDesc& model : scene.tetModels)
    for (const auto& tet : model.mesh.tetrahedra) {
      TetVolumeConstraint c;
      for (std::size_t i = 0; i < 4; ++i)
        c.particles[i] = model.firstParticle + int(tet[i]);
      std::array<Vector3, 4> rest;
      const bool anyDynamic = restPositions(scene, c.particles, rest);
      c.cutoff = femCutoffFor(scene.simulation);
      const bool seedForm = c.cutoff > 0;
      if (!anyDynamic && !seedForm) continue;
      c.restVolume = seedForm ? seedRestTetVolume(rest) : signedTetVolume(rest);
      c.xpbd = method == 6;
      c.stiffness = solidVolumeStiffnessFor(scene.simulation);
      constraints.push_back(c);
    }
  return constraints;
}

void solveTetVolumes(std::vector<TetVolumeConstraint>& constraints, ParticleStates& particles,
                     Real substepSize, bool firstIteration, std::size_t begin, std::size_t end) {
  for (std::size_t k = begin, n = std::min(end, constraints.size()); k < n; ++k) {
    TetVolumeConstraint& c = constraints[k];
    std::array<Vector3, 4> p;
    std::array<Real, 4> w;
    gatherParticles(particles, c.particles, p, w);
    TetVolumeCorrection d;
    if (c.xpbd) {
      if (firstIteration) c.multiplier = 0;
      d = c.cutoff > 0 ? seedTetVolumeXpbd(p, w, c.restVolume, c.stiffness, substepSize,
                                           c.multiplier, c.cutoff)
                       : tetVolumeXpbd(p, w, c.restVolume, c.stiffness, substepSize, c.multiplier);
      c.multiplier += d.multiplier;
    } else {
      d = c.cutoff > 0 ? seedTetVolumePbd(p, w, c.restVolume, c.stiffness, c.cutoff)
                       : tetVolumePbd(p, w, c.restVolume, c.stiffness);
    }
    applyCorrections(particles, c.particles, d.positions);
  }
}

}  // namespace pbd
