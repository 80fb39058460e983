// Damper joint (the seed's name; it acts as an axial spring): a slider whose axial row is
// compliant. Body 1 moves along an axis fixed in body 0, held by a spring of stiffness k (N/m)
// at its initial offset; the rest is locked.
//
//   C = (a·d, b·d, n·d,  vec(e)) ∈ ℝ⁶,  d = c₁ − c₀ (both at body 1's centre of mass at t = 0),
//   (a, b, n) body 0's joint frame (a = axis), e = F₀⁻¹ ⊗ F₁ (w ≥ 0).
//   Row 0 is XPBD-compliant with α̃ = 1/(k h²) (h the substep size, λ reset every substep);
//   the other five are hard. Potential energy ½ k (a·d)². There is no velocity damping.
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
  Vector compliance_ = Vector::Zero();
  Vector multiplier_ = Vector::Zero();
};

}  // namespace pbd
