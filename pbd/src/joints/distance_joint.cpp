#include "pbd/joints/distance_joint.h"

#include <cmath>

namespace pbd {

DistanceJoint::DistanceJoint(const BodyStates& bodies, const JointDesc& desc)
    : connectors_(ConnectorPair::init(bodies.rigid, desc)) {}

ConstraintRows<DistanceJoint::kRows> DistanceJoint::positionRows(const BodyStates& bodies) const {
  return connectors_.distanceRow(bodies.rigid);
}

void DistanceJoint::solvePosition(BodyStates& bodies, Real /*substepSize*/) {
  joint_parts::projectPositions(bodies.rigid, connectors_.body0, connectors_.body1,
                                positionRows(bodies));
}

JointError DistanceJoint::error(const BodyStates& bodies) const {
  return {std::abs(positionRows(bodies).value(0)), 0};
}

}  // namespace pbd
