#include "pbd/joints/rigid_body_particle_ball_joint.h"

namespace pbd {

RigidBodyParticleBallJoint::RigidBodyParticleBallJoint(const BodyStates& bodies,
                                                       const JointDesc& desc)
    : body_(desc.body1), particle_(desc.particle) {
  const Vector3 point = bodies.particles.position[static_cast<std::size_t>(particle_)];
  anchor_ = joint_parts::LocalAnchor::fromWorld(bodies.rigid, body_, point);
}

ConstraintRows<RigidBodyParticleBallJoint::kRows> RigidBodyParticleBallJoint::positionRows(
    const BodyStates& bodies) const {
  const Vector3& xp = bodies.particles.position[static_cast<std::size_t>(particle_)];
  ConstraintRows<kRows> rows;
  joint_parts::setPointRows(rows, 0, bodies.rigid.position[static_cast<std::size_t>(body_)],
                            anchor_.world(bodies.rigid, body_), xp, xp);
  return rows;
}

void RigidBodyParticleBallJoint::solvePosition(BodyStates& bodies, Real /*substepSize*/) {
  const auto p = static_cast<std::size_t>(particle_);
  const std::array<EndInverseMass, 2> ends{
      joint_parts::rigidEnd(bodies.rigid, body_),
      EndInverseMass{bodies.particles.inverseMass[p], Matrix3::Zero()}};
  const auto rows = positionRows(bodies);
  RowCorrection<kRows> c;
  if (!solveRows(rows, ends, Vector3::Zero().eval(), Vector3(-rows.value), c)) return;
  joint_parts::applyPositionCorrection(bodies.rigid, body_, c.linear[0], c.angular[0]);
  bodies.particles.position[p] += c.linear[1];
}

JointError RigidBodyParticleBallJoint::error(const BodyStates& bodies) const {
  return {positionRows(bodies).value.norm(), 0};
}

}  // namespace pbd
