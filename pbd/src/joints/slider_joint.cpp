#include "pbd/joints/slider_joint.h"

namespace pbd {

SliderJoint::SliderJoint(const BodyStates& bodies, const JointDesc& desc)
    : frames_(PointAxisFrames::initAtSecondBody(bodies.rigid, desc.body1, desc.body2, desc.axis)) {}

ConstraintRows<SliderJoint::kRows> SliderJoint::positionRows(const BodyStates& bodies) const {
  ConstraintRows<kRows> rows;
  frames_.setAxisRows(rows, 0, bodies.rigid, 1, 2);
  frames_.setRotationRows(rows, 2, bodies.rigid, 0, 3);
  return rows;
}

void SliderJoint::solvePosition(BodyStates& bodies, Real /*substepSize*/) {
  joint_parts::projectPositions(bodies.rigid, frames_.body0, frames_.body1, positionRows(bodies));
}

JointError SliderJoint::error(const BodyStates& bodies) const {
  const auto rows = positionRows(bodies);
  return {rowNorm(rows, 0, 2), joint_parts::angleFromHalfSine(rowNorm(rows, 2, 3))};
}

}  // namespace pbd
