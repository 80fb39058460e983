#include "pbd/joints/ball_on_line_joint.h"

namespace pbd {

BallOnLineJoint::BallOnLineJoint(const BodyStates& bodies, const JointDesc& desc)
    : frames_(
          PointAxisFrames::init(bodies.rigid, desc.body1, desc.body2, desc.position, desc.axis)) {}

ConstraintRows<BallOnLineJoint::kRows> BallOnLineJoint::positionRows(
    const BodyStates& bodies) const {
  ConstraintRows<kRows> rows;
  frames_.setAxisRows(rows, 0, bodies.rigid, 1, 2);  // the two directions ⟂ the line
  return rows;
}

void BallOnLineJoint::solvePosition(BodyStates& bodies, Real /*substepSize*/) {
  joint_parts::projectPositions(bodies.rigid, frames_.body0, frames_.body1, positionRows(bodies));
}

JointError BallOnLineJoint::error(const BodyStates& bodies) const {
  return {positionRows(bodies).value.norm(), 0};
}

}  // namespace pbd
