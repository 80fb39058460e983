// Target-velocity motor hinge: a hinge (position level, 5 rows, see hinge_joint.h) whose
// relative angular velocity about the axis is driven to ω* in the velocity pass.
//
// Velocity rows (6): J v = (v₁ + ω₁ × r₁ − v₀ − ω₀ × r₀,  ω₁ − ω₀) with targets (0, ω* a),
// a = the axis of body 0's joint frame; J's point rows are the ball joint's Jacobian, the
// angular rows B₀ = −𝟙, B₁ = 𝟙. One 6×6 solve per velocity iteration.
// The seed uses centre-of-mass velocities for the linear rows while its K uses connector
// matrices (docs/seed.md#velocity-motors): Simulation.jointModel seed (the `pbd` method's default)
// does the same (the linear rows' target ω₁ × r₁ − ω₀ × r₀ turns J v into v₁ − v₀);
// jointModel corrected keeps J and K consistent (connector velocities).
// Reference: PositionBasedDynamics TargetVelocityMotorHingeJoint.
#pragma once

#include "pbd/joints/hinge_joint.h"

namespace pbd {

class TargetVelocityMotorHingeJoint : public JointDefaults {
 public:
  static constexpr JointType kType = JointType::TargetVelocityMotorHinge;
  static constexpr int kRows = HingeJoint::kRows;
  static constexpr int kVelocityRows = 6;

  TargetVelocityMotorHingeJoint(const BodyStates& bodies, const JointDesc& desc);
  void updateTarget(Real time) { angularVelocity_ = targetAt(time); }
  void solvePosition(BodyStates& bodies, Real substepSize) {
    hinge_.solvePosition(bodies, substepSize);
  }
  void solveVelocity(BodyStates& bodies);
  ConstraintRows<kRows> positionRows(const BodyStates& bodies) const {
    return hinge_.positionRows(bodies);
  }
  JointError error(const BodyStates& bodies) const { return hinge_.error(bodies); }
  JointEnds ends() const { return hinge_.ends(); }
  Real currentTarget() const { return angularVelocity_; }

 private:
  HingeJoint hinge_;
  MotorTarget target_;
  JointModel model_ = JointModel::Seed;  ///< the seed's or pbdval's set-point schedule
  Real targetAt(Real time) const {
    return model_ == JointModel::Seed ? target_.seedValueAt(time) : target_.valueAt(time);
  }
  Real angularVelocity_ = 0;
};

}  // namespace pbd
