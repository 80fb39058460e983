// Two rigid bodies in general position for the point-constraint tests: turned about skew axes,
// with unequal inverse masses and principal inverse inertias (no symmetry hides a wrong arm,
// axis or inertia rotation).
#pragma once

#include "pbd/model/body_states.h"

namespace pbd::test {

/// Body 0 dynamic (inverse mass 1/3) or static (`firstDynamic` false: zero inverse mass and
/// inertia), body 1 dynamic (inverse mass 1/0.7). Velocities and substep-start poses as
/// RigidBodyStates::resize leaves them.
inline RigidBodyStates twoTurnedBodies(bool firstDynamic = true) {
  RigidBodyStates b;
  b.resize(2);
  b.position[0] = Vector3(0.1, -0.2, 0.3);
  b.position[1] = Vector3(0.6, 0.1, -0.2);
  b.rotation[0] = Quaternion(AngleAxis(0.7, Vector3(1, 2, -1).normalized()));
  b.rotation[1] = Quaternion(AngleAxis(-1.9, Vector3(0, 3, 1).normalized()));
  b.inverseMass[0] = firstDynamic ? Real(1) / 3 : 0;
  b.inverseMass[1] = Real(1) / Real(0.7);
  b.inverseInertia[0] = firstDynamic ? Vector3(2.0, 5.0, 11.0) : Vector3::Zero();
  b.inverseInertia[1] = Vector3(13.0, 3.0, 7.0);
  return b;
}

}  // namespace pbd::test
