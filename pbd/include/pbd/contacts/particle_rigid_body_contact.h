// Particle–rigid contact: a particle of a triangle or tet model inside the tolerance shell of a
// rigid body's SDF, solved once per step at velocity level (the seed's
// ParticleRigidBodyContactConstraint).
//
//   C = n·(x_p − c₁) ≥ 0     x_p the particle, c₁ its closest point on the body's shell,
//                            n the unit normal out of the body (both at detection)
//   ∇C: ∂C/∂x_p = nᵀ, ∂C/∂x₁ = −nᵀ, ∂C/∂θ₁ = −(r₁ × n)ᵀ, r₁ = c₁ − x₁
//   Ċ = n·u, u = v_p − (v₁ + ω₁ × r₁)
// The impulse is contact_impulse.h's with K = w_p 𝟙 + w₁ 𝟙 − [r₁]× J₁ [r₁]× and
// k_c = contactStiffnessParticleRigidBody (default 100/s). An impulse p changes v_p by w_p p,
// and the body by −w₁ p and −J₁ (r₁ × p).
// Reference: Bender, Erleben, Trinkle 2014, CGF 33(1), §4; the seed's
// PositionBasedRigidBodyDynamics::velocitySolve_ParticleRigidBodyContactConstraint.
#pragma once

#include "pbd/collision/collision_detection.h"
#include "pbd/contacts/contact_impulse.h"
#include "pbd/model/body_states.h"

namespace pbd {

struct ParticleRigidBodyContact {
  int particle = -1, body = -1;
  Vector3 lever = Vector3::Zero();  ///< r₁
  Real particleInverseMass = 0, bodyInverseMass = 0;
  Matrix3 bodyInverseInertia = Matrix3::Zero();  ///< world
  ContactImpulse impulse;

  void init(const ContactPointGeometry& geometry, const BodyStates& bodies,
            const ContactMaterial& material, Real stiffness, const ContactSolveSettings& settings);
  void solveVelocity(BodyStates& bodies, ContactModel model);
  /// Applies +p to the particle and −p at c₁ on the body.
  void applyImpulse(BodyStates& bodies, const Vector3& p) const;
  Vector3 relativeVelocity(const BodyStates& bodies) const;
};

}  // namespace pbd
