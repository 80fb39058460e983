#include "pbd/joints/xpbd_joint_damping.h"

#include <algorithm>

namespace pbd {

void dampJoint(RigidBodyStates& b, const JointDampingAnchor& anchor, Real linearDamping,
               Real angularDamping, Real h) {
  if (anchor.body0 < 0 || anchor.body1 < 0) return;
  const auto i0 = static_cast<std::size_t>(anchor.body0);
  const auto i1 = static_cast<std::size_t>(anchor.body1);
  const Matrix3 j0 = b.inverseInertiaWorld(i0), j1 = b.inverseInertiaWorld(i1);
  if (angularDamping > 0) {
    const Vector3 delta =
        (b.angularVelocity[i1] - b.angularVelocity[i0]) * std::min(angularDamping * h, Real(1));
    const Real size = delta.norm();
    if (size > 0) {
      const Vector3 n = delta / size;
      const Real w = n.dot(j0 * n) + n.dot(j1 * n);
      if (w > 0) {
        const Real p = size / w;
        b.angularVelocity[i0] += j0 * (p * n);
        b.angularVelocity[i1] -= j1 * (p * n);
      }
    }
  }
  if (linearDamping > 0) {
    const Vector3 r0 = b.rotation[i0] * anchor.local0, r1 = b.rotation[i1] * anchor.local1;
    const Vector3 v0 = b.velocity[i0] + b.angularVelocity[i0].cross(r0);
    const Vector3 v1 = b.velocity[i1] + b.angularVelocity[i1].cross(r1);
    const Vector3 delta = (v1 - v0) * std::min(linearDamping * h, Real(1));
    const Real size = delta.norm();
    if (size > 0) {
      const Vector3 n = delta / size;
      const Vector3 c0 = r0.cross(n), c1 = r1.cross(n);
      const Real w = b.inverseMass[i0] + c0.dot(j0 * c0) + b.inverseMass[i1] + c1.dot(j1 * c1);
      if (w > 0) {
        const Real p = size / w;
        b.velocity[i0] += b.inverseMass[i0] * p * n;
        b.angularVelocity[i0] += j0 * (p * c0);
        b.velocity[i1] -= b.inverseMass[i1] * p * n;
        b.angularVelocity[i1] -= j1 * (p * c1);
      }
    }
  }
}

}  // namespace pbd
