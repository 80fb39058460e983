// Ball-on-line joint: body 1's anchor point stays on a line fixed in body 0 (through the
// scene's `position`, direction `axis`); rotation is free.
//
//   C = (b·(c₁ − c₀), n·(c₁ − c₀)) ∈ ℝ², b, n ⟂ axis, fixed in body 0
//   ∇C per row (direction d): A₀ = −dᵀ, B₀ = (d × (c₁ − x₀))ᵀ, A₁ = dᵀ, B₁ = (r₁ × d)ᵀ
// The seed moves c₀ to the point of the line closest to c₁ in `update`; C above measures the
// same offset (the component along the line does not enter), so the constraint is the same.
// Reference: Deul, Charrier, Bender 2014, §4.2; PositionBasedDynamics BallOnLineJoint.
#pragma once

#include "pbd/joints/joint_common.h"

namespace pbd {

class BallOnLineJoint : public JointDefaults {
 public:
  static constexpr JointType kType = JointType::BallOnLine;
  static constexpr int kRows = 2;

  BallOnLineJoint(const BodyStates& bodies, const JointDesc& desc);
  void solvePosition(BodyStates& bodies, Real substepSize);
  ConstraintRows<kRows> positionRows(const BodyStates& bodies) const;
  JointError error(const BodyStates& bodies) const;
  JointEnds ends() const { return frames_.ends(); }

 private:
  PointAxisFrames frames_;
};

}  // namespace pbd
