#include "pbd/joints/rigid_body_spring.h"

namespace pbd {

RigidBodySpring::RigidBodySpring(const BodyStates& bodies, const JointDesc& desc)
    : connectors_(ConnectorPair::init(bodies.rigid, desc)), stiffness_(desc.stiffness) {}

void RigidBodySpring::beginSubstep(Real substepSize) {
  compliance_(0) = Real(1) / (stiffness_ * substepSize * substepSize);
  multiplier_.setZero();
}

ConstraintRows<RigidBodySpring::kRows> RigidBodySpring::positionRows(
    const BodyStates& bodies) const {
  return connectors_.distanceRow(bodies.rigid);
}

void RigidBodySpring::solvePosition(BodyStates& bodies, Real /*substepSize*/) {
  multiplier_ += joint_parts::projectPositions(bodies.rigid, connectors_.body0, connectors_.body1,
                                               positionRows(bodies), compliance_, multiplier_);
}

JointError RigidBodySpring::error(const BodyStates& /*bodies*/) const {
  return {};
}

}  // namespace pbd
