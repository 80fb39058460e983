#include "pbd/joints/target_velocity_motor_slider_joint.h"

#include <Eigen/Cholesky>
#include <cmath>

namespace pbd {
namespace {

/// PositionBasedDynamics' slider frame (init_SliderJoint): x = a, y = a × v, z = a × y, with
/// v = e_x unless |a · e_x| > 0.99, then e_y.
Quaternion seedSliderFrame(const Vector3& axis) {
  Matrix3 frame;
  frame.col(0) = axis.normalized();
  const Vector3 helper =
      std::abs(frame.col(0).x()) > Real(0.99) ? Vector3::UnitY() : Vector3::UnitX();
  frame.col(1) = frame.col(0).cross(helper);
  frame.col(2) = frame.col(0).cross(frame.col(1));
  frame.col(1).normalize();
  frame.col(2).normalize();
  return Quaternion(frame);
}

joint_parts::LocalFrame localFrame(const RigidBodyStates& bodies, int body, const Quaternion& q) {
  return {bodies.rotation[std::size_t(body)].conjugate() * q};
}

}  // namespace

TargetVelocityMotorSliderJoint::TargetVelocityMotorSliderJoint(const BodyStates& bodies,
                                                               const JointDesc& desc)
    : slider_(bodies, desc),
      target_(desc.target),
      model_(desc.model),
      seedFrame0_(localFrame(bodies.rigid, desc.body1, seedSliderFrame(desc.axis))),
      seedFrame1_(localFrame(bodies.rigid, desc.body2, seedSliderFrame(desc.axis))) {
  updateTarget(0);
}

ConstraintRows<TargetVelocityMotorSliderJoint::kRows> TargetVelocityMotorSliderJoint::positionRows(
    const BodyStates& bodies) const {
  ConstraintRows<kRows> rows = slider_.positionRows(bodies);
  if (model_ == JointModel::Seed) {
    // The seed's solve_SliderJoint: Jacobian (±P, 0) for the two linear rows.
    rows.angular[0].topRows<2>().setZero();
    rows.angular[1].topRows<2>().setZero();
  }
  return rows;
}

void TargetVelocityMotorSliderJoint::solvePosition(BodyStates& bodies, Real /*substepSize*/) {
  const PointAxisFrames& f = slider_.frames();
  joint_parts::projectPositions(bodies.rigid, f.body0, f.body1, positionRows(bodies));
}

void TargetVelocityMotorSliderJoint::solveVelocity(BodyStates& bodies) {
  if (model_ == JointModel::Seed) {
    solveVelocitySeed(bodies);
    return;
  }
  const PointAxisFrames& f = slider_.frames();
  ConstraintRows<kVelocityRows> rows;
  f.setAxisRows(rows, 0, bodies.rigid, 0, 3);
  rows.linear[0].block<3, 3>(3, 0).setZero();
  rows.linear[1].block<3, 3>(3, 0).setZero();
  rows.angular[0].block<3, 3>(3, 0) = -Matrix3::Identity();
  rows.angular[1].block<3, 3>(3, 0) = Matrix3::Identity();
  Eigen::Matrix<Real, kVelocityRows, 1> targetRate = Eigen::Matrix<Real, kVelocityRows, 1>::Zero();
  targetRate(0) = velocity_;
  joint_parts::projectVelocities(bodies.rigid, f.body0, f.body1, rows, targetRate);
}

void TargetVelocityMotorSliderJoint::solveVelocitySeed(BodyStates& bodies) {
  RigidBodyStates& b = bodies.rigid;
  const PointAxisFrames& f = slider_.frames();
  const auto i0 = std::size_t(f.body0), i1 = std::size_t(f.body1);
  const EndInverseMass end0 = joint_parts::rigidEnd(b, f.body0);
  const EndInverseMass end1 = joint_parts::rigidEnd(b, f.body1);
  const Quaternion frame0 = seedFrame0_.world(b, f.body0);
  const Vector3 axis = frame0 * Vector3::UnitX();
  Eigen::Matrix<Real, 6, 1> c;
  c.head<3>() = b.velocity[i0] - b.velocity[i1] + velocity_ * axis;
  c.tail<3>() = b.angularVelocity[i0] - b.angularVelocity[i1];
  // t: the Jacobian of vec(F₀⁻¹ F₁) with respect to body 1's rotation in the seed's frames (the
  // seed's −Pr Q(q₀)ᵀ G(q₁) up to its sign, which K does not see).
  const Matrix3 t = joint_parts::relativeRotationError(frame0, seedFrame1_.world(b, f.body1),
                                                       Quaternion::Identity())
                        .jacobianBody1;
  Eigen::Matrix<Real, 6, 6> k = Eigen::Matrix<Real, 6, 6>::Zero();
  k.topLeftCorner<3, 3>() = (end0.linear + end1.linear) * Matrix3::Identity();
  k.bottomRightCorner<3, 3>() = t * (end0.angular + end1.angular) * t.transpose();
  const Eigen::LLT<Eigen::Matrix<Real, 6, 6>> factor(k);
  if (factor.info() != Eigen::Success) return;
  const Eigen::Matrix<Real, 6, 1> lambda = factor.solve(-c);
  if (!lambda.allFinite()) return;
  joint_parts::applyVelocityCorrection(b, f.body0, end0.linear * lambda.head<3>(),
                                       end0.angular * lambda.tail<3>());
  joint_parts::applyVelocityCorrection(b, f.body1, -end1.linear * lambda.head<3>(),
                                       -end1.angular * lambda.tail<3>());
}

}  // namespace pbd
