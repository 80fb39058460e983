// The point constraint of a ball joint, solved without the generic m-row path.
//
//   C = c₁ − c₀ ∈ ℝ³, c_k = x_k + r_k, r_k = R_k a_k (a_k the anchor in body k's principal frame)
//   ∇C: A₀ = −𝟙, B₀ = [r₀]×, A₁ = 𝟙, B₁ = −[r₁]× (joint_parts::setPointRows)
// With S_k = [r_k]× R_k and D_k = diag(I_k⁻¹) in the principal frame (J_k = R_k D_k R_kᵀ),
//   K = (w₀ + w₁ + α̃) 𝟙 + S₀ D₀ S₀ᵀ + S₁ D₁ S₁ᵀ   (= Σ_k w_k 𝟙 − [r_k]× J_k [r_k]×, + α̃ 𝟙)
//   K Δλ = −C − α̃ λ,
//   Δx₀ = −w₀ Δλ, Δx₁ = w₁ Δλ, Δθ₀ = R₀ D₀ (S₀ᵀ Δλ), Δθ₁ = −R₁ D₁ (S₁ᵀ Δλ).
// This is the projection of constraint_rows.h (solveRows) for these rows, term by term; K is
// symmetric positive definite when an end is dynamic and is factorised as L D Lᵀ without
// pivoting. Reference: Deul, Charrier, Bender 2014, "Position-based rigid-body dynamics",
// eq. 16–20; Macklin, Müller, Chentanez 2016 (XPBD) for α̃.
//
// Operation count per solve with both ends dynamic (multiplications + additions; the target
// of bench/callgrind_harness.py): two rotation matrices from quaternions 2 × 25, two anchors
// 2 × 15, C 6, S_k 2 × 27, S_k D_k S_kᵀ 2 × (9 + 30), K 12, L D Lᵀ and its solve 30 (3
// divisions), corrections 2 × (15 + 3 + 15) + 6, two quaternion updates with normalisation
// 2 × 40 (one square root each): about 430.
#pragma once

#include "pbd/math/quaternion.h"
#include "pbd/model/body_states.h"

namespace pbd {

/// Projects the point constraint between anchors `anchor0` (in body0's principal frame) and
/// `anchor1` once, with compliance `complianceTilde` = α/h² (0: hard) and the accumulated
/// multiplier `lambda`. Returns Δλ (zero when neither end is dynamic).
Vector3 projectPointConstraint(RigidBodyStates& bodies, int body0, int body1,
                               const Vector3& anchor0, const Vector3& anchor1,
                               Real complianceTilde = 0, const Vector3& lambda = Vector3::Zero());

}  // namespace pbd
