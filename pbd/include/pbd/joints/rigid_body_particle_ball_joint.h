// Ball joint between a rigid body and a particle: the body's anchor (at the particle's
// position at t = 0) follows the particle.
//
//   C = x_p − c ∈ ℝ³
//   ∇C: rigid end A₀ = −𝟙, B₀ = [r]×; particle end A₁ = 𝟙 (no rotation)
//   K = w_rb 𝟙 − [r]× J [r]× + w_p 𝟙, one 3×3 Newton step as in the seed.
// Reference: PositionBasedDynamics RigidBodyParticleBallJoint.
#pragma once

#include "pbd/joints/joint_common.h"

namespace pbd {

class RigidBodyParticleBallJoint : public JointDefaults {
 public:
  static constexpr JointType kType = JointType::RigidBodyParticleBall;
  static constexpr int kRows = 3;

  RigidBodyParticleBallJoint(const BodyStates& bodies, const JointDesc& desc);
  void solvePosition(BodyStates& bodies, Real substepSize);
  ConstraintRows<kRows> positionRows(const BodyStates& bodies) const;
  JointError error(const BodyStates& bodies) const;
  JointEnds ends() const { return {body_, -1, particle_}; }

 private:
  int body_ = -1;
  int particle_ = -1;
  joint_parts::LocalAnchor anchor_;
};

}  // namespace pbd
