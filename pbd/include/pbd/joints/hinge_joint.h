// Hinge joint: a common point and a common axis; one rotational degree of freedom.
//
//   C = (c₁ − c₀ ∈ ℝ³,  e_y, e_z) ∈ ℝ⁵,  e = F₀⁻¹ ⊗ F₁ (relative rotation of the joint frames,
//   x axis = hinge axis, w ≥ 0); e_y = e_z = 0 iff the relative rotation is about the axis.
//   ∇C: point rows as the ball joint; rotation rows ∂vec(e)/∂θ₁ = ½ (w𝟙 − [vec e]×) R(F₀)ᵀ,
//   ∂/∂θ₀ = −∂/∂θ₁ (rows y, z).
// The seed's "projected relative quaternion" rows; solved as one 5×5 Newton step.
// The misalignment angle of the two axes is 2 asin √(e_y² + e_z²).
// Reference: Deul, Charrier, Bender 2014, §4.3.
#pragma once

#include "pbd/joints/joint_common.h"

namespace pbd {

class HingeJoint : public JointDefaults {
 public:
  static constexpr JointType kType = JointType::Hinge;
  static constexpr int kRows = 5;

  HingeJoint(const BodyStates& bodies, const JointDesc& desc);
  void solvePosition(BodyStates& bodies, Real substepSize);
  ConstraintRows<kRows> positionRows(const BodyStates& bodies) const;
  JointError error(const BodyStates& bodies) const;
  JointEnds ends() const { return frames_.ends(); }
  const PointAxisFrames& frames() const { return frames_; }

 private:
  PointAxisFrames frames_;
};

}  // namespace pbd
