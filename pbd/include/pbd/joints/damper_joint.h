// Damper joint (the seed's name; it acts as an axial spring): a slider whose axial row is
// compliant. Body 1 moves along an axis fixed in body 0, held by a spring of stiffness k (N/m)
// at its initial offset; the rest is locked.
//
//   C = (a·d, b·d, n·d,  vec(e)) ∈ ℝ⁶,  d = c₁ − c₀ (both at body 1's centre of mass at t = 0),
//   (a, b, n) body 0's joint frame (a = axis), e = F₀⁻¹ ⊗ F₁ (w ≥ 0).
//   Row 0 is XPBD-compliant with α̃ = 1/(k h²) (h the substep size, λ reset every substep);
//   the other five are hard. Potential energy ½ k (a·d)². There is no velocity damping.
// The linear rows' Jacobians (Simulation.jointModel, jointModelFor):
//   seed (the `pbd` method's default, as PositionBasedDynamics' solve_DamperJoint): A₀ = −[a b n]ᵀ,
//     A₁ = [a b n]ᵀ, B₀ = B₁ = 0 — the correction moves the centres of mass only; the rows'
//     dependence on the bodies' rotations (d is measured from body 0's anchor, along body 0's
//     axes) is left out, so once body 0 rotates the step is not the projection of C: the
//     linear corrections carry no torque and do not conserve angular momentum.
//   corrected (`pbd.xpbd`'s default): the anchor rows with their full Jacobian (setAxisRow:
//     B₀ = (n × (c₁ − x₀))ᵀ, B₁ = ((c₁ − x₁) × n)ᵀ), the Gauss–Newton step of C, which
//     conserves linear and angular momentum (docs/methods.md, "Joints").
// Reference: PositionBasedDynamics DamperJoint (docs/seed.md#damper-joint); XPBD eq. 18.
#pragma once

#include "pbd/joints/joint_common.h"

namespace pbd {

class DamperJoint : public JointDefaults {
 public:
  static constexpr JointType kType = JointType::Damper;
  static constexpr int kRows = 6;
  using Vector = Eigen::Matrix<Real, kRows, 1>;

  DamperJoint(const BodyStates& bodies, const JointDesc& desc);
  void beginSubstep(Real substepSize);
  void solvePosition(BodyStates& bodies, Real substepSize);
  ConstraintRows<kRows> positionRows(const BodyStates& bodies) const;
  /// Error of the five hard rows (the axial row is the spring's extension, not an error).
  JointError error(const BodyStates& bodies) const;
  JointEnds ends() const { return frames_.ends(); }
  Real stiffness() const { return stiffness_; }  ///< N/m

 private:
  PointAxisFrames frames_;
  Real stiffness_ = 0;
  JointModel model_ = JointModel::Seed;
  Vector compliance_ = Vector::Zero();
  Vector multiplier_ = Vector::Zero();
};

}  // namespace pbd
