#include "pbd/contacts/rigid_body_contact.h"

namespace pbd {
namespace {

void applyEndImpulse(RigidBodyStates& bodies, int body, Real inverseMass,
                     const Matrix3& inverseInertia, const Vector3& lever, const Vector3& impulse) {
  if (!(inverseMass > 0)) return;
  const auto i = static_cast<std::size_t>(body);
  bodies.velocity[i] += inverseMass * impulse;
  bodies.angularVelocity[i] += inverseInertia * lever.cross(impulse);
}

}  // namespace

Vector3 RigidBodyContact::relativeVelocity(const RigidBodyStates& bodies) const {
  const auto i0 = static_cast<std::size_t>(body0), i1 = static_cast<std::size_t>(body1);
  return (bodies.velocity[i0] + bodies.angularVelocity[i0].cross(lever0)) -
         (bodies.velocity[i1] + bodies.angularVelocity[i1].cross(lever1));
}

void RigidBodyContact::init(const ContactPointGeometry& geometry, const RigidBodyStates& bodies,
                            const ContactMaterial& material, Real stiffness,
                            const ContactSolveSettings& settings) {
  body0 = geometry.vertexSide;
  body1 = geometry.sdfBody;
  const auto i0 = static_cast<std::size_t>(body0), i1 = static_cast<std::size_t>(body1);
  lever0 = geometry.vertexPoint - bodies.position[i0];
  lever1 = geometry.surfacePoint - bodies.position[i1];
  inverseMass0 = bodies.inverseMass[i0];
  inverseMass1 = bodies.inverseMass[i1];
  inverseInertia0 = bodies.isDynamic(i0) ? bodies.inverseInertiaWorld(i0) : Matrix3::Zero();
  inverseInertia1 = bodies.isDynamic(i1) ? bodies.inverseInertiaWorld(i1) : Matrix3::Zero();
  const Matrix3 k = pointInverseMass(inverseMass0, inverseInertia0, lever0) +
                    pointInverseMass(inverseMass1, inverseInertia1, lever1);
  // d = n·(c₀ − c₁) from the stored points, as the seed computes it.
  const Real depth = geometry.normal.dot(geometry.vertexPoint - geometry.surfacePoint);
  initContactImpulse(impulse, geometry.normal, k, relativeVelocity(bodies), material,
                     depth < 0 ? -stiffness * depth : Real(0), settings);
}

void RigidBodyContact::applyImpulse(RigidBodyStates& bodies, const Vector3& p) const {
  applyEndImpulse(bodies, body0, inverseMass0, inverseInertia0, lever0, p);
  applyEndImpulse(bodies, body1, inverseMass1, inverseInertia1, lever1, -p);
}

void RigidBodyContact::solveVelocity(RigidBodyStates& bodies, ContactModel model) {
  if (!(inverseMass0 > 0) && !(inverseMass1 > 0)) return;
  applyImpulse(bodies, contactIterationImpulse(impulse, relativeVelocity(bodies), model));
}

}  // namespace pbd
