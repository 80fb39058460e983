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

/// K = Σ_k (w_k A_k A_kᵀ + B_k J_k B_kᵀ) + diag(compliance).
template <int Rows>
Eigen::Matrix<Real, Rows, Rows> effectiveMassMatrix(
    const ConstraintRows<Rows>& rows, const std::array<EndInverseMass, 2>& ends,
    const Eigen::Matrix<Real, Rows, 1>& compliance) {
  Eigen::Matrix<Real, Rows, Rows> k = compliance.asDiagonal();
  for (std::size_t e = 0; e < 2; ++e) {
    k.noalias() += ends[e].linear * rows.linear[e] * rows.linear[e].transpose();
    k.noalias() += rows.angular[e] * ends[e].angular * rows.angular[e].transpose();
  }
  return k;
}

/// Solves K Δλ = rhs and maps Δλ to per-end corrections. Returns false (and no correction)
/// when K is singular, e.g. both ends static.
template <int Rows>
bool solveRows(const ConstraintRows<Rows>& rows, const std::array<EndInverseMass, 2>& ends,
               const Eigen::Matrix<Real, Rows, 1>& compliance,
               const Eigen::Matrix<Real, Rows, 1>& rhs, RowCorrection<Rows>& out) {
  const Eigen::Matrix<Real, Rows, Rows> k = effectiveMassMatrix(rows, ends, compliance);
  if (!(k.diagonal().maxCoeff() > 0)) return false;
  const Eigen::LDLT<Eigen::Matrix<Real, Rows, Rows>> factor(k);
  if (factor.info() != Eigen::Success) return false;
  out.multiplier = factor.solve(rhs);
  if (!out.multiplier.allFinite()) return false;
  for (std::size_t e = 0; e < 2; ++e) {
    out.linear[e] = ends[e].linear * (rows.linear[e].transpose() * out.multiplier);
    out.angular[e] = ends[e].angular * (rows.angular[e].transpose() * out.multiplier);
  }
  return true;
}

}  // namespace pbd
