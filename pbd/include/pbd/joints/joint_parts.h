// Reusable constraint parts the joints are built from: rows, their Jacobians, and the
// projection of a rigid pair. Every joint file combines these parts; the math of each part is
// stated here once.
//
// Notation: body k has centre of mass x_k and rotation q_k; an anchor c_k = x_k + r_k is
// fixed in body k; a world-frame angular displacement δθ moves c_k by δθ × r_k, so
// ∂c_k/∂θ_k = −[r_k]×.
#pragma once

#include <algorithm>
#include <cmath>

#include "pbd/joints/constraint_rows.h"
#include "pbd/math/quaternion.h"
#include "pbd/model/body_states.h"

namespace pbd {

/// The joint's own constraint error, for tests and diagnostics (the validation suite measures
/// joints independently, from the Scene and the poses).
struct JointError {
  Real linear = 0;   ///< m
  Real angular = 0;  ///< rad
};

namespace joint_parts {

/// Point rows (3): C = c₁ − c₀.  A₀ = −𝟙, B₀ = [r₀]×, A₁ = 𝟙, B₁ = −[r₁]×.
template <int Rows>
void setPointRows(ConstraintRows<Rows>& rows, int row, const Vector3& x0, const Vector3& c0,
                  const Vector3& x1, const Vector3& c1) {
  rows.value.template segment<3>(row) = c1 - c0;
  rows.linear[0].template block<3, 3>(row, 0) = -Matrix3::Identity();
  rows.angular[0].template block<3, 3>(row, 0) = crossMatrix(c0 - x0);
  rows.linear[1].template block<3, 3>(row, 0) = Matrix3::Identity();
  rows.angular[1].template block<3, 3>(row, 0) = -crossMatrix(c1 - x1);
}

/// Axis row (1): C = n·(c₁ − c₀) − offset, with the unit direction n fixed in body 0.
///   A₀ = −nᵀ, B₀ = (n × (c₁ − x₀))ᵀ, A₁ = nᵀ, B₁ = (r₁ × n)ᵀ
/// (B₀ collects both the rotation of n and the motion of c₀ with body 0).
template <int Rows>
void setAxisRow(ConstraintRows<Rows>& rows, int row, const Vector3& n, const Vector3& x0,
                const Vector3& c0, const Vector3& x1, const Vector3& c1, Real offset) {
  rows.value(row) = n.dot(c1 - c0) - offset;
  rows.linear[0].row(row) = -n.transpose();
  rows.angular[0].row(row) = n.cross(c1 - x0).transpose();
  rows.linear[1].row(row) = n.transpose();
  rows.angular[1].row(row) = (c1 - x1).cross(n).transpose();
}

/// Distance row (1): C = ‖c₁ − c₀‖ − L, n = (c₁ − c₀)/‖c₁ − c₀‖.
///   A₀ = −nᵀ, B₀ = −(r₀ × n)ᵀ, A₁ = nᵀ, B₁ = (r₁ × n)ᵀ.
/// Returns false when the connectors coincide (the direction is undefined).
template <int Rows>
bool setDistanceRow(ConstraintRows<Rows>& rows, int row, const Vector3& x0, const Vector3& c0,
                    const Vector3& x1, const Vector3& c1, Real restLength) {
  const Vector3 d = c1 - c0;
  const Real length = d.norm();
  if (!(length > 0)) return false;
  const Vector3 n = d / length;
  rows.value(row) = length - restLength;
  rows.linear[0].row(row) = -n.transpose();
  rows.angular[0].row(row) = -(c0 - x0).cross(n).transpose();
  rows.linear[1].row(row) = n.transpose();
  rows.angular[1].row(row) = (c1 - x1).cross(n).transpose();
  return true;
}

/// Relative rotation error of two joint frames F₀ = q₀ ⊗ qJ₀ and F₁ = q₁ ⊗ qJ₁ (world) against
/// a target relative rotation t (in frame 0): e = t⁻¹ ⊗ F₀⁻¹ ⊗ F₁, sign-fixed so that w ≥ 0.
/// The vector part vec(e) vanishes iff F₁ = F₀ ⊗ t. For a world angular displacement δθ₁ of
/// body 1, δe = ½ [0, R(F₀ t)ᵀ δθ₁] ⊗ e, hence
///   ∂vec(e)/∂θ₁ = ½ (w 𝟙 − [vec e]×) R(F₀ t)ᵀ,   ∂vec(e)/∂θ₀ = −∂vec(e)/∂θ₁.
struct RotationError {
  Quaternion error = Quaternion::Identity();
  Matrix3 jacobianBody1 = Matrix3::Zero();
};

inline RotationError relativeRotationError(const Quaternion& frame0, const Quaternion& frame1,
                                           const Quaternion& target) {
  const Quaternion frame0Target = frame0 * target;
  RotationError result;
  result.error = withPositiveScalar(frame0Target.conjugate() * frame1);
  const Vector3 e = result.error.vec();
  result.jacobianBody1 = Real(0.5) * (result.error.w() * Matrix3::Identity() - crossMatrix(e)) *
                         frame0Target.toRotationMatrix().transpose();
  return result;
}

/// Rotation rows (count): components [first, first + count) of vec(e).
template <int Rows>
void setRotationRows(ConstraintRows<Rows>& rows, int row, const RotationError& rotation,
                     int firstComponent, int count) {
  for (int i = 0; i < count; ++i) {
    const int component = firstComponent + i;
    rows.value(row + i) = rotation.error.vec()(component);
    rows.linear[0].row(row + i).setZero();
    rows.linear[1].row(row + i).setZero();
    rows.angular[1].row(row + i) = rotation.jacobianBody1.row(component);
    rows.angular[0].row(row + i) = -rotation.jacobianBody1.row(component);
  }
}

/// The rotation angle whose half-angle sine is `halfAngleSine` (= ‖selected vec(e)‖).
inline Real angleFromHalfSine(Real halfAngleSine) {
  return Real(2) * std::asin(std::min(Real(1), std::abs(halfAngleSine)));
}

// --- Rigid bodies -------------------------------------------------------------------------

inline EndInverseMass rigidEnd(const RigidBodyStates& bodies, int body) {
  const auto i = static_cast<std::size_t>(body);
  if (!bodies.isDynamic(i)) return {};
  return {bodies.inverseMass[i], bodies.inverseInertiaWorld(i)};
}

inline void applyPositionCorrection(RigidBodyStates& bodies, int body, const Vector3& dx,
                                    const Vector3& dtheta) {
  const auto i = static_cast<std::size_t>(body);
  if (!bodies.isDynamic(i)) return;
  bodies.position[i] += dx;
  addAngularDisplacement(bodies.rotation[i], dtheta);
}

inline void applyVelocityCorrection(RigidBodyStates& bodies, int body, const Vector3& dv,
                                    const Vector3& domega) {
  const auto i = static_cast<std::size_t>(body);
  if (!bodies.isDynamic(i)) return;
  bodies.velocity[i] += dv;
  bodies.angularVelocity[i] += domega;
}

/// One XPBD/PBD projection of a two-body joint: solves K Δλ = −C − α̃ λ and moves both
/// bodies. Returns Δλ (zero when K is singular).
template <int Rows>
Eigen::Matrix<Real, Rows, 1> projectPositions(RigidBodyStates& bodies, int body0, int body1,
                                              const ConstraintRows<Rows>& rows,
                                              const Eigen::Matrix<Real, Rows, 1>& compliance,
                                              const Eigen::Matrix<Real, Rows, 1>& multiplier) {
  const std::array<EndInverseMass, 2> ends{rigidEnd(bodies, body0), rigidEnd(bodies, body1)};
  RowCorrection<Rows> c;
  const Eigen::Matrix<Real, Rows, 1> rhs = -rows.value - compliance.cwiseProduct(multiplier);
  if (!solveRows(rows, ends, compliance, rhs, c)) return Eigen::Matrix<Real, Rows, 1>::Zero();
  applyPositionCorrection(bodies, body0, c.linear[0], c.angular[0]);
  applyPositionCorrection(bodies, body1, c.linear[1], c.angular[1]);
  return c.multiplier;
}

/// Hard projection (all rows rigid).
template <int Rows>
void projectPositions(RigidBodyStates& bodies, int body0, int body1,
                      const ConstraintRows<Rows>& rows) {
  const Eigen::Matrix<Real, Rows, 1> zero = Eigen::Matrix<Real, Rows, 1>::Zero();
  projectPositions(bodies, body0, body1, rows, zero, zero);
}

/// Velocity-level projection: impulses so that J v = targetRate, with J the rows' Jacobians.
template <int Rows>
void projectVelocities(RigidBodyStates& bodies, int body0, int body1,
                       const ConstraintRows<Rows>& rows,
                       const Eigen::Matrix<Real, Rows, 1>& targetRate) {
  const auto i0 = static_cast<std::size_t>(body0);
  const auto i1 = static_cast<std::size_t>(body1);
  const Eigen::Matrix<Real, Rows, 1> rate =
      rows.linear[0] * bodies.velocity[i0] + rows.angular[0] * bodies.angularVelocity[i0] +
      rows.linear[1] * bodies.velocity[i1] + rows.angular[1] * bodies.angularVelocity[i1];
  const std::array<EndInverseMass, 2> ends{rigidEnd(bodies, body0), rigidEnd(bodies, body1)};
  const Eigen::Matrix<Real, Rows, 1> rigid = Eigen::Matrix<Real, Rows, 1>::Zero();
  const Eigen::Matrix<Real, Rows, 1> rhs = targetRate - rate;
  RowCorrection<Rows> c;
  if (!solveRows(rows, ends, rigid, rhs, c)) return;
  applyVelocityCorrection(bodies, body0, c.linear[0], c.angular[0]);
  applyVelocityCorrection(bodies, body1, c.linear[1], c.angular[1]);
}

/// Anchor and frame of a joint stored in each body's principal frame at initialisation.
struct LocalAnchor {
  Vector3 inBody = Vector3::Zero();
  Vector3 world(const RigidBodyStates& bodies, int body) const {
    const auto i = static_cast<std::size_t>(body);
    return bodies.position[i] + bodies.rotation[i] * inBody;
  }
  static LocalAnchor fromWorld(const RigidBodyStates& bodies, int body, const Vector3& point) {
    const auto i = static_cast<std::size_t>(body);
    return {bodies.rotation[i].conjugate() * (point - bodies.position[i])};
  }
};

struct LocalFrame {
  Quaternion inBody = Quaternion::Identity();  ///< joint frame → body principal frame
  Quaternion world(const RigidBodyStates& bodies, int body) const {
    return bodies.rotation[static_cast<std::size_t>(body)] * inBody;
  }
  /// The joint frame with x = `axis` (world), expressed in the body.
  static LocalFrame fromAxis(const RigidBodyStates& bodies, int body, const Vector3& axis) {
    const Quaternion frame(frameFromAxis(axis));
    return {(bodies.rotation[static_cast<std::size_t>(body)].conjugate() * frame).normalized()};
  }
};

}  // namespace joint_parts
}  // namespace pbd
