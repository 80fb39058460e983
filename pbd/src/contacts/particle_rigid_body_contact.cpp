#include "pbd/contacts/particle_rigid_body_contact.h"

namespace pbd {

Vector3 ParticleRigidBodyContact::relativeVelocity(const BodyStates& bodies) const {
  const auto b = static_cast<std::size_t>(body);
  return bodies.particles.velocity[std::size_t(particle)] -
         (bodies.rigid.velocity[b] + bodies.rigid.angularVelocity[b].cross(lever));
}

void ParticleRigidBodyContact::init(const ContactPointGeometry& geometry, const BodyStates& bodies,
                                    const ContactMaterial& material, Real stiffness,
                                    const ContactSolveSettings& settings) {
  particle = geometry.vertexSide;
  body = geometry.sdfBody;
  const auto b = static_cast<std::size_t>(body);
  lever = geometry.surfacePoint - bodies.rigid.position[b];
  particleInverseMass = bodies.particles.inverseMass[std::size_t(particle)];
  bodyInverseMass = bodies.rigid.inverseMass[b];
  bodyInverseInertia =
      bodies.rigid.isDynamic(b) ? bodies.rigid.inverseInertiaWorld(b) : Matrix3::Zero();
  const Matrix3 k = particleInverseMass * Matrix3::Identity() +
                    pointInverseMass(bodyInverseMass, bodyInverseInertia, lever);
  const Real depth = geometry.normal.dot(geometry.vertexPoint - geometry.surfacePoint);
  initContactImpulse(impulse, geometry.normal, k, relativeVelocity(bodies), material,
                     depth < 0 ? -stiffness * depth : Real(0), settings);
}

void ParticleRigidBodyContact::applyImpulse(BodyStates& bodies, const Vector3& p) const {
  if (particleInverseMass > 0)
    bodies.particles.velocity[std::size_t(particle)] += particleInverseMass * p;
  if (bodyInverseMass > 0) {
    const auto b = static_cast<std::size_t>(body);
    bodies.rigid.velocity[b] -= bodyInverseMass * p;
    bodies.rigid.angularVelocity[b] -= bodyInverseInertia * lever.cross(p);
  }
}

void ParticleRigidBodyContact::solveVelocity(BodyStates& bodies, ContactModel model) {
  if (!(particleInverseMass > 0) && !(bodyInverseMass > 0)) return;
  applyImpulse(bodies, contactIterationImpulse(impulse, relativeVelocity(bodies), model));
}

}  // namespace pbd
