#include "pbd/joints/point_constraint.h"

namespace pbd {
namespace {

// The helpers are inlined into the solve (a call each cost a copy of PointEnd and ~15 % of the
// solve's instructions, measured by bench/callgrind_harness.py).
#if defined(__GNUC__)
#define PBD_INLINE inline __attribute__((always_inline))
#else
#define PBD_INLINE inline
#endif

/// One end of the constraint at the current pose.
struct PointEnd {
  Matrix3 rotation;        // R_k
  Vector3 arm;             // r_k = R_k a_k
  Matrix3 armRotation;     // S_k = [r_k]× R_k
  Vector3 inverseInertia;  // D_k (zero for a static end)
  Real inverseMass = 0;    // w_k
  bool dynamic = false;
};

PBD_INLINE PointEnd pointEnd(const RigidBodyStates& bodies, int body, const Vector3& anchor) {
  const auto i = static_cast<std::size_t>(body);
  PointEnd end;
  end.rotation = bodies.rotation[i].toRotationMatrix();
  end.arm.noalias() = end.rotation * anchor;
  end.dynamic = bodies.isDynamic(i);
  if (!end.dynamic) return end;
  end.inverseMass = bodies.inverseMass[i];
  end.inverseInertia = bodies.inverseInertia[i];
  const Vector3& r = end.arm;
  for (int c = 0; c < 3; ++c) {  // column c of [r]× R is r × R.col(c)
    const Vector3 column = end.rotation.col(c);
    end.armRotation(0, c) = r.y() * column.z() - r.z() * column.y();
    end.armRotation(1, c) = r.z() * column.x() - r.x() * column.z();
    end.armRotation(2, c) = r.x() * column.y() - r.y() * column.x();
  }
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

#undef PBD_INLINE

}  // namespace

Vector3 projectPointConstraint(RigidBodyStates& bodies, int body0, int body1,
                               const Vector3& anchor0, const Vector3& anchor1, Real complianceTilde,
                               const Vector3& lambda) {
  const PointEnd end0 = pointEnd(bodies, body0, anchor0);
  const PointEnd end1 = pointEnd(bodies, body1, anchor1);
  if (!end0.dynamic && !end1.dynamic) return Vector3::Zero();
  const auto i0 = static_cast<std::size_t>(body0);
  const auto i1 = static_cast<std::size_t>(body1);
  const Vector3 value = (bodies.position[i1] + end1.arm) - (bodies.position[i0] + end0.arm);

  Matrix3 k = Matrix3::Zero();
  k.diagonal().setConstant(end0.inverseMass + end1.inverseMass + complianceTilde);
  if (end0.dynamic) addArmTerm(end0, k);
  if (end1.dynamic) addArmTerm(end1, k);
  Vector3 multiplier;
  if (!solveSymmetric3(k, -value - complianceTilde * lambda, multiplier)) return Vector3::Zero();

  if (end0.dynamic) {
    bodies.position[i0] -= end0.inverseMass * multiplier;
    addAngularDisplacement(bodies.rotation[i0], angularCorrection(end0, multiplier, 1));
  }
  if (end1.dynamic) {
    bodies.position[i1] += end1.inverseMass * multiplier;
    addAngularDisplacement(bodies.rotation[i1], angularCorrection(end1, multiplier, -1));
  }
  return multiplier;
}

}  // namespace pbd
