#include "pbd/constraints/particle_distance.h"

#include <algorithm>

#include "pbd/model/body_states.h"
#include "pbd/model/mesh.h"
#include "pbd/model/scene.h"

namespace pbd {

Real particleDistanceValue(const Vector3& p1, const Vector3& p2, Real restLength) {
  return (p1 - p2).norm() - restLength;
}

DistanceCorrection particleDistancePbd(const Vector3& p1, const Vector3& p2, Real inverseMass1,
                                       Real inverseMass2, Real restLength, Real stiffness) {
  DistanceCorrection c;
  const Real inverseMassSum = inverseMass1 + inverseMass2;
  const Vector3 d = p1 - p2;
  const Real length = d.norm();
  if (!(inverseMassSum > 0) || !(length > 0)) return c;
  const Vector3 n = d / length;
  const Real s = (length - restLength) / inverseMassSum;
  c.first = -stiffness * inverseMass1 * s * n;
  c.second = stiffness * inverseMass2 * s * n;
  return c;
}

DistanceCorrection particleDistanceXpbd(const Vector3& p1, const Vector3& p2, Real inverseMass1,
                                        Real inverseMass2, Real restLength, Real stiffness,
                                        Real substepSize, Real multiplier) {
  DistanceCorrection c;
  const Real inverseMassSum = inverseMass1 + inverseMass2;
  const Vector3 d = p1 - p2;
  const Real length = d.norm();
  if (!(inverseMassSum > 0) || !(length > 0) || !(stiffness > 0)) return c;
  const Vector3 n = d / length;
  const Real compliance = Real(1) / (stiffness * substepSize * substepSize);  // α̃
  c.multiplier = (-(length - restLength) - compliance * multiplier) / (inverseMassSum + compliance);
  c.first = inverseMass1 * c.multiplier * n;
  c.second = -inverseMass2 * c.multiplier * n;
  return c;
}

namespace {

/// A constraint along every edge of `elements` (triangles or tets of one model), each edge once,
/// in the order it first appears (uniqueEdges); none between two static particles.
template <std::size_t N>
void addEdges(const std::vector<std::array<int, N>>& elements, int firstParticle,
              const Scene& scene, bool xpbd, Real stiffness,
              std::vector<ParticleDistanceConstraint>& out) {
  for (const std::array<int, 2>& edge : uniqueEdges(elements)) {
    const int a = firstParticle + edge[0];
    const int b = firstParticle + edge[1];
    const ParticleDesc& pa = scene.particles[std::size_t(a)];
    const ParticleDesc& pb = scene.particles[std::size_t(b)];
    if (!(pa.mass > 0) && !(pb.mass > 0)) continue;
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
