// Scenes built in code for unit tests (no files): primitive bodies with closed-form mass
// properties, and joints in world coordinates, as the loader would produce them.
#pragma once

#include <initializer_list>
#include <string>

#include "pbd/model/scene.h"

namespace pbd::test {

/// A primitive body without a geometry file (the loader's extension), mass properties from the
/// closed form of its shape.
inline RigidBodyDesc primitiveBody(int id, CollisionObjectType type, const Vector3& scale,
                                   const SolidMoments& moments, const Vector3& position,
                                   Real density, bool dynamic, const Quaternion& rotation) {
  RigidBodyDesc b;
  b.id = id;
  b.jsonPath = "RigidBodies[" + std::to_string(id) + "]";
  b.isDynamic = dynamic;
  b.density = density;
  b.translation = position;
  b.rotation = rotation;
  b.collision.type = type;
  b.collision.scale = scale;
  b.massProperties = toPrincipal(moments);
  return b;
}

inline RigidBodyDesc boxBody(int id, const Vector3& extents, const Vector3& position,
                             Real density = 1, bool dynamic = true,
                             const Quaternion& rotation = Quaternion::Identity()) {
  return primitiveBody(id, CollisionObjectType::Box, extents, boxMoments(extents, density),
                       position, density, dynamic, rotation);
}

inline RigidBodyDesc sphereBody(int id, Real radius, const Vector3& position, Real density = 1,
                                bool dynamic = true) {
  return primitiveBody(id, CollisionObjectType::Sphere, Vector3::Constant(radius),
                       sphereMoments(radius, density), position, density, dynamic,
                       Quaternion::Identity());
}

/// Explicit friction and restitution for the pair of bodies `a` and `b` (indices = ids).
inline ContactPairDesc contactPair(int a, int b, Real friction, Real restitution) {
  ContactPairDesc pair;
  pair.body1 = pair.bodyId1 = a;
  pair.body2 = pair.bodyId2 = b;
  pair.hasFriction = pair.hasRestitution = true;
  pair.friction = friction;
  pair.restitution = restitution;
  return pair;
}

inline JointDesc makeJointDesc(JointType type, int body1, int body2) {
  JointDesc j;
  j.type = type;
  j.jsonPath = std::string(jointBlockName(type)) + "[0]";
  j.bodyId1 = j.body1 = body1;
  j.bodyId2 = j.body2 = body2;
  if (type == JointType::StiffRod) {  // a soft rod (E = 10 MPa, r = 5 cm, L = 0.4 m)
    j.stiffRod.youngsModulus = Real(1e7);
    j.stiffRod.torsionModulus = Real(4e6);
    j.stiffRod.averageRadius = Real(0.05);
    j.stiffRod.averageSegmentLength = Real(0.4);
  }
  return j;
}

/// A static anchor box (index 0) and a dynamic box (index 1) hanging `length` below the
/// joint point `pivot`, displaced sideways by `swing` (so the body moves under gravity).
inline Scene pendulumScene(JointType type, Real substepSize = Real(1e-3)) {
  Scene s;
  s.simulation.timeStepSize = 5 * substepSize;
  s.simulation.subSteps = 5;
  s.simulation.maxIterations = 1;
  s.rigidBodies.push_back(boxBody(0, Vector3(0.2, 0.2, 0.2), Vector3(0, 2, 0), 1, false));
  s.rigidBodies.push_back(boxBody(1, Vector3(0.1, 0.4, 0.1), Vector3(0.6, 1.2, 0), 100));
  JointDesc j = makeJointDesc(type, 0, 1);
  j.position = Vector3(0, 2, 0);
  j.axis = Vector3(0, 0, 1);
  j.axis1 = Vector3(0, 0, 1);
  j.axis2 = Vector3(1, 0, 0);
  s.joints.push_back(j);
  return s;
}

/// Appends a horizontal chain to `s`, whose body 0 (the anchor) is at (0, 2, 0): `links` boxes
/// 0.4 × 0.1 × 0.1 m (density 500) along +x, each joined to the previous one at their common
/// end by a joint of `type` with axis z.
inline void appendChain(Scene& s, int links, JointType type) {
  for (int i = 1; i <= links; ++i) {
    s.rigidBodies.push_back(
        boxBody(i, Vector3(0.4, 0.1, 0.1), Vector3(Real(0.4) * i - Real(0.2), 2, 0), 500));
    JointDesc j = makeJointDesc(type, i - 1, i);
    j.position = Vector3(Real(0.4) * (i - 1), 2, 0);
    j.axis = Vector3::UnitZ();
    s.joints.push_back(j);
  }
}

/// A motor set-point sequence from flat (time, value) pairs.
inline MotorTarget sequence(std::initializer_list<Real> flat) {
  MotorTarget t;
  for (auto it = flat.begin(); it != flat.end(); it += 2) {
    t.times.push_back(*it);
    t.values.push_back(*(it + 1));
  }
  return t;
}

// A static anchor (index 0) at the pivot (0, 2, 0) and a dynamic box (index 1, 0.4 kg) placed
// so that it moves under gravity, for one joint of `type`.
inline Scene singleJointScene(JointType type) {
  Scene s;
  s.simulation.timeStepSize = Real(0.005);
  s.simulation.subSteps = 5;
  const Vector3 pivot(0, 2, 0);
  s.rigidBodies.push_back(boxBody(0, Vector3(0.2, 0.2, 0.2), pivot, 1, false));
  Vector3 bodyPosition(0.6, 1.6, 0);
  JointDesc j = makeJointDesc(type, 0, 1);
  j.position = pivot;
  j.axis = Vector3::UnitZ();
  switch (type) {
    case JointType::Ball:
      bodyPosition = Vector3(0.6, 1.6, 0.3);
      break;
    case JointType::BallOnLine:
      j.axis = Vector3::UnitX();
      bodyPosition = Vector3(0.5, 1.5, 0);
      break;
    case JointType::Universal:
      j.axis1 = Vector3::UnitZ();
      j.axis2 = Vector3::UnitX();
      bodyPosition = Vector3(0.5, 1.5, 0.3);
      break;
    case JointType::Slider:
      j.axis = Vector3(1, -1, 0).normalized();
      break;
    case JointType::RigidBodyParticleBall: {
      ParticleDesc anchor;
      anchor.position = pivot;
      anchor.mass = 0;
      s.particles.push_back(anchor);
      j.body2 = -1;
      j.particle = 0;
      j.body1 = 1;
      break;
    }
    case JointType::Distance:
      j.position1 = pivot;
      j.position2 = bodyPosition + Vector3(0, 0.2, 0);
      break;
    case JointType::Damper:
      j.axis = Vector3::UnitY();
      j.stiffness = 500;
      bodyPosition = Vector3(0, 1.5, 0);
      break;
    case JointType::TargetAngleMotorHinge:
      j.target = sequence({0, 0, 1, 1, 2, -1, 3, 0});
      break;
    case JointType::TargetVelocityMotorHinge:
      j.target = sequence({0, 0, 1, 3, 3, 3});
      break;
    case JointType::TargetPositionMotorSlider:
      j.axis = Vector3::UnitX();
      j.target = sequence({0, 0, 1, 0.5, 2, -0.5, 3, 0});
      break;
    case JointType::TargetVelocityMotorSlider:
      j.axis = Vector3::UnitX();
      j.target = sequence({0, 0, 1, 1, 3, 1});
      break;
    default:
      break;
  }
  RigidBodyDesc body = boxBody(1, Vector3(0.1, 0.4, 0.1), bodyPosition, 100);
  // Velocities that the constraint must project away (off-axis spin, sideways drift).
  body.angularVelocity = Vector3(0.5, 0.2, 0.1);
  body.velocity = Vector3(0, 0, 0.5);
  s.rigidBodies.push_back(body);
  if (type == JointType::RigidBodyParticleBall)
    s.joints.push_back(j);
  else {
    j.body2 = 1;
    s.joints.push_back(j);
  }
  return s;
}

}  // namespace pbd::test
