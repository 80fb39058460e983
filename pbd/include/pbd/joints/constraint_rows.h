// The block solver shared by every joint: a Newton step on all rows of a joint at once.
//
// A joint with m rows C(x₀, θ₀, x₁, θ₁) ∈ ℝᵐ provides C and its Jacobians with respect to
// each end's position (A_k = ∂C/∂x_k, m×3) and rotation (B_k = ∂C/∂θ_k, m×3, for a world-frame
// angular displacement θ). With inverse mass w_k and world inverse inertia J_k,
//   K = Σ_k (w_k A_k A_kᵀ + B_k J_k B_kᵀ) + diag(α̃),     K Δλ = r,
//   Δx_k = w_k A_kᵀ Δλ,   Δθ_k = J_k B_kᵀ Δλ,
// with r = −C − α̃ λ at position level (XPBD with compliance α̃ = 1/(k h²); α̃ = 0 for hard
// rows, the seed's joints) and r = v_target − (Σ A_k v_k + B_k ω_k) at velocity level.
// For a ball joint this is exactly the seed's (K₀ + K₁) p = c₁ − c₀ with
// K_k = w_k 𝟙 − [r_k]× J_k [r_k]× (Deul, Charrier, Bender 2014, "Position-based rigid-body
// dynamics", CAVW 27(2), eq. 16–20); rows are solved together, as there.
#pragma once

#include <Eigen/Cholesky>
#include <array>

#include "pbd/math/types.h"

namespace pbd {

/// Inverse mass and world inverse inertia of one end of a constraint (zero when static; the
/// angular part is zero for a particle).
struct EndInverseMass {
  Real linear = 0;
  Matrix3 angular = Matrix3::Zero();
};

template <int Rows>
struct ConstraintRows {
  using Vector = Eigen::Matrix<Real, Rows, 1>;
  using Jacobian = Eigen::Matrix<Real, Rows, 3>;

