// Conversions between the Scene's Eigen types and Bullet's, and the precision check.
//
// Bullet stores quaternions as (x, y, z, w) and Eigen's constructor takes (w, x, y, z); every
// conversion goes through these functions so the order is written once.
#pragma once

#include <btBulletDynamicsCommon.h>

#include "pbd/math/types.h"

// Debian's bullet-float64 build; pkg-config supplies -DBT_USE_DOUBLE_PRECISION. Headers and
// libraries of different precision would link (pointer-only APIs) with a broken layout.
static_assert(sizeof(btScalar) == 8, "pbdval needs Bullet's double-precision build");

namespace pbdval::bullet {

inline btVector3 toBullet(const pbd::Vector3& v) {
  return btVector3(v.x(), v.y(), v.z());
}

inline pbd::Vector3 toEigen(const btVector3& v) {
  return pbd::Vector3(v.x(), v.y(), v.z());
}

inline btQuaternion toBullet(const pbd::Quaternion& q) {
  return btQuaternion(q.x(), q.y(), q.z(), q.w());
}

inline pbd::Quaternion toEigen(const btQuaternion& q) {
  return pbd::Quaternion(q.w(), q.x(), q.y(), q.z());
}

inline btMatrix3x3 toBullet(const pbd::Matrix3& m) {
  return btMatrix3x3(m(0, 0), m(0, 1), m(0, 2), m(1, 0), m(1, 1), m(1, 2), m(2, 0), m(2, 1),
                     m(2, 2));
}

inline btTransform toBullet(const pbd::Quaternion& rotation, const pbd::Vector3& origin) {
  return btTransform(toBullet(rotation), toBullet(origin));
}

inline btTransform toBullet(const pbd::Matrix3& basis, const pbd::Vector3& origin) {
  return btTransform(toBullet(basis), toBullet(origin));
}

/// True when `t` is exactly the identity (no round-off allowed: it decides whether a shape
/// needs a compound wrapper).
inline bool isExactIdentity(const btTransform& t) {
  const btMatrix3x3& b = t.getBasis();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (b[i][j] != (i == j ? 1.0 : 0.0)) return false;
  return t.getOrigin() == btVector3(0, 0, 0);
}

}  // namespace pbdval::bullet
