#include "pbd/joints/target_angle_motor_hinge_joint.h"

#include <algorithm>

namespace pbd {

TargetAngleMotorHingeJoint::TargetAngleMotorHingeJoint(const BodyStates& bodies,
                                                       const JointDesc& desc)
    : frames_(
          PointAxisFrames::init(bodies.rigid, desc.body1, desc.body2, desc.position, desc.axis)),
      target_(desc.target) {
  updateTarget(0);
}

void TargetAngleMotorHingeJoint::updateTarget(Real time) {
  const Real pi = Real(EIGEN_PI);
  angle_ = std::clamp(target_.valueAt(time), -pi, pi);
}

ConstraintRows<TargetAngleMotorHingeJoint::kRows> TargetAngleMotorHingeJoint::positionRows(
    const BodyStates& bodies) const {
  ConstraintRows<kRows> rows;
  frames_.setPointRows(rows, 0, bodies.rigid);
  frames_.setRotationRows(rows, 3, bodies.rigid, 0, 3,
                          quaternionFromAxisAngle(Vector3::UnitX(), angle_));
  return rows;
}

void TargetAngleMotorHingeJoint::solvePosition(BodyStates& bodies, Real /*substepSize*/) {
  joint_parts::projectPositions(bodies.rigid, frames_.body0, frames_.body1, positionRows(bodies));
}

JointError TargetAngleMotorHingeJoint::error(const BodyStates& bodies) const {
  const auto rows = positionRows(bodies);
  return {rowNorm(rows, 0, 3), joint_parts::angleFromHalfSine(rowNorm(rows, 3, 3))};
}

}  // namespace pbd
