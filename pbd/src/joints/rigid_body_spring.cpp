#include "pbd/joints/rigid_body_spring.h"

namespace pbd {

RigidBodySpring::RigidBodySpring(const BodyStates& bodies, const JointDesc& desc)
    : body0_(desc.body1),
      body1_(desc.body2),
      anchor0_(joint_parts::LocalAnchor::fromWorld(bodies.rigid, desc.body1, desc.position1)),
      anchor1_(joint_parts::LocalAnchor::fromWorld(bodies.rigid, desc.body2, desc.position2)),
      restLength_((desc.position2 - desc.position1).norm()),
      stiffness_(desc.stiffness) {}

void RigidBodySpring::beginSubstep(Real substepSize) {
  compliance_(0) = Real(1) / (stiffness_ * substepSize * substepSize);
  multiplier_.setZero();
}

ConstraintRows<RigidBodySpring::kRows> RigidBodySpring::positionRows(
    const BodyStates& bodies) const {
  const auto& b = bodies.rigid;
  ConstraintRows<kRows> rows;
  joint_parts::setDistanceRow(
      rows, 0, b.position[static_cast<std::size_t>(body0_)], anchor0_.world(b, body0_),
      b.position[static_cast<std::size_t>(body1_)], anchor1_.world(b, body1_), restLength_);
  return rows;
}

void RigidBodySpring::solvePosition(BodyStates& bodies, Real /*substepSize*/) {
  multiplier_ += joint_parts::projectPositions(bodies.rigid, body0_, body1_, positionRows(bodies),
                                               compliance_, multiplier_);
}

JointError RigidBodySpring::error(const BodyStates& /*bodies*/) const {
  return {};
}

}  // namespace pbd
