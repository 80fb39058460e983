#include "pbd/contacts/xpbd_contact.h"

#include <algorithm>
#include <cmath>

#include "pbd/math/quaternion.h"

namespace pbd {
namespace {

std::size_t at(int index) {
  return static_cast<std::size_t>(index);
}

/// I_w⁻¹ v = R (I⁻¹ ⊙ (Rᵀ v)) with R the principal frame's rotation q: two quaternion
/// rotations (2 × 30 operations) instead of building R diag(I⁻¹) Rᵀ (about 110).
Vector3 inverseInertiaTimes(const RigidBodyStates& b, std::size_t i, const Vector3& v) {
  const Quaternion& q = b.rotation[i];
  return q * Vector3(b.inverseInertia[i].cwiseProduct(q.conjugate() * v));
}

/// m⁻¹ + (r × d)ᵀ I⁻¹ (r × d): the inverse mass of a rigid body at lever r along unit d, with
/// u = Rᵀ (r × d) in the principal frame: m⁻¹ + Σ_k I⁻¹_k u_k².
Real rigidInverseMass(const RigidBodyStates& b, int body, const Vector3& lever,
                      const Vector3& direction) {
  const std::size_t i = at(body);
  if (!b.isDynamic(i)) return 0;
  const Vector3 u = b.rotation[i].conjugate() * lever.cross(direction);
  return b.inverseMass[i] + u.dot(b.inverseInertia[i].cwiseProduct(u));
}

/// A positional impulse P at lever r: x += m⁻¹ P, q ← normalize(q + ½ [0, I⁻¹ (r × P)] ⊗ q).
void applyRigidPositionImpulse(RigidBodyStates& b, int body, const Vector3& lever,
                               const Vector3& impulse) {
  const std::size_t i = at(body);
  if (!b.isDynamic(i)) return;
  const Vector3 angular = inverseInertiaTimes(b, i, lever.cross(impulse));
  b.position[i] += b.inverseMass[i] * impulse;
  addAngularDisplacement(b.rotation[i], angular);
}

void applyRigidVelocityImpulse(RigidBodyStates& b, int body, const Vector3& lever,
                               const Vector3& impulse) {
  const std::size_t i = at(body);
  if (!b.isDynamic(i)) return;
  b.velocity[i] += b.inverseMass[i] * impulse;
  b.angularVelocity[i] += inverseInertiaTimes(b, i, lever.cross(impulse));
}

Vector3 rigidPointVelocity(const RigidBodyStates& b, int body, const Vector3& lever) {
  return b.velocity[at(body)] + b.angularVelocity[at(body)].cross(lever);
}

/// World positions of p₀ and of its anchor p₁, their levers, and n, at the current poses.
struct ContactFrame {
  Vector3 point, surface;            ///< p₀, p₁
  Vector3 pointLever, surfaceLever;  ///< r₀ (zero for a particle), r₁
  Vector3 normal;
};

ContactFrame currentFrame(const XpbdContact& c, const BodyStates& bodies) {
  const RigidBodyStates& b = bodies.rigid;
  ContactFrame f;
  const Quaternion& q1 = b.rotation[at(c.body)];
  f.surfaceLever = q1 * c.surfaceLocal;
  f.surface = b.position[at(c.body)] + f.surfaceLever;
  f.normal = q1 * c.normalLocal;
  if (c.pointIsParticle) {
    f.point = bodies.particles.position[at(c.point)];
    f.pointLever = Vector3::Zero();
  } else {
    f.pointLever = b.rotation[at(c.point)] * c.pointLocal;
    f.point = b.position[at(c.point)] + f.pointLever;
  }
  return f;
}

Real pointInverseMass(const XpbdContact& c, const BodyStates& bodies, const ContactFrame& f,
                      const Vector3& direction) {
  if (c.pointIsParticle) return bodies.particles.inverseMass[at(c.point)];
  return rigidInverseMass(bodies.rigid, c.point, f.pointLever, direction);
}

Real pairInverseMass(const XpbdContact& c, const BodyStates& bodies, const ContactFrame& f,
                     const Vector3& direction) {
  return pointInverseMass(c, bodies, f, direction) +
         rigidInverseMass(bodies.rigid, c.body, f.surfaceLever, direction);
}

/// +P at p₀ on body 0, −P at p₁ on body 1 (positions).
void applyPositionImpulse(const XpbdContact& c, BodyStates& bodies, const ContactFrame& f,
                          const Vector3& impulse) {
  if (c.pointIsParticle)
    bodies.particles.position[at(c.point)] += bodies.particles.inverseMass[at(c.point)] * impulse;
  else
    applyRigidPositionImpulse(bodies.rigid, c.point, f.pointLever, impulse);
  applyRigidPositionImpulse(bodies.rigid, c.body, f.surfaceLever, -impulse);
}

/// +P at p₀ on body 0, −P at p₁ on body 1 (velocities).
void applyVelocityImpulse(const XpbdContact& c, BodyStates& bodies, const ContactFrame& f,
                          const Vector3& impulse) {
  if (c.pointIsParticle)
    bodies.particles.velocity[at(c.point)] += bodies.particles.inverseMass[at(c.point)] * impulse;
  else
    applyRigidVelocityImpulse(bodies.rigid, c.point, f.pointLever, impulse);
  applyRigidVelocityImpulse(bodies.rigid, c.body, f.surfaceLever, -impulse);
}

/// u = (v₀ + ω₀ × r₀) − (v₁ + ω₁ × r₁).
Vector3 relativeVelocity(const XpbdContact& c, const BodyStates& bodies, const ContactFrame& f) {
  const Vector3 u0 = c.pointIsParticle ? bodies.particles.velocity[at(c.point)]
                                       : rigidPointVelocity(bodies.rigid, c.point, f.pointLever);
  return u0 - rigidPointVelocity(bodies.rigid, c.body, f.surfaceLever);
}

/// p₁ ← p₀ − (n·(p₀ − p₁)) n: the anchor moves under the point, keeping the separation.
void reanchor(XpbdContact& c, const BodyStates& bodies, const ContactFrame& f) {
  const Vector3 anchor = f.point - f.normal.dot(f.point - f.surface) * f.normal;
  c.surfaceLocal =
      bodies.rigid.rotation[at(c.body)].conjugate() * (anchor - bodies.rigid.position[at(c.body)]);
}

}  // namespace

void XpbdContact::init(const ContactPointGeometry& geometry, bool particle,
                       const BodyStates& bodies, const ContactMaterial& material,
                       Real contactTolerance) {
  const RigidBodyStates& b = bodies.rigid;
  point = geometry.vertexSide;
  pointIsParticle = particle;
  body = geometry.sdfBody;
  // The detector's surfacePoint lies on the tolerance shell; the body's surface is
  // contactTolerance further in along the normal.
  const Vector3 surface = geometry.surfacePoint - contactTolerance * geometry.normal;
  const Quaternion inverse1 = b.rotation[at(body)].conjugate();
  surfaceLocal = inverse1 * (surface - b.position[at(body)]);
  normalLocal = inverse1 * geometry.normal;
  pointLocal = particle ? Vector3::Zero()
                        : Vector3(b.rotation[at(point)].conjugate() *
                                  (geometry.vertexPoint - b.position[at(point)]));
  friction = material.friction;
  restitution = material.restitution;
  normalMultiplier = 0;
  tangentMultiplier = 0;
  approachVelocity = 0;
}

void XpbdContact::beginSubstep(const BodyStates& bodies) {
  normalMultiplier = 0;
  tangentMultiplier = 0;
  const ContactFrame f = currentFrame(*this, bodies);
  approachVelocity = f.normal.dot(relativeVelocity(*this, bodies, f));
}

void XpbdContact::solvePosition(BodyStates& bodies, Real substepSize, Real compliance) {
  ContactFrame f = currentFrame(*this, bodies);
  const Real c = f.normal.dot(f.point - f.surface);
  if (!(c < 0)) {
    reanchor(*this, bodies, f);  // not touching: the anchor follows the point
    return;
  }
  // Normal row.
  const Real scaledCompliance = compliance / (substepSize * substepSize);  // α̃ = α/h²
  const Real w = pairInverseMass(*this, bodies, f, f.normal);
  if (!(w + scaledCompliance > 0)) return;
  const Real deltaNormal = (-c - scaledCompliance * normalMultiplier) / (w + scaledCompliance);
  normalMultiplier += deltaNormal;
  applyPositionImpulse(*this, bodies, f, deltaNormal * f.normal);

  // Static friction: the tangential offset of p₀ from its anchor p₁, C_t = |d_t|, removed by
  // Δλ_t = C_t / w_t, clamped to the cone μ λ_n; when clamped the point slides and the anchor
  // moves under it.
  f = currentFrame(*this, bodies);
  const Vector3 offset = f.point - f.surface;
  const Vector3 tangential = offset - f.normal.dot(offset) * f.normal;
  const Real slip = tangential.norm();
  if (!(slip > 0)) return;
  const Vector3 direction = tangential / slip;
  const Real wt = pairInverseMass(*this, bodies, f, direction);
  if (!(wt > 0)) return;
  const Real budget = std::max(Real(0), friction * normalMultiplier - tangentMultiplier);
  const Real wanted = slip / wt;
  const Real deltaTangent = std::min(wanted, budget);
  tangentMultiplier += deltaTangent;
  applyPositionImpulse(*this, bodies, f, -deltaTangent * direction);
  if (wanted > budget) reanchor(*this, bodies, currentFrame(*this, bodies));
}

void XpbdContact::solveVelocity(BodyStates& bodies, Real substepSize,
                                Real restitutionThreshold) const {
  if (!(normalMultiplier > 0)) return;
  const ContactFrame f = currentFrame(*this, bodies);
  // Restitution: the normal velocity becomes max(−e ṽ_n, 0), by a normal impulse P_n.
  const Real normalVelocity = f.normal.dot(relativeVelocity(*this, bodies, f));
  const Real e = std::abs(approachVelocity) <= restitutionThreshold ? Real(0) : restitution;
  const Real target = std::max(-e * approachVelocity, Real(0));
  const Real wn = pairInverseMass(*this, bodies, f, f.normal);
  const Real normalImpulse = wn > 0 ? (target - normalVelocity) / wn : Real(0);
  applyVelocityImpulse(*this, bodies, f, normalImpulse * f.normal);

  // Dynamic friction against the sliding velocity, within what the substep's Coulomb bound
  // μ (λ_n/h + P_n) leaves after the static friction impulse λ_t/h.
  const Real budget = (friction * normalMultiplier - tangentMultiplier) / substepSize;
  if (!(budget > 0)) return;
  const Vector3 u = relativeVelocity(*this, bodies, f);
  const Vector3 sliding = u - f.normal.dot(u) * f.normal;
  const Real speed = sliding.norm();
  if (!(speed > 0)) return;
  const Vector3 direction = sliding / speed;
  const Real wt = pairInverseMass(*this, bodies, f, direction);
  if (!(wt > 0)) return;
  applyVelocityImpulse(*this, bodies, f, -std::min(budget, speed / wt) * direction);
}

void XpbdContactSet::reserve(const ContactGeometryBuffer& geometry) {
  contacts.reserve(geometry.rigid.capacity() + geometry.particle.capacity());
}

void XpbdContactSet::initialise(const ContactGeometryBuffer& geometry, const BodyStates& bodies,
                                const ContactMaterials& materials, Real contactTolerance) {
  contacts.resize(geometry.rigid.size() + geometry.particle.size());  // within the capacity
  std::size_t k = 0;
  for (const ContactPointGeometry& g : geometry.rigid)
    contacts[k++].init(g, false, bodies, materials.rigid(g.vertexSide, g.sdfBody),
                       contactTolerance);
  for (const ContactPointGeometry& g : geometry.particle)
    contacts[k++].init(g, true, bodies, materials.particle(g.vertexSide, g.sdfBody),
                       contactTolerance);
}

}  // namespace pbd
