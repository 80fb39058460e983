#include "adapters/ode/ode_joints.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pbdval::ode {
namespace {

using pbd::JointType;

bool isMotor(JointType type) {
  return type == JointType::TargetAngleMotorHinge || type == JointType::TargetVelocityMotorHinge ||
         type == JointType::TargetPositionMotorSlider ||
         type == JointType::TargetVelocityMotorSlider;
}

/// The angle in [−π, π] equivalent to `angle`.
double wrapAngle(double angle) {
  return std::remainder(angle, 2 * M_PI);
}

/// ERP and CFM that make a constraint row an implicit spring of stiffness k with damping c over
/// a step h: ERP = h k/(h k + c), CFM = 1/(h k + c) (ODE manual, "Soft constraint and
/// constraint force mixing").
struct SpringRow {
  double erp;
  double cfm;
};
SpringRow springRow(double stiffness, double damping, double stepSize) {
  const double denominator = stepSize * stiffness + damping;
  return {stepSize * stiffness / denominator, 1 / denominator};
}

}  // namespace

OdeJoints::OdeJoints(OdeWorld& world, const pbd::Scene& scene, const OdeSettings& settings)
    : world_(world), scene_(scene), settings_(settings) {
  for (const pbd::JointDesc& joint : scene.joints)
    add(joint);
}

OdeJoints::Ends OdeJoints::endsOf(const pbd::JointDesc& desc) const {
  dBodyID body0 = world_.body(desc.body1);
  dBodyID body1 = world_.body(desc.body2);
  if (body1 != nullptr) return {body1, body0, false};
  return {body0, nullptr, true};
}

void OdeJoints::add(const pbd::JointDesc& desc) {
  if (desc.type == JointType::RigidBodyParticleBall)
    throw EngineError(desc.jsonPath + ": ODE has no particles");
  if (desc.type == JointType::BallOnLine) {
    addBallOnLine(desc);
    return;
  }
  const Ends ends = endsOf(desc);
  if (ends.first == nullptr) return;  // two static bodies: nothing can move
  dWorldID w = world_.id();
  const Vector3& p = desc.position;
  switch (desc.type) {
    case JointType::Ball: {
      dJointID joint = dJointCreateBall(w, nullptr);
      dJointAttach(joint, ends.first, ends.second);
      dJointSetBallAnchor(joint, p.x(), p.y(), p.z());
      break;
    }
    case JointType::Universal: {
      dJointID joint = dJointCreateUniversal(w, nullptr);
      dJointAttach(joint, ends.first, ends.second);
      dJointSetUniversalAnchor(joint, p.x(), p.y(), p.z());
      // ODE fixes axis 1 in its first body: scene body 1 carries `axis2`.
      const Vector3& first = ends.swapped ? desc.axis1 : desc.axis2;
      const Vector3& second = ends.swapped ? desc.axis2 : desc.axis1;
      dJointSetUniversalAxis1(joint, first.x(), first.y(), first.z());
      dJointSetUniversalAxis2(joint, second.x(), second.y(), second.z());
      break;
    }
    case JointType::Distance:
    case JointType::RigidBodySpring:
      addSpring(desc, ends);
      break;
    case JointType::Hinge:
    case JointType::TargetAngleMotorHinge:
    case JointType::TargetVelocityMotorHinge:
      addMotor(desc, addHinge(desc, ends));
      break;
    case JointType::Slider:
    case JointType::Damper:
    case JointType::TargetPositionMotorSlider:
    case JointType::TargetVelocityMotorSlider:
      addMotor(desc, addSlider(desc, ends));
      break;
    case JointType::BallOnLine:
    case JointType::RigidBodyParticleBall:
      break;  // handled above
    case JointType::StiffRod:
      break;  // unsupported: reported before load (OdeEngine::unsupported)
  }
}

// A distance joint holds the connectors' distance with the joint ERP/CFM; a spring makes the
// same row an implicit spring of the scene's stiffness.
void OdeJoints::addSpring(const pbd::JointDesc& desc, const Ends& ends) {
  dJointID joint = dJointCreateDBall(world_.id(), nullptr);
  dJointAttach(joint, ends.first, ends.second);
  const Vector3& onFirst = ends.swapped ? desc.position1 : desc.position2;
  const Vector3& onSecond = ends.swapped ? desc.position2 : desc.position1;
  dJointSetDBallAnchor1(joint, onFirst.x(), onFirst.y(), onFirst.z());
  dJointSetDBallAnchor2(joint, onSecond.x(), onSecond.y(), onSecond.z());
  dJointSetDBallDistance(joint, (desc.position2 - desc.position1).norm());
  SpringRow row{settings_.erp, settings_.cfm};
  if (desc.type == JointType::RigidBodySpring)
    row = springRow(desc.stiffness, 0, scene_.simulation.timeStepSize);
  dJointSetDBallParam(joint, dParamERP, row.erp);
  dJointSetDBallParam(joint, dParamCFM, row.cfm);
}

dJointID OdeJoints::addHinge(const pbd::JointDesc& desc, const Ends& ends) {
  dJointID joint = dJointCreateHinge(world_.id(), nullptr);
  dJointAttach(joint, ends.first, ends.second);
  const Vector3& p = desc.position;
  const Vector3 axis = ends.swapped ? Vector3(-desc.axis) : desc.axis;
  dJointSetHingeAnchor(joint, p.x(), p.y(), p.z());
  dJointSetHingeAxis(joint, axis.x(), axis.y(), axis.z());
  return joint;
}

