// Slider (prismatic) joint: body 1 translates along an axis fixed in body 0; the relative
// rotation is locked.
//
//   C = (b·(c₁ − c₀), n·(c₁ − c₀),  vec(e)) ∈ ℝ⁵
//   with c₀ fixed in body 0 and c₁ = x₁ (both at body 1's centre of mass at t = 0), b, n ⟂ the
//   axis (fixed in body 0), e = F₀⁻¹ ⊗ F₁ the relative rotation (w ≥ 0).
//   ∇C: axis rows as in joint_parts::setAxisRow; rotation rows ½ (w𝟙 − [vec e]×) R(F₀)ᵀ.
// The seed projects the centre-of-mass offset onto the plane ⟂ the axis in body 0's frame:
// the same constraint. Reference: Deul, Charrier, Bender 2014; PBD SliderJoint.
#pragma once

#include "pbd/joints/joint_common.h"

namespace pbd {

class SliderJoint : public JointDefaults {
 public:
  static constexpr JointType kType = JointType::Slider;
  static constexpr int kRows = 5;

  SliderJoint(const BodyStates& bodies, const JointDesc& desc);
  void solvePosition(BodyStates& bodies, Real substepSize);
  ConstraintRows<kRows> positionRows(const BodyStates& bodies) const;
  JointError error(const BodyStates& bodies) const;
  JointEnds ends() const { return frames_.ends(); }
  const PointAxisFrames& frames() const { return frames_; }

 private:
  PointAxisFrames frames_;
};

}  // namespace pbd
