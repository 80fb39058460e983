// Small quaternion and cross-product helpers shared by integration and joints.
//
// Conventions: quaternions are unit, Hamilton product, q rotates body vectors into world.
// An angular displacement dθ (world frame) updates an orientation to first order by
//   q ← normalize(q + ½ [0, dθ] ⊗ q)            (Deul, Charrier, Bender 2014, eq. 7)
#pragma once

#include <cmath>

#include "pbd/math/types.h"

namespace pbd {

/// [v]× such that [v]× w = v × w.
inline Matrix3 crossMatrix(const Vector3& v) {
  Matrix3 m;
  m << Real(0), -v.z(), v.y(),  //
      v.z(), Real(0), -v.x(),   //
      -v.y(), v.x(), Real(0);
  return m;
}

/// The pure quaternion [0, v].
inline Quaternion pureQuaternion(const Vector3& v) {
  return Quaternion(Real(0), v.x(), v.y(), v.z());
}

/// q ← normalize(q + ½ [0, dθ] ⊗ q): the first-order rotation update used by the seed for
/// both integration and position corrections.
inline void addAngularDisplacement(Quaternion& q, const Vector3& angularDisplacement) {
  const Quaternion dq = pureQuaternion(angularDisplacement) * q;
  q.coeffs() += Real(0.5) * dq.coeffs();
  q.normalize();
}

/// R v for the unit quaternion q: Eigen's `q * v` (QuaternionBase::_transformVector,
/// v + 2 w (q_v × v) + q_v × (2 q_v × v), 30 operations) written out so that it is inlined where
/// GCC keeps Eigen's as a call (the XPBD contact rows: 16 % of a box pile's step time). The same
/// operations in the same order: bitwise Eigen's result (tests/pbd/test_integration.cpp).
#if defined(__GNUC__)
__attribute__((always_inline))
#endif
inline Vector3
rotateVector(const Quaternion& q, const Vector3& v) {
  Vector3 twiceCross = q.vec().cross(v);
  twiceCross += twiceCross;
  return v + q.w() * twiceCross + q.vec().cross(twiceCross);
}

/// Rᵀ v: Eigen's `q.conjugate() * v` (the vector part negated, exactly), inlined likewise.
#if defined(__GNUC__)
__attribute__((always_inline))
#endif
inline Vector3
rotateVectorInverse(const Quaternion& q, const Vector3& v) {
  const Vector3 axis = -q.vec();
  Vector3 twiceCross = axis.cross(v);
  twiceCross += twiceCross;
  return v + q.w() * twiceCross + axis.cross(twiceCross);
}

/// Rotation by `angle` (radians) about the unit vector `axis`.
inline Quaternion quaternionFromAxisAngle(const Vector3& axis, Real angle) {
  return Quaternion(AngleAxis(angle, axis));
}

/// Geodesic angle between two orientations, in [0, π]; q and −q are the same orientation.
inline Real rotationAngleBetween(const Quaternion& a, const Quaternion& b) {
  const Real dot = std::abs(a.coeffs().dot(b.coeffs()));
  return Real(2) * std::acos(std::min(Real(1), dot));
}

/// Returns q or −q, whichever has a non-negative scalar part.
inline Quaternion withPositiveScalar(const Quaternion& q) {
  return q.w() < Real(0) ? Quaternion(-q.coeffs()) : q;
}

/// Orthonormal frame whose first column is the unit vector `axis`. The second column is
/// axis × e_y normalised, or axis × e_x when `axis` is close to e_y (|axis·e_y| > 0.99, the
/// seed's threshold); the third completes a right-handed frame.
inline Matrix3 frameFromAxis(const Vector3& axis) {
  const Vector3 helper = std::abs(axis.y()) > Real(0.99) ? Vector3::UnitX() : Vector3::UnitY();
  const Vector3 second = axis.cross(helper).normalized();
  Matrix3 frame;
  frame.col(0) = axis;
  frame.col(1) = second;
  frame.col(2) = axis.cross(second);
  return frame;
}

}  // namespace pbd
