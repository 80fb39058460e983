#include "pbd/joints/ball_joint.h"

#include "pbd/joints/point_constraint.h"

namespace pbd {

BallJoint::BallJoint(const BodyStates& bodies, const JointDesc& desc)
    : frames_(PointAxisFrames::init(bodies.rigid, desc.body1, desc.body2, desc.position,
                                    Vector3::UnitX())) {}

ConstraintRows<BallJoint::kRows> BallJoint::positionRows(const BodyStates& bodies) const {
  ConstraintRows<kRows> rows;
  frames_.setPointRows(rows, 0, bodies.rigid);
  return rows;
}

void BallJoint::solvePosition(BodyStates& bodies, Real /*substepSize*/) {
  projectPointConstraint(bodies.rigid, frames_.body0, frames_.body1, frames_.anchor0.inBody,
                         frames_.anchor1.inBody);
}

JointError BallJoint::error(const BodyStates& bodies) const {
  return {positionRows(bodies).value.norm(), 0};
}

}  // namespace pbd
