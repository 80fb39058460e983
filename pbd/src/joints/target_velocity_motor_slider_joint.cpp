#include "pbd/joints/target_velocity_motor_slider_joint.h"

namespace pbd {

TargetVelocityMotorSliderJoint::TargetVelocityMotorSliderJoint(const BodyStates& bodies,
                                                               const JointDesc& desc)
    : slider_(bodies, desc), target_(desc.target), model_(desc.model) {
  updateTarget(0);
}

void TargetVelocityMotorSliderJoint::solveVelocity(BodyStates& bodies) {
  const PointAxisFrames& f = slider_.frames();
  ConstraintRows<kVelocityRows> rows;
  f.setAxisRows(rows, 0, bodies.rigid, 0, 3);
  rows.linear[0].block<3, 3>(3, 0).setZero();
  rows.linear[1].block<3, 3>(3, 0).setZero();
  rows.angular[0].block<3, 3>(3, 0) = -Matrix3::Identity();
  rows.angular[1].block<3, 3>(3, 0) = Matrix3::Identity();
  Eigen::Matrix<Real, kVelocityRows, 1> targetRate = Eigen::Matrix<Real, kVelocityRows, 1>::Zero();
  targetRate(0) = velocity_;
  joint_parts::projectVelocities(bodies.rigid, f.body0, f.body1, rows, targetRate);
}

}  // namespace pbd
