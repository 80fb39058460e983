#include "pbd/joints/target_position_motor_slider_joint.h"

namespace pbd {

TargetPositionMotorSliderJoint::TargetPositionMotorSliderJoint(const BodyStates& bodies,
                                                               const JointDesc& desc)
    : frames_(PointAxisFrames::initAtSecondBody(bodies.rigid, desc.body1, desc.body2, desc.axis)),
      target_(desc.target),
      model_(desc.model),
      initialOffset_(frames_.x0(bodies.rigid) - frames_.x1(bodies.rigid)) {
  updateTarget(0);
}

ConstraintRows<TargetPositionMotorSliderJoint::kRows> TargetPositionMotorSliderJoint::positionRows(
    const BodyStates& bodies) const {
  ConstraintRows<kRows> rows;
  if (model_ == JointModel::Seed) {
    const RigidBodyStates& b = bodies.rigid;
    const Vector3 axis = frames_.worldFrame0(b) * Vector3::UnitX();
    rows.value.head<3>() = frames_.x1(b) - frames_.x0(b) + initialOffset_ - offset_ * axis;
    rows.linear[0].topRows<3>() = -Matrix3::Identity();
    rows.linear[1].topRows<3>() = Matrix3::Identity();
    rows.angular[0].topRows<3>().setZero();
    rows.angular[1].topRows<3>().setZero();
  } else {
    frames_.setAxisRows(rows, 0, bodies.rigid, 0, 3, offset_);
  }
  frames_.setRotationRows(rows, 3, bodies.rigid, 0, 3);
  return rows;
}

void TargetPositionMotorSliderJoint::solvePosition(BodyStates& bodies, Real /*substepSize*/) {
  joint_parts::projectPositions(bodies.rigid, frames_.body0, frames_.body1, positionRows(bodies));
}

JointError TargetPositionMotorSliderJoint::error(const BodyStates& bodies) const {
  const auto rows = positionRows(bodies);
  return {rowNorm(rows, 0, 3), joint_parts::angleFromHalfSine(rowNorm(rows, 3, 3))};
}

}  // namespace pbd
