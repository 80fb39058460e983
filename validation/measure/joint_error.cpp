#include "validation/measure/joint_error.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "validation/measure/numerics.h"

namespace pbdval {

using pbd::JointType;

namespace {

constexpr double kPi = 3.14159265358979323846;

const BodyState& bodyIn(const State& state, int body) {
  if (body < 0 || static_cast<std::size_t>(body) >= state.bodies.size())
    throw std::invalid_argument("joint metrics: the state has no body at index " +
                                std::to_string(body));
  return state.bodies[static_cast<std::size_t>(body)];
}

const pbd::RigidBodyDesc& sceneBody(const pbd::Scene& scene, int body) {
  if (body < 0 || static_cast<std::size_t>(body) >= scene.rigidBodies.size())
    throw std::invalid_argument("joint metrics: the scene has no body at index " +
                                std::to_string(body));
  return scene.rigidBodies[static_cast<std::size_t>(body)];
}

/// Offset perpendicular to the unit axis a: ‖d − (a·d) a‖.
double perpendicularOffset(const Vector3& d, const Vector3& axis) {
  return (d - axis.dot(d) * axis).norm();
}

/// Tracking of the target-velocity slider: d/dt (a₀·d) − f.
double axialSpeed(const JointGeometry& joint, const State& state, const Vector3& d) {
  const BodyState& b0 = bodyIn(state, joint.anchor0.body);
  const BodyState& b1 = bodyIn(state, joint.anchor1.body);
  const Vector3 a = joint.axis0.world(state);
  const Vector3 anchorVelocity =
      b0.velocity + b0.angularVelocity.cross(joint.anchor0.world(state) - b0.position);
  return b0.angularVelocity.cross(a).dot(d) + a.dot(b1.velocity - anchorVelocity);
}

double motorTracking(const JointGeometry& joint, const State& state, const Vector3& d) {
  const double target = double(joint.target.valueAt(Real(state.time)));
  switch (joint.type) {
    case JointType::TargetAngleMotorHinge: {
      const double angle = twistAngle(relativeRotationChange(joint, state), joint.initialAxis);
      return wrapAngle(angle - std::clamp(target, -kPi, kPi));
    }
    case JointType::TargetVelocityMotorHinge: {
      const BodyState& b0 = bodyIn(state, joint.axis0.body);
      const BodyState& b1 = bodyIn(state, joint.axis1.body);
      return (b1.angularVelocity - b0.angularVelocity).dot(joint.axis0.world(state)) - target;
    }
    case JointType::TargetPositionMotorSlider:
      return joint.axis0.world(state).dot(d) - target;
    case JointType::TargetVelocityMotorSlider:
      return axialSpeed(joint, state, d) - target;
    default:
      return 0;
  }
}

}  // namespace

Vector3 BodyFixedPoint::world(const State& state) const {
  const BodyState& b = bodyIn(state, body);
  return b.position + b.rotation.normalized() * offset;
}

Vector3 BodyFixedDirection::world(const State& state) const {
  return bodyIn(state, body).rotation.normalized() * direction;
}

BodyFixedPoint fixPointInBody(const pbd::Scene& scene, int body, const Vector3& worldPoint) {
  const pbd::RigidBodyDesc& desc = sceneBody(scene, body);
  return {body, desc.rotation.normalized().conjugate() * (worldPoint - desc.initialCenterOfMass())};
}

BodyFixedDirection fixDirectionInBody(const pbd::Scene& scene, int body,
                                      const Vector3& worldDirection) {
  const pbd::RigidBodyDesc& desc = sceneBody(scene, body);
  return {body, desc.rotation.normalized().conjugate() * worldDirection.normalized()};
}

MotorQuantity motorQuantity(JointType type) {
  switch (type) {
    case JointType::TargetAngleMotorHinge:
      return MotorQuantity::Angle;
    case JointType::TargetVelocityMotorHinge:
      return MotorQuantity::AngularVelocity;
    case JointType::TargetPositionMotorSlider:
      return MotorQuantity::Position;
    case JointType::TargetVelocityMotorSlider:
      return MotorQuantity::Velocity;
    default:
      return MotorQuantity::None;
  }
}

const char* motorQuantityName(MotorQuantity quantity) {
  switch (quantity) {
    case MotorQuantity::Angle:
      return "angle";
    case MotorQuantity::AngularVelocity:
      return "angular_velocity";
    case MotorQuantity::Position:
      return "position";
    case MotorQuantity::Velocity:
      return "velocity";
    case MotorQuantity::None:
      break;
  }
  return "";
}

JointShape jointShape(JointType type) {
  switch (type) {
    case JointType::Ball:
      return JointShape::Ball;
    case JointType::RigidBodyParticleBall:
      return JointShape::ParticleBall;
    case JointType::Hinge:
    case JointType::TargetAngleMotorHinge:
    case JointType::TargetVelocityMotorHinge:
      return JointShape::Hinge;
    case JointType::Universal:
      return JointShape::Universal;
    case JointType::Slider:
    case JointType::Damper:
    case JointType::TargetPositionMotorSlider:
    case JointType::TargetVelocityMotorSlider:
      return JointShape::Slider;
    case JointType::BallOnLine:
      return JointShape::BallOnLine;
    case JointType::Distance:
      return JointShape::Distance;
    case JointType::RigidBodySpring:
      return JointShape::Spring;
    case JointType::StiffRod:  // its hard part is the point (zero-stretch) constraint
      return JointShape::Ball;
  }
  return JointShape::Ball;
}

bool isConstraint(JointType type) {
  return jointShape(type) != JointShape::Spring;
}

bool hasAngularError(JointType type) {
  const JointShape shape = jointShape(type);
  return shape == JointShape::Hinge || shape == JointShape::Universal ||
         shape == JointShape::Slider;
}

JointGeometry captureJointGeometry(const pbd::Scene& scene, const pbd::JointDesc& joint) {
  JointGeometry g;
  g.type = joint.type;
  g.jsonPath = joint.jsonPath;
  g.stiffness = double(joint.stiffness);
  g.target = joint.target;
  if (joint.type == JointType::StiffRod) {
    const pbd::StiffRodJointParams& rod = joint.stiffRod;
    const Real r2 = rod.averageRadius * rod.averageRadius;
    const Real secondMoment = Real(EIGEN_PI) / 4 * r2 * r2;
    g.rodStiffness =
        Vector3(rod.youngsModulus * secondMoment, 2 * rod.torsionModulus * secondMoment,
                rod.youngsModulus * secondMoment)
            .cwiseProduct(rod.stiffnessModifier);
    g.rodSegmentLength = double(rod.averageSegmentLength);
  }
  const int body0 = joint.body1, body1 = joint.body2;
  if (body0 < 0 || static_cast<std::size_t>(body0) >= scene.rigidBodies.size())
    throw std::invalid_argument("joint metrics: " + joint.jsonPath + ": unknown first body");
  g.initialRotation0 = scene.rigidBodies[static_cast<std::size_t>(body0)].rotation.normalized();
  g.initialAxis = joint.axis.normalized();
  const JointShape shape = jointShape(joint.type);
  if (shape == JointShape::ParticleBall) {
    if (joint.particle < 0 || static_cast<std::size_t>(joint.particle) >= scene.particles.size())
      throw std::invalid_argument("joint metrics: " + joint.jsonPath + ": unknown particle");
    g.particle = joint.particle;
    g.anchor0 = fixPointInBody(scene, body0, scene.particles[std::size_t(joint.particle)].position);
    return g;
  }
  if (body1 < 0 || static_cast<std::size_t>(body1) >= scene.rigidBodies.size())
    throw std::invalid_argument("joint metrics: " + joint.jsonPath + ": unknown second body");
  g.initialRotation1 = scene.rigidBodies[static_cast<std::size_t>(body1)].rotation.normalized();
  switch (shape) {
    case JointShape::Distance:
    case JointShape::Spring:
      g.anchor0 = fixPointInBody(scene, body0, joint.position1);
      g.anchor1 = fixPointInBody(scene, body1, joint.position2);
      g.restLength = double((joint.position2 - joint.position1).norm());
      break;
    case JointShape::Slider: {
      const Vector3 start =
          scene.rigidBodies[static_cast<std::size_t>(body1)].initialCenterOfMass();
      g.anchor0 = fixPointInBody(scene, body0, start);
      g.anchor1 = fixPointInBody(scene, body1, start);
      g.axis0 = fixDirectionInBody(scene, body0, joint.axis);
      g.axis1 = fixDirectionInBody(scene, body1, joint.axis);
      break;
    }
    case JointShape::Universal:
      g.anchor0 = fixPointInBody(scene, body0, joint.position);
      g.anchor1 = fixPointInBody(scene, body1, joint.position);
      g.axis0 = fixDirectionInBody(scene, body0, joint.axis1);
      g.axis1 = fixDirectionInBody(scene, body1, joint.axis2);
      break;
    default:  // ball, hinge, ball-on-line
      g.anchor0 = fixPointInBody(scene, body0, joint.position);
      g.anchor1 = fixPointInBody(scene, body1, joint.position);
      g.axis0 = fixDirectionInBody(scene, body0, joint.axis);
      g.axis1 = fixDirectionInBody(scene, body1, joint.axis);
      break;
  }
  return g;
}

Quaternion relativeRotationChange(const JointGeometry& joint, const State& state) {
  const Quaternion w0 =
      bodyIn(state, joint.anchor0.body).rotation.normalized() * joint.initialRotation0.conjugate();
  const Quaternion w1 =
      bodyIn(state, joint.anchor1.body).rotation.normalized() * joint.initialRotation1.conjugate();
  return w0.conjugate() * w1;
}

JointMeasurement measureJoint(const JointGeometry& joint, const State& state) {
  JointMeasurement m;
  const Vector3 p0 = joint.anchor0.world(state);
  switch (jointShape(joint.type)) {
    case JointShape::Ball:
      m.linear = (joint.anchor1.world(state) - p0).norm();
      break;
    case JointShape::ParticleBall:
      if (joint.particle < 0 || static_cast<std::size_t>(joint.particle) >= state.particles.size())
        throw std::invalid_argument("joint metrics: " + joint.jsonPath +
                                    ": the state has no particle " +
                                    std::to_string(joint.particle));
      m.linear = (state.particles[std::size_t(joint.particle)].position - p0).norm();
      break;
    case JointShape::Hinge:
      m.linear = (joint.anchor1.world(state) - p0).norm();
      m.angular = angleBetween(joint.axis0.world(state), joint.axis1.world(state));
      break;
    case JointShape::Universal: {
      const Vector3 a0 = joint.axis0.world(state), a1 = joint.axis1.world(state);
      m.linear = (joint.anchor1.world(state) - p0).norm();
      m.angular = std::atan2(std::abs(a0.dot(a1)), a0.cross(a1).norm());
      break;
    }
    case JointShape::Slider: {
      const Vector3 d = joint.anchor1.world(state) - p0;
      const Vector3 axis = joint.axis0.world(state);
      m.linear = perpendicularOffset(d, axis);
      m.angular = rotationAngle(relativeRotationChange(joint, state));
      m.springExtension = axis.dot(d);
      break;
    }
    case JointShape::BallOnLine:
      m.linear = perpendicularOffset(joint.anchor1.world(state) - p0, joint.axis0.world(state));
      break;
    case JointShape::Distance:
      m.linear = std::abs((joint.anchor1.world(state) - p0).norm() - joint.restLength);
      break;
    case JointShape::Spring:
      m.springExtension = (joint.anchor1.world(state) - p0).norm() - joint.restLength;
      break;
  }
  if (motorQuantity(joint.type) != MotorQuantity::None) {
    const Vector3 d = joint.anchor1.world(state) - p0;
    m.tracking = motorTracking(joint, state, d);
  }
  return m;
}

namespace {
Vector3 positiveScalarVector(const Quaternion& q) {
  return q.w() < 0 ? Vector3(-q.vec()) : Vector3(q.vec());
}
}  // namespace

double springPotential(const JointGeometry& joint, const State& state) {
  if (joint.type == JointType::StiffRod) {
    const Quaternion s0 = bodyIn(state, joint.anchor0.body).rotation.normalized();
    const Quaternion s1 = bodyIn(state, joint.anchor1.body).rotation.normalized();
    const double length = joint.rodSegmentLength;
    const Vector3 change =
        (2 / length) *
        (positiveScalarVector(s0.conjugate() * s1) -
         positiveScalarVector(joint.initialRotation0.conjugate() * joint.initialRotation1));
    return 0.5 * length * change.dot(joint.rodStiffness.cwiseProduct(change));
  }
  if (joint.type != JointType::RigidBodySpring && joint.type != JointType::Damper) return 0;
  const double extension = measureJoint(joint, state).springExtension;
  return 0.5 * joint.stiffness * extension * extension;
}

}  // namespace pbdval
