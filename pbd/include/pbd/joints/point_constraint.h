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
//
// Directions (XpbdSettings::jointDirections): with JointDirections::Start the corrections act
// along the constraint gradient of the substep's start (RigidBodyStates::oldRotation: R_kⁿ,
// r_kⁿ, S_kⁿ, J_kⁿ), SHAKE's (Ryckaert, Ciccotti, Berendsen 1977), while C = c₁ − c₀ stays at
// the current poses (r_k = q_k a_k) and Δλ is the Newton step on C along those directions:
//   K = (w₀ + w₁ + α̃) 𝟙 + Σ_k T_k D_k S_kⁿᵀ,  T_k = [r_k]× R_kⁿ  (not symmetric),
// solved by L U without pivoting (constraint_rows.h, solveUnpivoted; the current directions
// when a pivot is not positive). Extra work: two quaternion rotations, T_k and the full K
// (bench/callgrind_step.py, docs/benchmarks.md).
#pragma once

#include <cmath>

#include "pbd/math/quaternion.h"
#include "pbd/model/body_states.h"
#include "pbd/model/scene.h"

namespace pbd {

/// JointDirections::Start projects a joint along its substep-start directions only while each
/// of its rigid ends has turned by at most kStartDirectionsMaxTurn = 0.1 rad since the substep's
/// start (a turn resolved by more than 60 substeps per revolution; the library's joint cases
/// stay below 0.05 rad at their samples, chain_100's whip and robot_minitaur_drop's landing
/// touch it between them); beyond, the joint is projected along
/// the current directions. The limit keeps scenes whose constraints fight finite: in
/// cases/double_pendulum_boxes.json (contacts inside the joints, energy already 10⁵ × the
/// scale with the current directions) the start directions without a limit, or with 0.2 rad,
/// overflow at some substep counts (10, 80), and the current directions' numerical damping does
/// not (docs/methods.md, "Joint directions").
/// True when `body` (-1: none) turned by at most that limit: |q_start · q_now| ≥ cos(0.05).
inline bool startDirectionsApply(const RigidBodyStates& bodies, int body) {
  constexpr Real kCosHalfMaxTurn = Real(0.99875026039496628);  // cos(0.1 rad / 2)
  if (body < 0) return true;
  const auto i = static_cast<std::size_t>(body);
  return std::abs(bodies.oldRotation[i].dot(bodies.rotation[i])) >= kCosHalfMaxTurn;
}

/// Projects the point constraint between anchors `anchor0` (in body0's principal frame) and
/// `anchor1` once, with compliance `complianceTilde` = α/h² (0: hard) and the accumulated
/// multiplier `lambda`, along the constraint directions `directions` take (Predicted: the
/// current rotations, the seed's and the paper's). Returns Δλ (zero when neither end is
/// dynamic).
Vector3 projectPointConstraint(RigidBodyStates& bodies, int body0, int body1,
                               const Vector3& anchor0, const Vector3& anchor1,
                               Real complianceTilde = 0, const Vector3& lambda = Vector3::Zero(),
                               JointDirections directions = JointDirections::Predicted);

}  // namespace pbd
