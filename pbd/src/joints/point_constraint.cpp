#include "pbd/joints/point_constraint.h"

#include "pbd/joints/constraint_rows.h"

namespace pbd {
namespace {

// The helpers are inlined into the solve (a call each cost a copy of PointEnd and ~15 % of the
// solve's instructions, measured by bench/callgrind_harness.py).
#if defined(__GNUC__)
#define PBD_INLINE inline __attribute__((always_inline))
#else
#define PBD_INLINE inline
#endif

/// One end of the constraint at the pose its directions are taken at (the current pose, or
/// the substep's start).
struct PointEnd {
  Matrix3 rotation;        // R_k
  Vector3 arm;             // r_k = R_k a_k
  Matrix3 armRotation;     // S_k = [r_k]× R_k
  Vector3 inverseInertia;  // D_k (zero for a static end)
  Real inverseMass = 0;    // w_k
  bool dynamic = false;
};

/// [r]× R: column c is r × R.col(c).
PBD_INLINE void setCrossTimesRotation(const Vector3& r, const Matrix3& rotation, Matrix3& out) {
  for (int c = 0; c < 3; ++c) {
    const Vector3 column = rotation.col(c);
    out(0, c) = r.y() * column.z() - r.z() * column.y();
    out(1, c) = r.z() * column.x() - r.x() * column.z();
    out(2, c) = r.x() * column.y() - r.y() * column.x();
  }
}

/// Body `body`'s end with rotation `rotation` (its current one, or its substep-start one).
PBD_INLINE PointEnd pointEnd(const RigidBodyStates& bodies, int body, const Quaternion& rotation,
                             const Vector3& anchor) {
  const auto i = static_cast<std::size_t>(body);
  PointEnd end;
  end.rotation = rotation.toRotationMatrix();
  end.arm.noalias() = end.rotation * anchor;
  end.dynamic = bodies.isDynamic(i);
  if (!end.dynamic) return end;
  end.inverseMass = bodies.inverseMass[i];
  end.inverseInertia = bodies.inverseInertia[i];
  setCrossTimesRotation(end.arm, end.rotation, end.armRotation);
  return end;
}

/// k += S D Sᵀ (the upper triangle and diagonal; k is symmetric).
PBD_INLINE void addArmTerm(const PointEnd& end, Matrix3& k) {
  const Matrix3& s = end.armRotation;
  Matrix3 sd;
  for (int c = 0; c < 3; ++c)
    sd.col(c) = s.col(c) * end.inverseInertia(c);
  for (int row = 0; row < 3; ++row)
    for (int column = row; column < 3; ++column)
      k(row, column) += sd.row(row).dot(s.row(column));
}

/// k += T D Sᵀ with T = [r_now]× R (every entry: k is not symmetric), the mixed term of SHAKE's
/// Newton step: −[r_now]× J [r]× with J = R D Rᵀ and r, R those of `end`.
PBD_INLINE void addMixedArmTerm(const PointEnd& end, const Vector3& currentArm, Matrix3& k) {
  Matrix3 t;
  setCrossTimesRotation(currentArm, end.rotation, t);
  for (int c = 0; c < 3; ++c)
    t.col(c) *= end.inverseInertia(c);
  const Matrix3& s = end.armRotation;
  for (int row = 0; row < 3; ++row)
    for (int column = 0; column < 3; ++column)
      k(row, column) += t.row(row).dot(s.row(column));
}

/// Solves the symmetric K x = b by K = L D Lᵀ (upper triangle of K read). False when a pivot
/// is not positive (K not positive definite: no dynamic end).
PBD_INLINE bool solveSymmetric3(const Matrix3& k, const Vector3& b, Vector3& x) {
  const Real d0 = k(0, 0);
  if (!(d0 > 0)) return false;
  const Real l10 = k(0, 1) / d0;
  const Real l20 = k(0, 2) / d0;
  const Real d1 = k(1, 1) - l10 * l10 * d0;
  if (!(d1 > 0)) return false;
  const Real l21 = (k(1, 2) - l20 * l10 * d0) / d1;
  const Real d2 = k(2, 2) - l20 * l20 * d0 - l21 * l21 * d1;
  if (!(d2 > 0)) return false;
  const Real y0 = b(0);
  const Real y1 = b(1) - l10 * y0;
  const Real y2 = b(2) - l20 * y0 - l21 * y1;
  x(2) = y2 / d2;
  x(1) = y1 / d1 - l21 * x(2);
  x(0) = y0 / d0 - l10 * x(1) - l20 * x(2);
  return x.allFinite();
}

/// Δθ = R D (Sᵀ Δλ) (times `sign`).
PBD_INLINE Vector3 angularCorrection(const PointEnd& end, const Vector3& multiplier, Real sign) {
  const Vector3 local = (end.armRotation.transpose() * multiplier).cwiseProduct(end.inverseInertia);
  return sign * (end.rotation * local);
}

/// Moves both ends by Δλ along the directions of `end0` and `end1`.
PBD_INLINE void applyCorrection(RigidBodyStates& bodies, std::size_t i0, std::size_t i1,
                                const PointEnd& end0, const PointEnd& end1,
                                const Vector3& multiplier) {
  if (end0.dynamic) {
    bodies.position[i0] -= end0.inverseMass * multiplier;
    addAngularDisplacement(bodies.rotation[i0], angularCorrection(end0, multiplier, 1));
  }
  if (end1.dynamic) {
    bodies.position[i1] += end1.inverseMass * multiplier;
    addAngularDisplacement(bodies.rotation[i1], angularCorrection(end1, multiplier, -1));
  }
}

/// The projection along the current poses' directions (the seed's and XPBD's).
Vector3 projectAlongPredicted(RigidBodyStates& bodies, int body0, int body1, const Vector3& anchor0,
                              const Vector3& anchor1, Real complianceTilde, const Vector3& lambda) {
  const auto i0 = static_cast<std::size_t>(body0);
  const auto i1 = static_cast<std::size_t>(body1);
  const PointEnd end0 = pointEnd(bodies, body0, bodies.rotation[i0], anchor0);
  const PointEnd end1 = pointEnd(bodies, body1, bodies.rotation[i1], anchor1);
  if (!end0.dynamic && !end1.dynamic) return Vector3::Zero();
  const Vector3 value = (bodies.position[i1] + end1.arm) - (bodies.position[i0] + end0.arm);

  Matrix3 k = Matrix3::Zero();
  k.diagonal().setConstant(end0.inverseMass + end1.inverseMass + complianceTilde);
  if (end0.dynamic) addArmTerm(end0, k);
  if (end1.dynamic) addArmTerm(end1, k);
  Vector3 multiplier;
  if (!solveSymmetric3(k, -value - complianceTilde * lambda, multiplier)) return Vector3::Zero();
  applyCorrection(bodies, i0, i1, end0, end1, multiplier);
  return multiplier;
}

/// SHAKE's step (see the header): the corrections along the substep-start directions G_n,
/// Δx₀ = −w₀ Δλ, Δθ₀ = −J₀ⁿ (r₀ⁿ × Δλ), … with Δλ from the Newton step on C(Δλ) at the
/// current poses, K = ∂C/∂λ = (w₀ + w₁ + α̃) 𝟙 − Σ_k [r_k]× J_kⁿ [r_kⁿ]× (current arms on the
/// left, not symmetric; Ryckaert et al. 1977's SHAKE denominator). K's pivots are positive
/// while the arms turn by well under 90° in a substep; when one is not, the projection falls
/// back to the current directions.
Vector3 projectAlongStart(RigidBodyStates& bodies, int body0, int body1, const Vector3& anchor0,
                          const Vector3& anchor1, Real complianceTilde, const Vector3& lambda) {
  const auto i0 = static_cast<std::size_t>(body0);
  const auto i1 = static_cast<std::size_t>(body1);
  const PointEnd end0 = pointEnd(bodies, body0, bodies.oldRotation[i0], anchor0);
  const PointEnd end1 = pointEnd(bodies, body1, bodies.oldRotation[i1], anchor1);
  if (!end0.dynamic && !end1.dynamic) return Vector3::Zero();
  const Vector3 arm0 = bodies.rotation[i0] * anchor0;  // current arms: C and ∂C/∂λ
  const Vector3 arm1 = bodies.rotation[i1] * anchor1;
  const Vector3 value = (bodies.position[i1] + arm1) - (bodies.position[i0] + arm0);

  Matrix3 k = Matrix3::Zero();
  k.diagonal().setConstant(end0.inverseMass + end1.inverseMass + complianceTilde);
  if (end0.dynamic) addMixedArmTerm(end0, arm0, k);
  if (end1.dynamic) addMixedArmTerm(end1, arm1, k);
  Vector3 multiplier;
  if (!solveUnpivoted(k, Vector3(-value - complianceTilde * lambda), multiplier))
    return projectAlongPredicted(bodies, body0, body1, anchor0, anchor1, complianceTilde, lambda);
  applyCorrection(bodies, i0, i1, end0, end1, multiplier);
  return multiplier;
}

#undef PBD_INLINE

}  // namespace

Vector3 projectPointConstraint(RigidBodyStates& bodies, int body0, int body1,
                               const Vector3& anchor0, const Vector3& anchor1, Real complianceTilde,
                               const Vector3& lambda, JointDirections directions) {
  if (directions == JointDirections::Start && startDirectionsApply(bodies, body0) &&
      startDirectionsApply(bodies, body1))
    return projectAlongStart(bodies, body0, body1, anchor0, anchor1, complianceTilde, lambda);
  return projectAlongPredicted(bodies, body0, body1, anchor0, anchor1, complianceTilde, lambda);
}

}  // namespace pbd
