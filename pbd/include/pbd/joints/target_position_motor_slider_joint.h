// Target-position motor slider: a slider whose axial offset is driven to a set point s*.
//
//   C = (a·d − s*, b·d, n·d,  vec(e)) ∈ ℝ⁶,  d = c₁ − c₀ (both at body 1's centre of mass at
//   t = 0), (a, b, n) body 0's joint frame (a = axis), e = F₀⁻¹ ⊗ F₁ (w ≥ 0).
//   ∇C: axis rows (joint_parts::setAxisRow) and rotation rows ½ (w𝟙 − [vec e]×) R(F₀)ᵀ.
// s* > 0 moves body 1 along +axis relative to body 0. The seed stores the initial offset in
// world coordinates and never rotates it with body 0 (docs/seed.md#position-motor-slider-offset);
// here it is fixed in body 0. Reference: PositionBasedDynamics TargetPositionMotorSliderJoint.
#pragma once

#include "pbd/joints/joint_common.h"

namespace pbd {

class TargetPositionMotorSliderJoint : public JointDefaults {
 public:
  static constexpr JointType kType = JointType::TargetPositionMotorSlider;
  static constexpr int kRows = 6;

  TargetPositionMotorSliderJoint(const BodyStates& bodies, const JointDesc& desc);
  void updateTarget(Real time) { offset_ = targetAt(time); }
  void solvePosition(BodyStates& bodies, Real substepSize);
  ConstraintRows<kRows> positionRows(const BodyStates& bodies) const;
  JointError error(const BodyStates& bodies) const;
  JointEnds ends() const { return frames_.ends(); }
  Real currentTarget() const { return offset_; }

 private:
  PointAxisFrames frames_;
  MotorTarget target_;
  JointModel model_ = JointModel::Seed;  ///< the seed's or pbdval's set-point schedule
  Real targetAt(Real time) const {
    return model_ == JointModel::Seed ? target_.seedValueAt(time) : target_.valueAt(time);
  }
  Real offset_ = 0;
};

}  // namespace pbd
