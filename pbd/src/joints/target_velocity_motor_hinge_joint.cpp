#include "pbd/joints/target_velocity_motor_hinge_joint.h"

namespace pbd {

TargetVelocityMotorHingeJoint::TargetVelocityMotorHingeJoint(const BodyStates& bodies,
                                                             const JointDesc& desc)
    : hinge_(bodies, desc), target_(desc.target), model_(desc.model) {
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
  if (model_ == JointModel::Seed) {
    // The seed's velocitySolve_TargetVelocityMotorHingeJoint drives the centres of mass'
    // velocity difference v₁ − v₀ to zero with the connector rows' K: the rows' rate is
    // J v = v₁ − v₀ + ω₁ × r₁ − ω₀ × r₀, so the target ω₁ × r₁ − ω₀ × r₀ leaves v₁ − v₀.
    const RigidBodyStates& b = bodies.rigid;
    const auto i0 = std::size_t(f.body0), i1 = std::size_t(f.body1);
    targetRate.segment<3>(0) = b.angularVelocity[i1].cross(f.c1(b) - f.x1(b)) -
                               b.angularVelocity[i0].cross(f.c0(b) - f.x0(b));
  }
  joint_parts::projectVelocities(bodies.rigid, f.body0, f.body1, rows, targetRate);
}

}  // namespace pbd
