// Stiff-rod joint: zero stretch plus elastic bending and twisting between two rigid segments
// (the seed's StretchBendingTwistingConstraint; the `CosseratJoints` of its stiff-rods scenes).
//
// Frames: F_k = q_k ⊗ s_k is the world rotation of segment k's *scene frame* (its geometry's
// frame; q_k the principal-frame rotation, s_k = principal → scene inverse). The rod axis is
// the segment's local **y** axis, as in the seed (Blender armatures); x and z span the
// cross-section. The joint point p (world, t = 0) is captured in both segments: c_k = x_k + r_k.
//
//   C = ( c₁ − c₀ ,  Ω − Ω⁰ ) ∈ ℝ⁶,   Ω = (2/L) vec(e),  e = F₀⁻¹ ⊗ F₁ (sign-fixed: w ≥ 0),
//   Ω⁰ = Ω at t = 0 (the rest Darboux vector, in segment 0's frame), L = mean segment length.
//   ∇C: point rows A₀ = −𝟙, B₀ = [r₀]×, A₁ = 𝟙, B₁ = −[r₁]× (joint_parts::setPointRows);
//   Darboux rows ∂Ω/∂θ₁ = (2/L) ½ (w𝟙 − [vec e]×) R(F₀)ᵀ, ∂Ω/∂θ₀ = −∂Ω/∂θ₁, ∂Ω/∂x_k = 0
//   (joint_parts::relativeRotationError).
//   Energy: ½ L (Ω − Ω⁰)ᵀ K (Ω − Ω⁰), K = diag(E I, 2 G I, E I) ∘ stiffnessModifier, I = π r⁴/4
//   (2 I = J, the polar moment of a circle). For a bend or twist φ about a frame axis the joint is
//   a rotational spring: torque (K_i/L) sin φ.
//   XPBD compliances (h the substep): stretch rows α̃ = 10⁻¹⁰/h² (a regularisation: the
//   joint is practically rigid in stretch and shear), Darboux rows α̃_i = 1/(K_i L h²).
//   Solve: K Δλ = −C − α̃ ∘ λ for all six rows together (constraint_rows.h), λ accumulated over
//   the substep's iterations and reset by beginSubstep (as the seed).
// Reference: Deul, Müller, Bender 2018, "Direct position-based solver for stiff rods", CGF 37(6),
// eq. 7 (Ω), 10–11 (∇Ω), 19–23 (the 6-row system), 23 (zero stretch).
// Differences from the seed: C's point rows are c₁ − c₀ (the seed c₀ − c₁: only λ's sign
// differs); the Darboux rows use the segments' scene frames rather than the bodies' frames (the
// same in the seed's demo, whose segments are built with diagonal inertia; here the principal
// frame of a symmetric segment may differ from its geometry's); e is sign-fixed (the seed's
// q̄₀q₁ is not, which matters only for relative rotations beyond 180°); the seed's
// `stiffnessModifier` is read but unused there, here it scales K.
#pragma once

#include "pbd/joints/joint_common.h"

namespace pbd {

namespace stiff_rod {

using Vector6 = Eigen::Matrix<Real, 6, 1>;

/// Stretch regularisation of the seed: α = 10⁻¹⁰ (before the 1/h² scaling).
inline constexpr Real kStretchRegularisation = Real(1e-10);

/// K = (E I, 2 G I, E I) ∘ modifier with I = π r⁴ / 4 (N m²): bending about x, twist about the
/// rod axis y, bending about z.
Vector3 bendingTwistingStiffness(const StiffRodJointParams& params);

/// α̃ of the six rows for substep h: 10⁻¹⁰/h² (stretch), 1/(K_i L h²) (Darboux).
Vector6 rowCompliance(const Vector3& stiffness, Real segmentLength, Real substepSize);

/// Throws std::invalid_argument naming `jsonPath` unless E, G, r, L and the modifiers are > 0.
void checkParams(const StiffRodJointParams& params, const std::string& jsonPath);

}  // namespace stiff_rod

class StretchBendingTwistingJoint : public JointDefaults {
 public:
  static constexpr JointType kType = JointType::StiffRod;
  static constexpr int kRows = 6;

  StretchBendingTwistingJoint(const BodyStates& bodies, const JointDesc& desc);
  /// α̃ for substep h, λ = 0.
  void beginSubstep(Real substepSize);
  /// One projection of all six rows, λ accumulated.
  void solvePosition(BodyStates& bodies, Real substepSize);
  ConstraintRows<kRows> positionRows(const BodyStates& bodies) const;
  /// linear: ‖c₁ − c₀‖ (the zero-stretch constraint); angular: 0 (bending is elastic).
  JointError error(const BodyStates& bodies) const;
  JointEnds ends() const { return {body0_, body1_, -1}; }

  /// One projection with explicit compliance and multiplier (the XPBD step's); returns Δλ.
  stiff_rod::Vector6 project(BodyStates& bodies, const stiff_rod::Vector6& complianceTilde,
                             const stiff_rod::Vector6& multiplier) const;
  /// ½ L (Ω − Ω⁰)ᵀ K (Ω − Ω⁰), J.
  Real elasticEnergy(const BodyStates& bodies) const;
  const Vector3& stiffness() const { return stiffness_; }               ///< K, N m²
  Real segmentLength() const { return segmentLength_; }                 ///< L, m
  const stiff_rod::Vector6& compliance() const { return compliance_; }  ///< α̃ of this substep
  const stiff_rod::Vector6& multiplier() const { return multiplier_; }

 private:
  int body0_ = -1, body1_ = -1;
  joint_parts::LocalAnchor anchor0_, anchor1_;
  joint_parts::LocalFrame frame0_, frame1_;  ///< segment scene frames in the principal frames
  Vector3 restVector_ = Vector3::Zero();     ///< vec(e) at t = 0 (Ω⁰ L / 2)
  Vector3 stiffness_ = Vector3::Zero();
  Real segmentLength_ = 1;
  stiff_rod::Vector6 compliance_ = stiff_rod::Vector6::Zero();
  stiff_rod::Vector6 multiplier_ = stiff_rod::Vector6::Zero();
};

}  // namespace pbd
