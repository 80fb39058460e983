#include "pbd/joints/target_velocity_motor_hinge_joint.h"

namespace pbd {

TargetVelocityMotorHingeJoint::TargetVelocityMotorHingeJoint(const BodyStates& bodies,
                                                             const JointDesc& desc)
    : hinge_(bodies, desc), target_(desc.target) {
  updateTarget(0);
}

void TargetVelocityMotorHingeJoint::solveVelocity(BodyStates& bodies) {
  const PointAxisFrames& f = hinge_.frames();
  ConstraintRows<kVelocityRows> rows;
  f.setPointRows(rows, 0, bodies.rigid);
  rows.angular[0].block<3, 3>(3, 0) = -Matrix3::Identity();
  rows.angular[1].block<3, 3>(3, 0) = Matrix3::Identity();
  Eigen::Matrix<Real, kVelocityRows, 1> targetRate = Eigen::Matrix<Real, kVelocityRows, 1>::Zero();
  targetRate.segment<3>(3) = angularVelocity_ * (f.worldFrame0(bodies.rigid) * Vector3::UnitX());
  joint_parts::projectVelocities(bodies.rigid, f.body0, f.body1, rows, targetRate);
}

}  // namespace pbd
