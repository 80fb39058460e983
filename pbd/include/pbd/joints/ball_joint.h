// Ball joint: two bodies share a point and rotate freely about it.
//
//   C = c₁ − c₀ ∈ ℝ³ (anchors at the scene's `position`)
//   ∇C: A₀ = −𝟙, B₀ = [r₀]×, A₁ = 𝟙, B₁ = −[r₁]×
// Solved as one 3×3 Newton step (K₀ + K₁) Δλ = −C, K_k = w_k 𝟙 − [r_k]× J_k [r_k]×, by the
// direct point-constraint solve of point_constraint.h (the rows below are the same C and ∇C,
// for the error, the tests and the generic solver).
// Reference: Deul, Charrier, Bender 2014, "Position-based rigid-body dynamics", §4.2.
#pragma once

#include "pbd/joints/joint_common.h"
#include "pbd/joints/point_constraint.h"

namespace pbd {

class BallJoint : public JointDefaults {
 public:
  static constexpr JointType kType = JointType::Ball;
  static constexpr int kRows = 3;

  BallJoint(const BodyStates& bodies, const JointDesc& desc);
  void solvePosition(BodyStates& bodies, Real substepSize);
  /// XPBD: one projection with compliance α̃ = α/h² and the accumulated λ, along the
  /// constraint directions `directions` take; returns Δλ.
  /// Defined here so that the XPBD joint loop calls the point-constraint solve directly.
  Vector3 solvePositionCompliant(BodyStates& bodies, Real complianceTilde, const Vector3& lambda,
                                 JointDirections directions) {
    return projectPointConstraint(bodies.rigid, frames_.body0, frames_.body1,
                                  frames_.anchor0.inBody, frames_.anchor1.inBody, complianceTilde,
                                  lambda, directions);
  }
  ConstraintRows<kRows> positionRows(const BodyStates& bodies) const;
  JointError error(const BodyStates& bodies) const;
  JointEnds ends() const { return frames_.ends(); }
  const PointAxisFrames& frames() const { return frames_; }

 private:
  PointAxisFrames frames_;
};

}  // namespace pbd
