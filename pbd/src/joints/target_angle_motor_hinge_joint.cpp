#include "pbd/joints/target_angle_motor_hinge_joint.h"

#include <algorithm>
#include <cmath>

namespace pbd {

TargetAngleMotorHingeJoint::TargetAngleMotorHingeJoint(const BodyStates& bodies,
                                                       const JointDesc& desc)
    : frames_(
          PointAxisFrames::init(bodies.rigid, desc.body1, desc.body2, desc.position, desc.axis)),
      target_(desc.target),
      model_(desc.model) {
  updateTarget(0);
}

void TargetAngleMotorHingeJoint::updateTarget(Real time) {
  const Real pi = Real(EIGEN_PI);
  angle_ = std::clamp(targetAt(time), -pi, pi);
}

ConstraintRows<TargetAngleMotorHingeJoint::kRows> TargetAngleMotorHingeJoint::positionRows(
    const BodyStates& bodies) const {
  ConstraintRows<kRows> rows;
  frames_.setPointRows(rows, 0, bodies.rigid);
  if (model_ == JointModel::Seed) {
    // The seed's solve_TargetAngleMotorHingeJoint: the hinge's rotation rows vec(e), the one
    // along the axis offset by sin(θ*/2).
    frames_.setRotationRows(rows, 3, bodies.rigid, 0, 3);
    rows.value(3) -= std::sin(Real(0.5) * angle_);
    return rows;
  }
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