  Vector value = Vector::Zero();                                        ///< C
  std::array<Jacobian, 2> linear{Jacobian::Zero(), Jacobian::Zero()};   ///< A_k = ∂C/∂x_k
  std::array<Jacobian, 2> angular{Jacobian::Zero(), Jacobian::Zero()};  ///< B_k = ∂C/∂θ_k
};

template <int Rows>
struct RowCorrection {
  using Vector = Eigen::Matrix<Real, Rows, 1>;
  std::array<Vector3, 2> linear{Vector3::Zero(), Vector3::Zero()};   ///< Δx_k (or Δv_k)
  std::array<Vector3, 2> angular{Vector3::Zero(), Vector3::Zero()};  ///< Δθ_k (or Δω_k)
  Vector multiplier = Vector::Zero();                                ///< Δλ
};

/// K = Σ_k (w_k A_k A_kᵀ + B_k J_k B_kᵀ) + diag(compliance), accumulated on the upper triangle
/// and mirrored (K is symmetric): N_k = B_k J_k once, then K_ij += w_k A_k,i·A_k,j + N_k,i·B_k,j
/// for j ≥ i.
template <int Rows>
Eigen::Matrix<Real, Rows, Rows> effectiveMassMatrix(
    const ConstraintRows<Rows>& rows, const std::array<EndInverseMass, 2>& ends,
    const Eigen::Matrix<Real, Rows, 1>& compliance) {
  Eigen::Matrix<Real, Rows, Rows> k = compliance.asDiagonal();
  for (std::size_t e = 0; e < 2; ++e) {
    const Real w = ends[e].linear;
    const Eigen::Matrix<Real, Rows, 3> n = rows.angular[e] * ends[e].angular;
    for (int i = 0; i < Rows; ++i)
      for (int j = i; j < Rows; ++j)
        k(i, j) += w * rows.linear[e].row(i).dot(rows.linear[e].row(j)) +
                   n.row(i).dot(rows.angular[e].row(j));
  }
  for (int i = 0; i < Rows; ++i)
    for (int j = 0; j < i; ++j)
      k(i, j) = k(j, i);
  return k;
}

/// Solves the symmetric K x = b by L D Lᵀ without pivoting (fixed size, unrolled by the
/// compiler; Eigen's pivoting LDLT spent most of a 5-row joint solve in dynamic-size blocks).
/// Returns false when a pivot is not above 10⁻¹² of K's largest diagonal entry (K singular or
/// nearly: the caller then uses the pivoting factorisation).
template <int Rows>
bool solveSymmetricUnpivoted(Eigen::Matrix<Real, Rows, Rows> k,
                             const Eigen::Matrix<Real, Rows, 1>& b,
                             Eigen::Matrix<Real, Rows, 1>& x) {
  const Real floor = Real(1e-12) * k.diagonal().maxCoeff();
  for (int j = 0; j < Rows; ++j) {  // in place: D on the diagonal, L below it
    Real d = k(j, j);
    for (int m = 0; m < j; ++m)
      d -= k(j, m) * k(j, m) * k(m, m);
    if (!(d > floor)) return false;
    k(j, j) = d;
    for (int i = j + 1; i < Rows; ++i) {
      Real v = k(i, j);
      for (int m = 0; m < j; ++m)
        v -= k(i, m) * k(j, m) * k(m, m);
      k(i, j) = v / d;
    }
  }
  x = b;
  for (int i = 0; i < Rows; ++i)
    for (int m = 0; m < i; ++m)
      x(i) -= k(i, m) * x(m);
  for (int i = 0; i < Rows; ++i)
    x(i) /= k(i, i);
  for (int i = Rows - 1; i >= 0; --i)
    for (int m = i + 1; m < Rows; ++m)
      x(i) -= k(m, i) * x(m);
  return true;
}

/// Solves a general (not symmetric) K x = b by K = L U without pivoting (Doolittle; fixed size,
/// unrolled by the compiler). Returns false when a pivot of U is not above 10⁻¹² of K's largest
/// diagonal entry. For the matrices it is used on — K of SHAKE's Newton step, a perturbation of
/// a symmetric positive definite K (constraint directions of the substep's start on the right,
/// current ones on the left) — positive pivots say the perturbation is small enough for the
/// step to be meaningful; the callers then use the symmetric projection instead.
template <int Rows>
bool solveUnpivoted(Eigen::Matrix<Real, Rows, Rows> k, const Eigen::Matrix<Real, Rows, 1>& b,
                    Eigen::Matrix<Real, Rows, 1>& x) {
  const Real floor = Real(1e-12) * k.diagonal().maxCoeff();
  for (int j = 0; j < Rows; ++j) {  // in place: U on and above the diagonal, L (unit) below
    for (int i = j; i < Rows; ++i)
      for (int m = 0; m < j; ++m)
        k(j, i) -= k(j, m) * k(m, i);
    if (!(k(j, j) > floor)) return false;
    for (int i = j + 1; i < Rows; ++i) {
      for (int m = 0; m < j; ++m)
        k(i, j) -= k(i, m) * k(m, j);
      k(i, j) /= k(j, j);
    }
  }
  x = b;
  for (int i = 0; i < Rows; ++i)
    for (int m = 0; m < i; ++m)
      x(i) -= k(i, m) * x(m);
  for (int i = Rows - 1; i >= 0; --i) {
    for (int m = i + 1; m < Rows; ++m)
      x(i) -= k(i, m) * x(m);
    x(i) /= k(i, i);
  }
  return x.allFinite();
}

/// SHAKE's Newton step on a joint's rows (JointDirections::Start): the corrections act along
/// the Jacobians `start` (A_k, B_k of the substep's start, with `ends` its inverse masses), and
/// Δλ solves the linearisation of C at the current poses along them,
///   K = ∂C/∂λ = Σ_k (w_k A_kⁿᵒʷ A_kᵀ + B_kⁿᵒʷ J_k B_kᵀ) + diag(compliance),   K Δλ = rhs,
/// A_kⁿᵒʷ, B_kⁿᵒʷ those of `current` (K not symmetric; Ryckaert, Ciccotti, Berendsen 1977).
/// Returns false (no correction) when a pivot of K's L U is not positive (solveUnpivoted):
/// the directions have turned too far in the substep for the step to mean anything.
template <int Rows>
bool solveRowsAlongStart(const ConstraintRows<Rows>& start, const ConstraintRows<Rows>& current,
                         const std::array<EndInverseMass, 2>& ends,
                         const Eigen::Matrix<Real, Rows, 1>& compliance,
                         const Eigen::Matrix<Real, Rows, 1>& rhs, RowCorrection<Rows>& out) {
  Eigen::Matrix<Real, Rows, Rows> k = compliance.asDiagonal();
  for (std::size_t e = 0; e < 2; ++e) {
    const Real w = ends[e].linear;
    const Eigen::Matrix<Real, Rows, 3> n = current.angular[e] * ends[e].angular;
    for (int i = 0; i < Rows; ++i)
      for (int j = 0; j < Rows; ++j)
        k(i, j) += w * current.linear[e].row(i).dot(start.linear[e].row(j)) +
                   n.row(i).dot(start.angular[e].row(j));
  }
  if (!(k.diagonal().maxCoeff() > 0)) return false;
  if (!solveUnpivoted(k, rhs, out.multiplier)) return false;
  for (std::size_t e = 0; e < 2; ++e) {
    out.linear[e] = ends[e].linear * (start.linear[e].transpose() * out.multiplier);
    out.angular[e] = ends[e].angular * (start.angular[e].transpose() * out.multiplier);
  }
  return true;
}

/// Solves K Δλ = rhs and maps Δλ to per-end corrections. Returns false (and no correction)
/// when K is singular, e.g. both ends static.
template <int Rows>
bool solveRows(const ConstraintRows<Rows>& rows, const std::array<EndInverseMass, 2>& ends,
               const Eigen::Matrix<Real, Rows, 1>& compliance,
               const Eigen::Matrix<Real, Rows, 1>& rhs, RowCorrection<Rows>& out) {
  const Eigen::Matrix<Real, Rows, Rows> k = effectiveMassMatrix(rows, ends, compliance);
  if (!(k.diagonal().maxCoeff() > 0)) return false;
  if (!solveSymmetricUnpivoted(k, rhs, out.multiplier)) {
    // Singular or nearly (rows that depend on each other in this pose): the pivoting
    // factorisation solves what can be solved.
    const Eigen::LDLT<Eigen::Matrix<Real, Rows, Rows>> factor(k);
    if (factor.info() != Eigen::Success) return false;
    out.multiplier = factor.solve(rhs);
  }
  if (!out.multiplier.allFinite()) return false;
  for (std::size_t e = 0; e < 2; ++e) {
    out.linear[e] = ends[e].linear * (rows.linear[e].transpose() * out.multiplier);
    out.angular[e] = ends[e].angular * (rows.angular[e].transpose() * out.multiplier);
  }
  return true;
}

}  // namespace pbd
