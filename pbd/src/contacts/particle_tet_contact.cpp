#include "pbd/contacts/particle_tet_contact.h"

#include <algorithm>
#include <cmath>

namespace pbd {
namespace {

/// W = w_p + Σ b_i² w_i.
Real generalisedInverseMass(Real particleInverseMass, const std::array<Real, 4>& tetInverseMasses,
                            const std::array<Real, 4>& weights) {
  Real w = particleInverseMass;
  for (std::size_t i = 0; i < 4; ++i)
    w += weights[i] * weights[i] * tetInverseMasses[i];
  return w;
}

/// Δx_p = w_p s d, Δx_i = −w_i b_i s d.
void distribute(ParticleTetCorrection& c, Real particleInverseMass,
                const std::array<Real, 4>& tetInverseMasses, const std::array<Real, 4>& weights,
                const Vector3& impulse) {
  c.particle = particleInverseMass * impulse;
  for (std::size_t i = 0; i < 4; ++i)
    c.tet[i] = -tetInverseMasses[i] * weights[i] * impulse;
}

}  // namespace

Real particleTetContactValue(const Vector3& particle, const std::array<Vector3, 4>& tet,
                             const std::array<Real, 4>& weights, const Vector3& normal) {
  Vector3 point = Vector3::Zero();
  for (std::size_t i = 0; i < 4; ++i)
    point += weights[i] * tet[i];
  return normal.dot(particle - point);
}

std::array<Vector3, 5> particleTetContactGradients(const std::array<Real, 4>& weights,
                                                   const Vector3& normal) {
  return {normal, -weights[0] * normal, -weights[1] * normal, -weights[2] * normal,
          -weights[3] * normal};
}

ParticleTetCorrection particleTetContactCorrection(
    const Vector3& particle, const std::array<Vector3, 4>& tet, Real particleInverseMass,
    const std::array<Real, 4>& tetInverseMasses, const std::array<Real, 4>& weights,
    const Vector3& normal, Real alphaTilde, Real multiplier, bool unilateral) {
  ParticleTetCorrection c;
  const Real w = generalisedInverseMass(particleInverseMass, tetInverseMasses, weights);
  if (!(w > 0)) return c;
  const Real value = particleTetContactValue(particle, tet, weights, normal);
  Real delta = (-value - alphaTilde * multiplier) / (w + alphaTilde);
  if (unilateral && multiplier + delta < 0) delta = -multiplier;
  if (delta == 0) return c;
  c.multiplier = delta;
  distribute(c, particleInverseMass, tetInverseMasses, weights, delta * normal);
  return c;
}

ParticleTetCorrection particleTetFrictionCorrection(const Vector3& displacement,
                                                    Real particleInverseMass,
                                                    const std::array<Real, 4>& tetInverseMasses,
                                                    const std::array<Real, 4>& weights,
                                                    const Vector3& normal, Real remainingBound) {
  ParticleTetCorrection c;
  const Real w = generalisedInverseMass(particleInverseMass, tetInverseMasses, weights);
  if (!(w > 0) || !(remainingBound > 0)) return c;
  const Vector3 tangential = displacement - normal.dot(displacement) * normal;
  const Real slip = tangential.norm();
  if (!(slip > 0)) return c;
  const Real delta = std::min(slip / w, remainingBound);
  c.multiplier = delta;
  distribute(c, particleInverseMass, tetInverseMasses, weights, -delta / slip * tangential);
  return c;
}

void ParticleTetContactSet::reserve(const TetContactDetector& detector) {
  detector.reserve(geometry);
  contacts.reserve(geometry.contacts.capacity());
}

void ParticleTetContactSet::initialise(const ParticleStates& particles,
                                       const ContactMaterials& materials) {
  contacts.resize(geometry.contacts.size());  // within the reserved capacity: no allocation
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    const ParticleTetContactGeometry& g = geometry.contacts[k];
    ParticleTetContact& c = contacts[k];
    c.particle = g.particle;
    c.vertices = g.vertices;
    c.weights = g.weights;
    c.normal = g.normal;
    for (std::size_t i = 0; i < 4; ++i)
      c.snapshot[i] = particles.position[std::size_t(g.vertices[i])];
    // The material of the tet side: any of its vertices' model (all four are in one model).
    c.friction = materials.particles(g.particle, g.vertices[0]).friction;
    c.normalMultiplier = 0;
    c.tangentMultiplier = 0;
  }
}

void ParticleTetContactSet::beginSubstep() {
  for (ParticleTetContact& c : contacts) {
    c.normalMultiplier = 0;
    c.tangentMultiplier = 0;
  }
}

void ParticleTetContactSet::solvePositions(ParticleStates& particles, ParticleTetSchedule schedule,
                                           Real alphaTilde) {
  const bool seed = schedule == ParticleTetSchedule::Seed;
  for (ParticleTetContact& c : contacts) {
    const auto p = std::size_t(c.particle);
    std::array<Real, 4> tetInverseMasses;
    std::array<Vector3, 4> tet;
    for (std::size_t i = 0; i < 4; ++i) {
      const auto v = std::size_t(c.vertices[i]);
      tetInverseMasses[i] = particles.inverseMass[v];
      tet[i] = seed ? c.snapshot[i] : particles.position[v];
    }
    const Real particleInverseMass = particles.inverseMass[p];
    const ParticleTetCorrection normal = particleTetContactCorrection(
        particles.position[p], tet, particleInverseMass, tetInverseMasses, c.weights, c.normal,
        seed ? Real(0) : alphaTilde, seed ? Real(0) : c.normalMultiplier, !seed);
    c.normalMultiplier = seed ? normal.multiplier : c.normalMultiplier + normal.multiplier;
    particles.position[p] += normal.particle;
    for (std::size_t i = 0; i < 4; ++i)
      particles.position[std::size_t(c.vertices[i])] += normal.tet[i];
    if (seed || !(c.normalMultiplier > 0) || !(c.friction > 0)) continue;
    Vector3 displacement = particles.position[p] - particles.oldPosition[p];
    for (std::size_t i = 0; i < 4; ++i) {
      const auto v = std::size_t(c.vertices[i]);
      displacement -= c.weights[i] * (particles.position[v] - particles.oldPosition[v]);
    }
    const ParticleTetCorrection friction = particleTetFrictionCorrection(
        displacement, particleInverseMass, tetInverseMasses, c.weights, c.normal,
        c.friction * c.normalMultiplier - c.tangentMultiplier);
    c.tangentMultiplier += friction.multiplier;
    particles.position[p] += friction.particle;
    for (std::size_t i = 0; i < 4; ++i)
      particles.position[std::size_t(c.vertices[i])] += friction.tet[i];
  }
}

}  // namespace pbd
