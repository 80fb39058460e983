// Rigid–rigid contact: a surface point of body 0 inside the tolerance shell of body 1's SDF,
// solved once per step at velocity level (the seed's RigidBodyContactConstraint).
//
//   C = n·(c₀ − c₁) ≥ 0      c₀ the point of body 0, c₁ its closest point on body 1's shell,
//                            n the unit normal out of body 1 (both at detection)
//   ∇C: ∂C/∂x₀ = nᵀ, ∂C/∂θ₀ = (r₀ × n)ᵀ, ∂C/∂x₁ = −nᵀ, ∂C/∂θ₁ = −(r₁ × n)ᵀ, r_k = c_k − x_k
//   Ċ = n·u, u = (v₀ + ω₀ × r₀) − (v₁ + ω₁ × r₁)
// The impulse (normal with restitution and penalty, friction; both models) is
// contact_impulse.h's, with K = K₀ + K₁, K_k = w_k 𝟙 − [r_k]× J_k [r_k]× and
// k_c = contactStiffnessRigidBody. An impulse p changes v₀ by w₀ p and ω₀ by J₀ (r₀ × p), and
// body 1 by the opposite. Positions are not touched (docs/seed.md#rigid-contacts).
// Reference: Bender, Erleben, Trinkle 2014, CGF 33(1), §4; the seed's
// PositionBasedRigidBodyDynamics::velocitySolve_RigidBodyContactConstraint.
#pragma once

#include "pbd/collision/collision_detection.h"
#include "pbd/contacts/contact_impulse.h"
#include "pbd/model/body_states.h"

namespace pbd {

struct RigidBodyContact {
  int body0 = -1, body1 = -1;                                  ///< vertex side, SDF side
  Vector3 lever0 = Vector3::Zero(), lever1 = Vector3::Zero();  ///< r_k
  Real inverseMass0 = 0, inverseMass1 = 0;
  Matrix3 inverseInertia0 = Matrix3::Zero(), inverseInertia1 = Matrix3::Zero();  ///< world
  ContactImpulse impulse;

  /// Sets up the contact from its geometry and the bodies' velocities at detection.
  void init(const ContactPointGeometry& geometry, const RigidBodyStates& bodies,
            const ContactMaterial& material, Real stiffness, const ContactSolveSettings& settings);
  /// One velocity iteration.
  void solveVelocity(RigidBodyStates& bodies, ContactModel model);
  /// Applies +p at c₀ and −p at c₁.
  void applyImpulse(RigidBodyStates& bodies, const Vector3& p) const;
  /// u at the current velocities.
  Vector3 relativeVelocity(const RigidBodyStates& bodies) const;
};

}  // namespace pbd
