#include "pbd/joints/stretch_bending_twisting_joint.h"

#include <stdexcept>
#include <string>

namespace pbd {
namespace stiff_rod {

Vector3 bendingTwistingStiffness(const StiffRodJointParams& params) {
  const Real r2 = params.averageRadius * params.averageRadius;
  const Real secondMoment = Real(EIGEN_PI) / 4 * r2 * r2;  // I = π r⁴ / 4
  const Real bending = params.youngsModulus * secondMoment;
  const Real twisting = 2 * params.torsionModulus * secondMoment;
  return Vector3(bending, twisting, bending).cwiseProduct(params.stiffnessModifier);
}

Vector6 rowCompliance(const Vector3& stiffness, Real segmentLength, Real substepSize) {
  const Real inverseH2 = Real(1) / (substepSize * substepSize);
  Vector6 alpha;
  alpha.head<3>().setConstant(kStretchRegularisation * inverseH2);
  for (int i = 0; i < 3; ++i)
    alpha(3 + i) = inverseH2 / (stiffness(i) * segmentLength);
  return alpha;
}

void checkParams(const StiffRodJointParams& p, const std::string& jsonPath) {
  const auto require = [&](bool ok, const char* what) {
    if (!ok)
      throw std::invalid_argument("stiff-rod joint " + jsonPath + ": " + what + " must be > 0");
  };
  require(p.youngsModulus > 0, "youngsModulus");
  require(p.torsionModulus > 0, "torsionModulus");
  require(p.averageRadius > 0, "the segments' radius");
  require(p.averageSegmentLength > 0, "the segments' length");
  require((p.stiffnessModifier.array() > 0).all(), "every stiffnessModifier component");
}

}  // namespace stiff_rod

namespace {

joint_parts::LocalFrame sceneFrame(const RigidBodyStates& bodies, int body) {
  return {bodies.principalInScene[static_cast<std::size_t>(body)].conjugate()};
}

}  // namespace

StretchBendingTwistingJoint::StretchBendingTwistingJoint(const BodyStates& bodies,
                                                         const JointDesc& desc)
    : body0_(desc.body1), body1_(desc.body2) {
  stiff_rod::checkParams(desc.stiffRod, desc.jsonPath);
  const RigidBodyStates& b = bodies.rigid;
  anchor0_ = joint_parts::LocalAnchor::fromWorld(b, body0_, desc.position);
  anchor1_ = joint_parts::LocalAnchor::fromWorld(b, body1_, desc.position);
  frame0_ = sceneFrame(b, body0_);
  frame1_ = sceneFrame(b, body1_);
  stiffness_ = stiff_rod::bendingTwistingStiffness(desc.stiffRod);
  segmentLength_ = desc.stiffRod.averageSegmentLength;
  restVector_ = joint_parts::relativeRotationError(frame0_.world(b, body0_),
                                                   frame1_.world(b, body1_), Quaternion::Identity())
                    .error.vec();
}

void StretchBendingTwistingJoint::beginSubstep(Real substepSize) {
  compliance_ = stiff_rod::rowCompliance(stiffness_, segmentLength_, substepSize);
  multiplier_.setZero();
}

ConstraintRows<6> StretchBendingTwistingJoint::positionRows(const BodyStates& bodies) const {
  const RigidBodyStates& b = bodies.rigid;
  ConstraintRows<kRows> rows;
  joint_parts::setPointRows(rows, 0, b.position[static_cast<std::size_t>(body0_)],
                            anchor0_.world(b, body0_), b.position[static_cast<std::size_t>(body1_)],
                            anchor1_.world(b, body1_));
  const auto rotation = joint_parts::relativeRotationError(
      frame0_.world(b, body0_), frame1_.world(b, body1_), Quaternion::Identity());
  const Real scale = 2 / segmentLength_;  // Ω = (2/L) vec(e)
  rows.value.tail<3>() = scale * (rotation.error.vec() - restVector_);
  rows.angular[1].bottomRows<3>() = scale * rotation.jacobianBody1;
  rows.angular[0].bottomRows<3>() = -scale * rotation.jacobianBody1;
  return rows;
}

stiff_rod::Vector6 StretchBendingTwistingJoint::project(
    BodyStates& bodies, const stiff_rod::Vector6& complianceTilde,
    const stiff_rod::Vector6& multiplier) const {
  return joint_parts::projectPositions(bodies.rigid, body0_, body1_, positionRows(bodies),
                                       complianceTilde, multiplier);
}

void StretchBendingTwistingJoint::solvePosition(BodyStates& bodies, Real /*substepSize*/) {
  multiplier_ += project(bodies, compliance_, multiplier_);
}

JointError StretchBendingTwistingJoint::error(const BodyStates& bodies) const {
  const RigidBodyStates& b = bodies.rigid;
  return {(anchor1_.world(b, body1_) - anchor0_.world(b, body0_)).norm(), 0};
}

Real StretchBendingTwistingJoint::elasticEnergy(const BodyStates& bodies) const {
  const Vector3 darboux = positionRows(bodies).value.tail<3>();  // Ω − Ω⁰
  return Real(0.5) * segmentLength_ * darboux.dot(stiffness_.cwiseProduct(darboux));
}

}  // namespace pbd
