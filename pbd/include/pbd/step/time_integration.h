// Time integration of the seed (PositionBasedDynamics TimeIntegration), per body.
// All functions leave static bodies and particles (inverse mass 0) untouched.
//
//   semi-implicit Euler:   v ← v + h a,  x ← x + h v
//   rotation:              ω ← ω + h I_w⁻¹ (τ − ω × (I_w ω)),  q ← normalize(q + ½ h [0, ω] ⊗ q)
//                          (explicit gyroscopic term, world inertia at the current rotation;
//                          evaluated in the principal frame, I_w = R diag(I) Rᵀ:
//                          I_w ω = R (I ∘ Rᵀω), I_w⁻¹ u = R (I⁻¹ ∘ Rᵀu), ~90 operations instead of
//                          forming both 3×3 world matrices)
//   velocity update, first order (velocityUpdateMethod 0):
//                          v = (x − x_old)/h,   ω = 2 vec(q ⊗ q_old⁻¹)/h
//   second order (velocityUpdateMethod 1, BDF2; the angular part stays first order, as in
//   the seed):             v = (1.5 x − 2 x_old + 0.5 x_last)/h
// The angular update takes the shorter of q ⊗ q_old⁻¹ and its negative (the seed does not;
// the two differ only for rotations above π per substep).
#pragma once

#include "pbd/math/quaternion.h"

namespace pbd::integration {

inline void semiImplicitEuler(Real h, Real inverseMass, Vector3& position, Vector3& velocity,
                              const Vector3& acceleration) {
  if (inverseMass == 0) return;
  velocity += h * acceleration;
  position += h * velocity;
}

// Inlined into the prediction loop: as a call it cost ~20 of its ~250 instructions per body
// (argument passing; bench/callgrind_step.py on chain_100 with pbd.xpbd).
#if defined(__GNUC__)
__attribute__((always_inline))
#endif
inline void
semiImplicitEulerRotation(Real h, Real inverseMass, const Vector3& inertia,
                          const Vector3& inverseInertia, Quaternion& rotation,
                          Vector3& angularVelocity, const Vector3& torque) {
  if (inverseMass == 0) return;
  const Matrix3 r = rotation.toRotationMatrix();
  const Vector3 angularMomentum = r * inertia.cwiseProduct(r.transpose() * angularVelocity);
  const Vector3 netTorque = torque - angularVelocity.cross(angularMomentum);
  angularVelocity += h * (r * inverseInertia.cwiseProduct(r.transpose() * netTorque));
  addAngularDisplacement(rotation, h * angularVelocity);
}

// The velocity updates take 1/h (and 2/h) computed once per pass by the caller: the seed's
// (1/h) (x − x_old) is a multiplication by the rounded 1/h, and a division per body cost the
// pass ~10 % of its instructions (bench/callgrind_step.py on chain_100).
inline void velocityUpdateFirstOrder(Real inverseStep, Real inverseMass, const Vector3& position,
                                     const Vector3& oldPosition, Vector3& velocity) {
  if (inverseMass == 0) return;
  velocity = inverseStep * (position - oldPosition);
}

inline void velocityUpdateSecondOrder(Real inverseStep, Real inverseMass, const Vector3& position,
                                      const Vector3& oldPosition, const Vector3& lastPosition,
                                      Vector3& velocity) {
  if (inverseMass == 0) return;
  velocity =
      inverseStep * (Real(1.5) * position - Real(2) * oldPosition + Real(0.5) * lastPosition);
}

/// ω = (2/h) vec(q ⊗ q_old⁻¹) with the product's scalar made non-negative; `twoOverStep` = 2/h.
/// The sign is applied to the factor (−v · s = v · (−s) exactly).
inline void angularVelocityUpdateFirstOrder(Real twoOverStep, Real inverseMass,
                                            const Quaternion& rotation,
                                            const Quaternion& oldRotation,
                                            Vector3& angularVelocity) {
  if (inverseMass == 0) return;
  const Quaternion relative = rotation * oldRotation.conjugate();
  angularVelocity = relative.vec() * (relative.w() < Real(0) ? -twoOverStep : twoOverStep);
}

}  // namespace pbd::integration
