// Universal (Cardan) joint: a common point; axis1 fixed in body 0 and axis2 fixed in body 1
// stay perpendicular, leaving rotation about both axes free.
//
//   C = (c₁ − c₀ ∈ ℝ³,  a₀·a₁) ∈ ℝ⁴
//   ∇C: point rows as the ball joint; for the last row, with u = a₀ × a₁,
//   B₀ = uᵀ (δa₀ = δθ₀ × a₀), B₁ = −uᵀ (δa₁ = δθ₁ × a₁), A = 0.
// The angular error is |asin(a₀·a₁)|, the deviation from perpendicular.
// Reference: Deul, Charrier, Bender 2014; PositionBasedDynamics UniversalJoint.
#pragma once

#include "pbd/joints/joint_common.h"

namespace pbd {

class UniversalJoint : public JointDefaults {
 public:
  static constexpr JointType kType = JointType::Universal;
  static constexpr int kRows = 4;

  UniversalJoint(const BodyStates& bodies, const JointDesc& desc);
  void solvePosition(BodyStates& bodies, Real substepSize);
  ConstraintRows<kRows> positionRows(const BodyStates& bodies) const;
  JointError error(const BodyStates& bodies) const;
  JointEnds ends() const { return frames_.ends(); }

 private:
  PointAxisFrames frames_;
  Vector3 axis0InBody_ = Vector3::UnitX();  ///< axis1, in body 0
  Vector3 axis1InBody_ = Vector3::UnitY();  ///< axis2, in body 1
};

}  // namespace pbd
