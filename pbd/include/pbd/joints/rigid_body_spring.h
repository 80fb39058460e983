// Rigid-body spring: an XPBD distance constraint between the connectors c₀ (`position1`,
// fixed in body 0) and c₁ (`position2`, fixed in body 1), stiffness k in N/m, rest length
// L = ‖position2 − position1‖ at t = 0.
//
//   C = ‖c₁ − c₀‖ − L,  ∇C as the distance joint,
//   α̃ = 1/(k h²) with h the substep size, Δλ = (−C − α̃ λ)/(∇C M⁻¹ ∇Cᵀ + α̃), λ reset at the
//   start of every substep (as in the seed). Potential energy ½ k C².
// Reference: Macklin, Müller, Chentanez 2016, "XPBD", eq. 18; PBD RigidBodySpring.
#pragma once

#include "pbd/joints/joint_common.h"

namespace pbd {

class RigidBodySpring : public JointDefaults {
 public:
  static constexpr JointType kType = JointType::RigidBodySpring;
  static constexpr int kRows = 1;

  RigidBodySpring(const BodyStates& bodies, const JointDesc& desc);
  void beginSubstep(Real substepSize);
  void solvePosition(BodyStates& bodies, Real substepSize);
  ConstraintRows<kRows> positionRows(const BodyStates& bodies) const;
  /// A spring has no hard constraint: its error is zero; its extension is positionRows().value.
  JointError error(const BodyStates& bodies) const;
  JointEnds ends() const { return connectors_.ends(); }
  Real stiffness() const { return stiffness_; }  ///< N/m

 private:
  ConnectorPair connectors_;
  Real stiffness_ = 0;
  Eigen::Matrix<Real, 1, 1> compliance_ = Eigen::Matrix<Real, 1, 1>::Zero();
  Eigen::Matrix<Real, 1, 1> multiplier_ = Eigen::Matrix<Real, 1, 1>::Zero();
};

}  // namespace pbd
