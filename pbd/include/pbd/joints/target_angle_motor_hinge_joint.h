// Target-angle motor hinge: a hinge whose rotation angle θ about the axis is driven to a set
// point θ* (from `target` or `targetSequence`, clamped to [−π, π] as in the seed).
//
//   C = (c₁ − c₀ ∈ ℝ³,  vec(e)) ∈ ℝ⁶,  e = t⁻¹ ⊗ F₀⁻¹ ⊗ F₁,  t = rotation by θ* about x,
//   w ≥ 0; vec(e) = 0 iff body 1's frame is body 0's frame turned by θ* about the axis.
//   ∇C: point rows as the ball joint; ∂vec(e)/∂θ₁ = ½ (w𝟙 − [vec e]×) R(F₀ t)ᵀ = −∂/∂θ₀.
// That is Simulation.jointModel corrected. jointModel seed (the `pbd` method's default) is the
// seed's: the first rotation row offset instead (C_x = e_x − sin(θ*/2) on the untargeted e,
// the set point f(t − 2h) for the step ending at t); both vanish at θ = θ*, the corrected one
// is regular at |θ*| = π (the seed's Jacobian of e_x is that of the untargeted e, which
// degenerates there). Reference: Deul, Charrier, Bender 2014; PBD TargetAngleMotorHingeJoint.
#pragma once

#include "pbd/joints/joint_common.h"

namespace pbd {

class TargetAngleMotorHingeJoint : public JointDefaults {
 public:
  static constexpr JointType kType = JointType::TargetAngleMotorHinge;
  static constexpr int kRows = 6;

  TargetAngleMotorHingeJoint(const BodyStates& bodies, const JointDesc& desc);
  void updateTarget(Real time);
  void solvePosition(BodyStates& bodies, Real substepSize);
  ConstraintRows<kRows> positionRows(const BodyStates& bodies) const;
  JointError error(const BodyStates& bodies) const;
  JointEnds ends() const { return frames_.ends(); }
  Real currentTarget() const { return angle_; }

 private:
  PointAxisFrames frames_;
  MotorTarget target_;
  JointModel model_ = JointModel::Seed;  ///< the seed's or pbdval's set-point schedule
  Real targetAt(Real time) const {
    return model_ == JointModel::Seed ? target_.seedValueAt(time) : target_.valueAt(time);
  }
  Real angle_ = 0;
};

}  // namespace pbd