// The seed's sliders anchor at body 1's centre of mass; ODE's slider holds the initial offset
// perpendicular to the axis wherever it is measured, so no anchor is needed. A damper is a
// slider whose position (0 at the start) is held by a spring: both stops at 0 make the limit row
// bilateral, and the stop ERP/CFM make it a spring of the scene's stiffness.
dJointID OdeJoints::addSlider(const pbd::JointDesc& desc, const Ends& ends) {
  dJointID joint = dJointCreateSlider(world_.id(), nullptr);
  dJointAttach(joint, ends.first, ends.second);
  const Vector3 axis = ends.swapped ? Vector3(-desc.axis) : desc.axis;
  dJointSetSliderAxis(joint, axis.x(), axis.y(), axis.z());
  if (desc.type == JointType::Damper) {
    const SpringRow row = springRow(desc.stiffness, 0, scene_.simulation.timeStepSize);
    dJointSetSliderParam(joint, dParamLoStop, 0);
    dJointSetSliderParam(joint, dParamHiStop, 0);
    dJointSetSliderParam(joint, dParamStopERP, row.erp);
    dJointSetSliderParam(joint, dParamStopCFM, row.cfm);
  }
  return joint;
}

void OdeJoints::addMotor(const pbd::JointDesc& desc, dJointID joint) {
  if (!isMotor(desc.type)) return;
  const bool hinge = desc.type == JointType::TargetAngleMotorHinge ||
                     desc.type == JointType::TargetVelocityMotorHinge;
  if (hinge)
    dJointSetHingeParam(joint, dParamFMax, dInfinity);
  else
    dJointSetSliderParam(joint, dParamFMax, dInfinity);
  motors_.push_back({joint, desc.type, desc.target});
}

/// The velocity of the point `point` fixed in scene body `index` (zero when static).
Vector3 OdeJoints::pointVelocity(int index, const Vector3& point) const {
  const pbd::RigidBodyDesc& body = scene_.rigidBodies[std::size_t(index)];
  if (!body.isDynamic) return Vector3::Zero();
  return body.velocity + body.angularVelocity.cross(point - body.initialCenterOfMass());
}

// The carriage starts at the joint point, slides along the line fixed in body 0 (its rotation
// locked to body 0), and carries body 1 on a ball joint. Its mass and inertia are a fraction of
// the lighter dynamic end's, so it adds that fraction to the motion along the line. It starts
// with the velocity the joint implies: body 0's at the point, plus body 1's anchor velocity
// relative to it along the line.
void OdeJoints::addBallOnLine(const pbd::JointDesc& desc) {
  dBodyID body0 = world_.body(desc.body1);
  dBodyID body1 = world_.body(desc.body2);
  if (body0 == nullptr && body1 == nullptr) return;
  double mass = std::numeric_limits<double>::infinity();
  double inertia = std::numeric_limits<double>::infinity();
  for (const int index : {desc.body1, desc.body2}) {
    const pbd::RigidBodyDesc& body = scene_.rigidBodies[std::size_t(index)];
    if (!body.isDynamic) continue;
    mass = std::min(mass, double(body.massProperties.mass));
    inertia = std::min(inertia, double(body.massProperties.principalInertia.minCoeff()));
  }
  const double ratio = settings_.carriageMassRatio;
  dBodyID carriage = world_.addAuxiliaryBody(ratio * mass, ratio * inertia, desc.position);
  const Vector3 railVelocity = pointVelocity(desc.body1, desc.position);
  const Vector3 velocity =
      railVelocity +
      desc.axis * desc.axis.dot(pointVelocity(desc.body2, desc.position) - railVelocity);
  dBodySetLinearVel(carriage, velocity.x(), velocity.y(), velocity.z());
  const pbd::RigidBodyDesc& rail = scene_.rigidBodies[std::size_t(desc.body1)];
  if (rail.isDynamic)
    dBodySetAngularVel(carriage, rail.angularVelocity.x(), rail.angularVelocity.y(),
                       rail.angularVelocity.z());
  dWorldID w = world_.id();
  dJointID slider = dJointCreateSlider(w, nullptr);
  dJointAttach(slider, carriage, body0);
  dJointSetSliderAxis(slider, desc.axis.x(), desc.axis.y(), desc.axis.z());
  dJointID ball = dJointCreateBall(w, nullptr);
  dJointAttach(ball, carriage, body1);
  dJointSetBallAnchor(ball, desc.position.x(), desc.position.y(), desc.position.z());
}

void OdeJoints::prepareStep(double endTime, double stepSize) {
  for (const MotorDrive& motor : motors_) {
    const double setPoint = motor.target.valueAt(Real(endTime));
    switch (motor.type) {
      case JointType::TargetVelocityMotorHinge:
        dJointSetHingeParam(motor.joint, dParamVel, setPoint);
        break;
      case JointType::TargetVelocityMotorSlider:
        dJointSetSliderParam(motor.joint, dParamVel, setPoint);
        break;
      case JointType::TargetAngleMotorHinge:
        dJointSetHingeParam(motor.joint, dParamVel,
                            wrapAngle(setPoint - dJointGetHingeAngle(motor.joint)) / stepSize);
        break;
      case JointType::TargetPositionMotorSlider:
        dJointSetSliderParam(motor.joint, dParamVel,
                             (setPoint - dJointGetSliderPosition(motor.joint)) / stepSize);
        break;
      default:
        break;
    }
  }
}

}  // namespace pbdval::ode
