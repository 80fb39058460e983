// Distance joint: the connectors c₀ (scene `position1`, fixed in body 0) and c₁ (`position2`,
// fixed in body 1) keep their initial distance L = ‖position2 − position1‖.
//
//   C = ‖c₁ − c₀‖ − L ∈ ℝ,  n = (c₁ − c₀)/‖c₁ − c₀‖
//   ∇C: A₀ = −nᵀ, B₀ = −(r₀ × n)ᵀ, A₁ = nᵀ, B₁ = (r₁ × n)ᵀ
// Hard (the seed's solve_DistanceJoint with stiffness 0).
// Reference: PositionBasedDynamics DistanceJoint.
#pragma once

#include "pbd/joints/joint_common.h"

namespace pbd {

class DistanceJoint : public JointDefaults {
 public:
  static constexpr JointType kType = JointType::Distance;
  static constexpr int kRows = 1;

  DistanceJoint(const BodyStates& bodies, const JointDesc& desc);
  void solvePosition(BodyStates& bodies, Real substepSize);
  ConstraintRows<kRows> positionRows(const BodyStates& bodies) const;
  JointError error(const BodyStates& bodies) const;
  JointEnds ends() const { return connectors_.ends(); }

 private:
  ConnectorPair connectors_;
};

}  // namespace pbd
