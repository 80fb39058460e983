#include "pbd/joints/distance_joint.h"

#include <cmath>

namespace pbd {

DistanceJoint::DistanceJoint(const BodyStates& bodies, const JointDesc& desc)
    : body0_(desc.body1),
      body1_(desc.body2),
      anchor0_(joint_parts::LocalAnchor::fromWorld(bodies.rigid, desc.body1, desc.position1)),
      anchor1_(joint_parts::LocalAnchor::fromWorld(bodies.rigid, desc.body2, desc.position2)),
      restLength_((desc.position2 - desc.position1).norm()) {}

ConstraintRows<DistanceJoint::kRows> DistanceJoint::positionRows(const BodyStates& bodies) const {
  const auto& b = bodies.rigid;
  ConstraintRows<kRows> rows;
  joint_parts::setDistanceRow(
      rows, 0, b.position[static_cast<std::size_t>(body0_)], anchor0_.world(b, body0_),
      b.position[static_cast<std::size_t>(body1_)], anchor1_.world(b, body1_), restLength_);
  return rows;
}

void DistanceJoint::solvePosition(BodyStates& bodies, Real /*substepSize*/) {
  joint_parts::projectPositions(bodies.rigid, body0_, body1_, positionRows(bodies));
}

JointError DistanceJoint::error(const BodyStates& bodies) const {
  return {std::abs(positionRows(bodies).value(0)), 0};
}

}  // namespace pbd
