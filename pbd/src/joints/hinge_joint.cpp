#include "pbd/joints/hinge_joint.h"

namespace pbd {

HingeJoint::HingeJoint(const BodyStates& bodies, const JointDesc& desc)
    : frames_(
          PointAxisFrames::init(bodies.rigid, desc.body1, desc.body2, desc.position, desc.axis)) {}

ConstraintRows<HingeJoint::kRows> HingeJoint::positionRows(const BodyStates& bodies) const {
  ConstraintRows<kRows> rows;
  frames_.setPointRows(rows, 0, bodies.rigid);
  frames_.setRotationRows(rows, 3, bodies.rigid, 1, 2);
  return rows;
}

void HingeJoint::solvePosition(BodyStates& bodies, Real /*substepSize*/) {
  joint_parts::projectPositions(bodies.rigid, frames_.body0, frames_.body1, positionRows(bodies));
}

JointError HingeJoint::error(const BodyStates& bodies) const {
  const auto rows = positionRows(bodies);
  return {rowNorm(rows, 0, 3), joint_parts::angleFromHalfSine(rowNorm(rows, 3, 2))};
}

}  // namespace pbd
