// Target-position motor slider: a slider whose axial offset is driven to a set point s*.
//
// Simulation.jointModel corrected (pbd.xpbd's default):
//   C = (a·d − s*, b·d, n·d,  vec(e)) ∈ ℝ⁶,  d = c₁ − c₀ (both at body 1's centre of mass at
//   t = 0), (a, b, n) body 0's joint frame (a = axis), e = F₀⁻¹ ⊗ F₁ (w ≥ 0).
//   ∇C: axis rows (joint_parts::setAxisRow) and rotation rows ½ (w𝟙 − [vec e]×) R(F₀)ᵀ.
//   The offset is fixed in body 0, and the linear rows carry their rotational Jacobians.
// jointModel seed (the `pbd` method's default), as PositionBasedDynamics'
// solve_TargetPositionMotorSliderJoint:
//   C = (x₁ − x₀) + d₀ − s* a  (3 world rows) and the same rotation rows, with d₀ = x₀ − x₁ at
//   t = 0 in world coordinates, never rotated with body 0
//   (docs/seed.md#position-motor-slider-offset), and a the axis rotating with body 0; the linear
//   Jacobians are (−𝟙, 0) and (𝟙, 0): the linear correction moves the centres of mass only. (The
//   seed writes C with the opposite sign; the projection is the same.) Both models agree while body
//   0 cannot rotate.
// s* > 0 moves body 1 along +axis relative to body 0.
// Reference: PositionBasedDynamics TargetPositionMotorSliderJoint.
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
  JointModel model_ = JointModel::Seed;  ///< the seed's or pbdval's rows and set-point schedule
  Real targetAt(Real time) const {
    return model_ == JointModel::Seed ? target_.seedValueAt(time) : target_.valueAt(time);
  }
  Real offset_ = 0;
  Vector3 initialOffset_ = Vector3::Zero();  ///< seed model: x₀ − x₁ at t = 0, world
};

}  // namespace pbd
