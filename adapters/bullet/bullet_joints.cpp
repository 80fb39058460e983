#include "adapters/bullet/bullet_joints.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "pbd/math/quaternion.h"

namespace pbdval::bullet {
namespace {

using pbd::JointType;
using pbd::Matrix3;
using pbd::Vector3;

// btGeneric6DofSpring2Constraint's degrees of freedom: 0–2 linear, 3–5 angular (frame axes).
constexpr int kLinearX = 0;
constexpr int kDofCount = 6;

constexpr const char* kSixDof = "btGeneric6DofSpring2Constraint";
constexpr const char* kHinge = "btHingeConstraint";

/// A frame given in the world at t = 0, expressed in a body's frame.
btTransform inBody(const btRigidBody& body, const btTransform& world) {
  return body.getCenterOfMassTransform().inverse() * world;
}

/// Orthonormal right-handed frame whose z axis is `axis` (Bullet's hinge axis).
Matrix3 frameWithZ(const Vector3& axis) {
  const Matrix3 x = pbd::frameFromAxis(axis);  // columns (axis, s, axis × s)
  Matrix3 frame;
  frame << x.col(1), x.col(2), x.col(0);  // cyclic permutation: still right-handed
  return frame;
}

/// The universal joint's frame: z = axis1 (fixed in A), x = axis2 (fixed in B).
Matrix3 universalFrame(const Vector3& axis1, const Vector3& axis2) {
  Matrix3 frame;
  frame << axis2, axis1.cross(axis2), axis1;
  return frame;
}

using DofLocks = std::array<bool, kDofCount>;

/// A 6-dof constraint with the given degrees of freedom locked (at 0) and the rest free.
std::unique_ptr<btGeneric6DofSpring2Constraint> sixDof(btRigidBody& a, btRigidBody& b,
                                                       const btTransform& world,
                                                       const DofLocks& locked) {
  auto c = std::make_unique<btGeneric6DofSpring2Constraint>(a, b, inBody(a, world),
                                                            inBody(b, world), RO_XYZ);
  for (int dof = 0; dof < kDofCount; ++dof) {
    if (locked[static_cast<std::size_t>(dof)])
      c->setLimit(dof, 0, 0);
    else
      c->setLimit(dof, 1, -1);  // lower > upper: free
  }
  return c;
}

/// The slider family: frame at B's centre of mass (the PBD slider's anchor), x = axis; every
/// degree of freedom but linear x locked.
std::unique_ptr<btGeneric6DofSpring2Constraint> slider(const pbd::JointDesc& joint, btRigidBody& a,
                                                       btRigidBody& b) {
  const btTransform world(toBullet(pbd::frameFromAxis(joint.axis)), b.getCenterOfMassPosition());
  return sixDof(a, b, world, {false, true, true, true, true, true});
}

std::unique_ptr<btHingeConstraint> hinge(const pbd::JointDesc& joint, btRigidBody& a,
                                         btRigidBody& b) {
  const btTransform world = toBullet(frameWithZ(joint.axis), joint.position);
  // useReferenceFrameA = true (Bullet's m_referenceSign = −1): the hinge angle and the motor
  // velocity are B's rotation relative to A about the axis, right-handed, as the Scene's.
  return std::make_unique<btHingeConstraint>(a, b, inBody(a, world), inBody(b, world), true);
}

/// Time-dependent set points: the value at `time`.
double setPoint(const pbd::MotorTarget& target, double time) {
  return double(target.valueAt(pbd::Real(time)));
}

void addAngleMotor(const pbd::JointDesc& joint, btRigidBody& a, btRigidBody& b, JointModel& m) {
  auto c = hinge(joint, a, b);
  c->enableMotor(true);
  c->setMaxMotorImpulse(SIMD_INFINITY);
  btHingeConstraint* raw = c.get();
  m.beforeStep.push_back([raw, target = joint.target](double endTime, double stepSize) {
    // The seed clamps angle targets to [−π, π]; the motor turns the shortest way to it.
    const double angle = std::clamp(setPoint(target, endTime), -SIMD_PI, SIMD_PI);
    const double current = raw->getHingeAngle();
    raw->setMotorTarget(current + btNormalizeAngle(angle - current), stepSize);
  });
  m.constraints.push_back(std::move(c));
}

void addVelocityMotorHinge(const pbd::JointDesc& joint, btRigidBody& a, btRigidBody& b,
                           JointModel& m) {
  auto c = hinge(joint, a, b);
  c->enableAngularMotor(true, setPoint(joint.target, 0), SIMD_INFINITY);
  btHingeConstraint* raw = c.get();
  m.beforeStep.push_back([raw, target = joint.target](double endTime, double) {
    raw->setMotorTargetVelocity(setPoint(target, endTime));
  });
  m.constraints.push_back(std::move(c));
}

void addPositionMotorSlider(const pbd::JointDesc& joint, btRigidBody& a, btRigidBody& b,
                            JointModel& m) {
  auto c = slider(joint, a, b);
  const double start = setPoint(joint.target, 0);
  c->setLimit(kLinearX, start, start);
  c->setParam(BT_CONSTRAINT_STOP_ERP, 1, kLinearX);
  btGeneric6DofSpring2Constraint* raw = c.get();
  m.beforeStep.push_back([raw, target = joint.target](double endTime, double) {
    const double offset = setPoint(target, endTime);
    raw->setLimit(kLinearX, offset, offset);
  });
  m.constraints.push_back(std::move(c));
}

void addVelocityMotorSlider(const pbd::JointDesc& joint, btRigidBody& a, btRigidBody& b,
                            JointModel& m) {
  auto c = slider(joint, a, b);
  c->enableMotor(kLinearX, true);
  c->setMaxMotorForce(kLinearX, SIMD_INFINITY);
  c->setTargetVelocity(kLinearX, kLinearMotorVelocitySign * setPoint(joint.target, 0));
  btGeneric6DofSpring2Constraint* raw = c.get();
  m.beforeStep.push_back([raw, target = joint.target](double endTime, double) {
    raw->setTargetVelocity(kLinearX, kLinearMotorVelocitySign * setPoint(target, endTime));
  });
  m.constraints.push_back(std::move(c));
}

void addDamper(const pbd::JointDesc& joint, btRigidBody& a, btRigidBody& b, JointModel& m) {
  auto c = slider(joint, a, b);
  c->setLimit(kLinearX, 1, -1);
  c->enableSpring(kLinearX, true);
  // limitIfNeeded = false: Bullet would otherwise soften stiff springs on its own.
  c->setStiffness(kLinearX, double(joint.stiffness), false);
  c->setDamping(kLinearX, 0, false);
  c->setEquilibriumPoint(kLinearX, 0);
  m.constraints.push_back(std::move(c));
}

/// A spring between two connectors, applied as forces (F = −k (‖d‖ − L) d/‖d‖ on B).
void addSpringForce(const pbd::JointDesc& joint, btRigidBody& a, btRigidBody& b, JointModel& m) {
  const btVector3 anchorA = a.getCenterOfMassTransform().inverse() * toBullet(joint.position1);
  const btVector3 anchorB = b.getCenterOfMassTransform().inverse() * toBullet(joint.position2);
  const double restLength = double((joint.position2 - joint.position1).norm());
  const double stiffness = double(joint.stiffness);
  m.beforeStep.push_back([&a, &b, anchorA, anchorB, restLength, stiffness](double, double) {
    const btVector3 cA = a.getCenterOfMassTransform() * anchorA;
    const btVector3 cB = b.getCenterOfMassTransform() * anchorB;
    const btVector3 d = cB - cA;
    const double length = d.length();
    if (length == 0) return;  // direction undefined; the force is continuous only for L = 0
    const btVector3 force = -stiffness * (length - restLength) / length * d;
    if (!b.isStaticObject()) b.applyForce(force, cB - b.getCenterOfMassPosition());
    if (!a.isStaticObject()) a.applyForce(-force, cA - a.getCenterOfMassPosition());
  });
}

}  // namespace

// btGeneric6DofSpring2Constraint's motor row asks (v_A − v_B)·axis = target (its Jacobian is
// +axis on A, −axis on B), so B moving along +axis needs a negative target.
const double kLinearMotorVelocitySign = -1;

void addJoint(const pbd::JointDesc& joint, btRigidBody& a, btRigidBody& b, JointModel& m) {
  const char* kind = kSixDof;
  switch (joint.type) {
    case JointType::Ball: {
      const btVector3 point = toBullet(joint.position);
      m.constraints.push_back(std::make_unique<btPoint2PointConstraint>(
          a, b, a.getCenterOfMassTransform().inverse() * point,
          b.getCenterOfMassTransform().inverse() * point));
      kind = "btPoint2PointConstraint";
      break;
    }
    case JointType::BallOnLine:
      m.constraints.push_back(sixDof(a, b, toBullet(pbd::frameFromAxis(joint.axis), joint.position),
                                     {false, true, true, false, false, false}));
      break;
    case JointType::Hinge:
      m.constraints.push_back(hinge(joint, a, b));
      kind = kHinge;
      break;
    case JointType::Universal:
      m.constraints.push_back(
          sixDof(a, b, toBullet(universalFrame(joint.axis1, joint.axis2), joint.position),
                 {true, true, true, false, true, false}));
      break;
    case JointType::Slider:
      m.constraints.push_back(slider(joint, a, b));
      break;
    case JointType::Damper:
      addDamper(joint, a, b, m);
      break;
    case JointType::TargetAngleMotorHinge:
      addAngleMotor(joint, a, b, m);
      kind = kHinge;
      break;
    case JointType::TargetVelocityMotorHinge:
      addVelocityMotorHinge(joint, a, b, m);
      kind = kHinge;
      break;
    case JointType::TargetPositionMotorSlider:
      addPositionMotorSlider(joint, a, b, m);
      break;
    case JointType::TargetVelocityMotorSlider:
      addVelocityMotorSlider(joint, a, b, m);
      break;
    case JointType::RigidBodySpring:
      addSpringForce(joint, a, b, m);
      kind = "force element";
      break;
    default:
      return;  // unsupported(): reported before load
  }
  ++m.kindCounts[std::string(pbd::jointTypeName(joint.type)) + ": " + kind];
}

}  // namespace pbdval::bullet
