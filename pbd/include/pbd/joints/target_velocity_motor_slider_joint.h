// Target-velocity motor slider: a slider (position level, 5 rows, see slider_joint.h) whose
// axial velocity is driven to v* in the velocity pass.
//
// Velocity rows (6): the time derivatives of (a·d, b·d, n·d) (same Jacobians as the axis
// rows, d = c₁ − c₀) with targets (v*, 0, 0), and ω₁ − ω₀ = 0 (B₀ = −𝟙, B₁ = 𝟙).
// v* > 0 moves body 1 along +axis relative to body 0. The seed uses centre-of-mass velocities
// (docs/seed.md#velocity-motors); here J is the exact derivative of the position rows.
// Reference: PositionBasedDynamics TargetVelocityMotorSliderJoint.
#pragma once

#include "pbd/joints/slider_joint.h"

namespace pbd {

class TargetVelocityMotorSliderJoint : public JointDefaults {
 public:
  static constexpr JointType kType = JointType::TargetVelocityMotorSlider;
  static constexpr int kRows = SliderJoint::kRows;
  static constexpr int kVelocityRows = 6;

  TargetVelocityMotorSliderJoint(const BodyStates& bodies, const JointDesc& desc);
  void updateTarget(Real time) { velocity_ = targetAt(time); }
  void solvePosition(BodyStates& bodies, Real substepSize) {
    slider_.solvePosition(bodies, substepSize);
  }
  void solveVelocity(BodyStates& bodies);
  ConstraintRows<kRows> positionRows(const BodyStates& bodies) const {
    return slider_.positionRows(bodies);
  }
  JointError error(const BodyStates& bodies) const { return slider_.error(bodies); }
  JointEnds ends() const { return slider_.ends(); }
  Real currentTarget() const { return velocity_; }

 private:
  SliderJoint slider_;
  MotorTarget target_;
  JointModel model_ = JointModel::Seed;  ///< the seed's or pbdval's set-point schedule
  Real targetAt(Real time) const {
    return model_ == JointModel::Seed ? target_.seedValueAt(time) : target_.valueAt(time);
  }
  Real velocity_ = 0;
};

}  // namespace pbd
