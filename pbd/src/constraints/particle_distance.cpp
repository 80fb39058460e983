#include "pbd/constraints/particle_distance.h"

#include <algorithm>
#include <cmath>

#include "pbd/model/body_states.h"
#include "pbd/model/mesh.h"
#include "pbd/model/scene.h"

namespace pbd {

Real particleDistanceValue(const Vector3& p1, const Vector3& p2, Real restLength) {
  return (p1 - p2).norm() - restLength;
}

DistanceCorrection particleDistancePbd(const Vector3& p1, const Vector3& p2, Real inverseMass1,
                                       Real inverseMass2, Real restLength, Real stiffness) {
  // In the seed's operation order (PositionBasedDynamics::solve_DistanceConstraint), so that the
  // two agree bit for bit: n = (p₂ − p₁)/|p₂ − p₁|, c = k n (d − L) / Σw, Δp₁ = w₁ c, Δp₂ = −w₂ c.
  DistanceCorrection c;
  const Real inverseMassSum = inverseMass1 + inverseMass2;
  const Vector3 d = p2 - p1;
  const Real length = d.norm();
  if (!(inverseMassSum > 0) || !(length > 0)) return c;
  const Vector3 n = d / length;
  const Vector3 correction = stiffness * n * (length - restLength) / inverseMassSum;
  c.first = inverseMass1 * correction;
  c.second = -inverseMass2 * correction;
  return c;
}

DistanceCorrection particleDistanceXpbd(const Vector3& p1, const Vector3& p2, Real inverseMass1,
                                        Real inverseMass2, Real restLength, Real stiffness,
                                        Real substepSize, Real multiplier) {
  // In the seed's operation order and with its cut-offs (XPBD::solve_DistanceConstraint): no
  // correction (and λ unchanged) when |p₁ − p₂| ≤ 10⁻⁶ m or Σw + α̃ ≤ 10⁻⁶;
  // Δλ = −(C + α̃ λ) · (1/(Σw + α̃)), Δp₁ = w₁ (n Δλ), Δp₂ = −w₂ (n Δλ).
  DistanceCorrection c;
  const Vector3 d = p1 - p2;
  const Real length = d.norm();
  if (!(length > Real(1e-6)) || !(stiffness > 0)) return c;
  const Vector3 n = d / length;
  const Real compliance = Real(1) / (stiffness * substepSize * substepSize);  // α̃
  const Real k = inverseMass1 + inverseMass2 + compliance;
  if (!(std::abs(k) > Real(1e-6))) return c;
  const Real inverseK = Real(1) / k;
  c.multiplier = -inverseK * ((length - restLength) + compliance * multiplier);
  const Vector3 step = n * c.multiplier;
  c.first = inverseMass1 * step;
  c.second = -inverseMass2 * step;
  return c;
}

namespace {

/// A constraint along every edge of `elements` (triangles or tets of one model), each edge once,
/// in the seed's order (uniqueEdges), between two static particles too: the seed keeps those,
/// and though they move nothing they take their particles in a colour group.
template <std::size_t N>
void addEdges(const std::vector<std::array<int, N>>& elements, int firstParticle,
              const Scene& scene, bool xpbd, Real stiffness,
              std::vector<ParticleDistanceConstraint>& out) {
  for (const std::array<int, 2>& edge : uniqueEdges(elements)) {
    const int a = firstParticle + edge[0];
    const int b = firstParticle + edge[1];
    const ParticleDesc& pa = scene.particles[std::size_t(a)];
    const ParticleDesc& pb = scene.particles[std::size_t(b)];
    ParticleDistanceConstraint c;
    c.particle1 = a;
    c.particle2 = b;
    c.restLength = (pa.position - pb.position).norm();
    c.xpbd = xpbd;
    c.stiffness = stiffness;
    out.push_back(c);
  }
}

}  // namespace

std::vector<ParticleDistanceConstraint> deformableDistanceConstraints(const Scene& scene) {
  std::vector<ParticleDistanceConstraint> constraints;
  const int cloth = scene.simulation.clothSimulationMethod;
  if (cloth == 1 || cloth == 4)
    for (const TriangleModelDesc& model : scene.triangleModels)
      addEdges(model.mesh.triangles, model.firstParticle, scene, cloth == 4,
               clothStiffnessFor(scene.simulation), constraints);
  const int solid = scene.simulation.solidSimulationMethod;
  if (solid == 1 || solid == 6)
    for (const TetModelDesc& model : scene.tetModels)
      addEdges(model.mesh.tetrahedra, model.firstParticle, scene, solid == 6,
               solidStiffnessFor(scene.simulation), constraints);
  return constraints;
}

void solveParticleDistances(std::vector<ParticleDistanceConstraint>& constraints,
                            ParticleStates& particles, Real substepSize, bool firstIteration,
                            std::size_t begin, std::size_t end) {
  for (std::size_t k = begin, n = std::min(end, constraints.size()); k < n; ++k) {
    ParticleDistanceConstraint& c = constraints[k];
    const auto i = std::size_t(c.particle1), j = std::size_t(c.particle2);
    DistanceCorrection d;
    if (c.xpbd) {
      if (firstIteration) c.multiplier = 0;
      d = particleDistanceXpbd(particles.position[i], particles.position[j],
                               particles.inverseMass[i], particles.inverseMass[j], c.restLength,
                               c.stiffness, substepSize, c.multiplier);
      c.multiplier += d.multiplier;
    } else {
      d = particleDistancePbd(particles.position[i], particles.position[j],
                              particles.inverseMass[i], particles.inverseMass[j], c.restLength,
                              c.stiffness);
    }
    particles.position[i] += d.first;
    particles.position[j] += d.second;
  }
}

}  // namespace pbd
