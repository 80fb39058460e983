#include "pbd/model/body_states.h"

namespace pbd {

void RigidBodyStates::resize(std::size_t n) {
  position.resize(n, Vector3::Zero());
  rotation.resize(n, Quaternion::Identity());
  velocity.resize(n, Vector3::Zero());
  angularVelocity.resize(n, Vector3::Zero());
  oldPosition.resize(n, Vector3::Zero());
  lastPosition.resize(n, Vector3::Zero());
  oldRotation.resize(n, Quaternion::Identity());
  lastRotation.resize(n, Quaternion::Identity());
  acceleration.resize(n, Vector3::Zero());
  torque.resize(n, Vector3::Zero());
  inverseMass.resize(n, 0);
  inertia.resize(n, Vector3::Ones());
  inverseInertia.resize(n, Vector3::Zero());
  mass.resize(n, 0);
  principalInScene.resize(n, Quaternion::Identity());
  centerOfMassInScene.resize(n, Vector3::Zero());
}

void ParticleStates::resize(std::size_t n) {
  position.resize(n, Vector3::Zero());
  velocity.resize(n, Vector3::Zero());
  oldPosition.resize(n, Vector3::Zero());
  lastPosition.resize(n, Vector3::Zero());
  acceleration.resize(n, Vector3::Zero());
  inverseMass.resize(n, 0);
  mass.resize(n, 0);
}

void SegmentStates::resize(std::size_t n) {
  rotation.resize(n, Quaternion::Identity());
  oldRotation.resize(n, Quaternion::Identity());
  angularVelocity.resize(n, Vector3::Zero());
  torque.resize(n, Vector3::Zero());
  inverseMass.resize(n, 0);
}

}  // namespace pbd
