#include "pbd/joints/damper_joint.h"

namespace pbd {

DamperJoint::DamperJoint(const BodyStates& bodies, const JointDesc& desc)
    : frames_(PointAxisFrames::initAtSecondBody(bodies.rigid, desc.body1, desc.body2, desc.axis)),
      stiffness_(desc.stiffness),
      model_(desc.model) {}

void DamperJoint::beginSubstep(Real substepSize) {
  compliance_.setZero();
  compliance_(0) = Real(1) / (stiffness_ * substepSize * substepSize);
  multiplier_.setZero();
}

ConstraintRows<DamperJoint::kRows> DamperJoint::positionRows(const BodyStates& bodies) const {
  ConstraintRows<kRows> rows;
  frames_.setAxisRows(rows, 0, bodies.rigid, 0, 3);
  if (model_ == JointModel::Seed) {
    // The seed's solve_DamperJoint: the linear rows move the centres of mass only (its
    // Jacobian is (±I, 0) in the joint frame), with no rotational coupling.
    for (std::size_t k = 0; k < 2; ++k)
      rows.angular[k].topRows(3).setZero();
  }
  frames_.setRotationRows(rows, 3, bodies.rigid, 0, 3);
  return rows;
}

void DamperJoint::solvePosition(BodyStates& bodies, Real /*substepSize*/) {
  multiplier_ += joint_parts::projectPositions(bodies.rigid, frames_.body0, frames_.body1,
                                               positionRows(bodies), compliance_, multiplier_);
}

JointError DamperJoint::error(const BodyStates& bodies) const {
  const auto rows = positionRows(bodies);
  return {rowNorm(rows, 1, 2), joint_parts::angleFromHalfSine(rowNorm(rows, 3, 3))};
}

}  // namespace pbd
