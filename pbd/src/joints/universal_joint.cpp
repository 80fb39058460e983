#include "pbd/joints/universal_joint.h"

#include <cmath>

namespace pbd {

UniversalJoint::UniversalJoint(const BodyStates& bodies, const JointDesc& desc)
    : frames_(
          PointAxisFrames::init(bodies.rigid, desc.body1, desc.body2, desc.position, desc.axis1)) {
  const auto& b = bodies.rigid;
  axis0InBody_ = b.rotation[static_cast<std::size_t>(desc.body1)].conjugate() * desc.axis1;
  axis1InBody_ = b.rotation[static_cast<std::size_t>(desc.body2)].conjugate() * desc.axis2;
}

ConstraintRows<UniversalJoint::kRows> UniversalJoint::positionRows(const BodyStates& bodies) const {
  const auto& b = bodies.rigid;
  ConstraintRows<kRows> rows;
  frames_.setPointRows(rows, 0, b);
  const Vector3 a0 = b.rotation[static_cast<std::size_t>(frames_.body0)] * axis0InBody_;
  const Vector3 a1 = b.rotation[static_cast<std::size_t>(frames_.body1)] * axis1InBody_;
  const Vector3 u = a0.cross(a1);
  rows.value(3) = a0.dot(a1);
  rows.angular[0].row(3) = u.transpose();
  rows.angular[1].row(3) = -u.transpose();
  return rows;
}

void UniversalJoint::solvePosition(BodyStates& bodies, Real /*substepSize*/) {
  joint_parts::projectPositions(bodies.rigid, frames_.body0, frames_.body1, positionRows(bodies));
}

JointError UniversalJoint::error(const BodyStates& bodies) const {
  const auto rows = positionRows(bodies);
  return {rowNorm(rows, 0, 3), std::asin(std::min(Real(1), std::abs(rows.value(3))))};
}

}  // namespace pbd
