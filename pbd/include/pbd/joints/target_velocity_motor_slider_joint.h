// Target-velocity motor slider: a slider (position level, 5 rows, see slider_joint.h) whose
// axial velocity is driven to v* in the velocity pass.
//
// Simulation.jointModel corrected (pbd.xpbd's default): velocity rows (6) the time derivatives
// of (a·d, b·d, n·d) (same Jacobians as the axis rows, d = c₁ − c₀) with targets (v*, 0, 0), and
// ω₁ − ω₀ = 0 (B₀ = −𝟙, B₁ = 𝟙): J is the exact derivative of the position rows, K = J M⁻¹ Jᵀ.
// jointModel seed (the `pbd` method's default), as PositionBasedDynamics:
//   position (solve_SliderJoint): the slider's rows with the two linear rows' rotational
//   Jacobians left out (they move the centres of mass only, as the seed's damper);
//   velocity (velocitySolve_TargetVelocityMotorSliderJoint): C = (v₀ − v₁ + v* a, ω₀ − ω₁),
//   the centres of mass' velocities (docs/seed.md#velocity-motors), solved with
//   K = diag((w₀ + w₁) 𝟙, t (I₀⁻¹ + I₁⁻¹) tᵀ), t the rotation rows' Jacobian of the position
//   constraint in the seed's joint frame (frame x = a, y = a × v, z = a × y with v = e_x, or
//   e_y when |a·e_x| > 0.99), and Δω₀ = I₀⁻¹ λ, Δω₁ = −I₁⁻¹ λ: the angular K is not the rows'
//   (it would be I₀⁻¹ + I₁⁻¹), so the angular rows do not close ω₁ − ω₀ in one solve. Both
//   models agree while ω₀ = ω₁ = 0 and body 0 cannot rotate.
// v* > 0 moves body 1 along +axis relative to body 0.
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
  void solvePosition(BodyStates& bodies, Real substepSize);
  void solveVelocity(BodyStates& bodies);
  ConstraintRows<kRows> positionRows(const BodyStates& bodies) const;
  JointError error(const BodyStates& bodies) const { return slider_.error(bodies); }
  JointEnds ends() const { return slider_.ends(); }
  Real currentTarget() const { return velocity_; }

 private:
  void solveVelocitySeed(BodyStates& bodies);

  SliderJoint slider_;
  MotorTarget target_;
  JointModel model_ = JointModel::Seed;  ///< the seed's or pbdval's rows and set-point schedule
  Real targetAt(Real time) const {
    return model_ == JointModel::Seed ? target_.seedValueAt(time) : target_.valueAt(time);
  }
  Real velocity_ = 0;
  /// Seed model: the seed's joint frame in body 0 and in body 1 (both the same world frame at
  /// t = 0), which its angular K depends on.
  joint_parts::LocalFrame seedFrame0_, seedFrame1_;
};

}  // namespace pbd
