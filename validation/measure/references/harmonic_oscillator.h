// Harmonic oscillator: a body on a spring to a static body (model "harmonic_oscillator").
//
// Along the unit direction u the body of mass m obeys m s″ = −k s + m (g·u), s(0) = 0,
// s′(0) = u₀ = v₀·u:
//   s(t) = s_eq (1 − cos ω t) + (u₀/ω) sin ω t,   s′(t) = s_eq ω sin ω t + u₀ cos ω t,
//   ω = √(k/m),  s_eq = (g·u)/ω²;   x(t) = x₀ + s(t) u,  v(t) = s′(t) u,  R(t) = R(0).
// DamperJoints (an axial spring in the seed): u = the joint axis, the slider holds the rest;
//   body 0 (bodyID1) must be static.
// RigidBodySprings: u = (c_dyn − c_static)/L from the connectors at t = 0 (L = rest length,
//   one end static); the motion stays on the line only when gravity and v₀ are along u, the
//   body does not spin and its connector lies on the line through its centre of mass (all
//   checked), and the spring never reaches zero length (L + s_eq − A > 0, A = √(s_eq² + (u₀/ω)²),
//   checked).
// Parameters: "joint": the joint's JSON path ("DamperJoints[0]", "RigidBodySprings[0]"),
// default the scene's only spring or damper joint.
// Literature: Landau & Lifshitz, Mechanics §21; Gazebo test/accuracy/joints (1-DOF + spring).
#pragma once

#include "validation/measure/references/analytic_model.h"

namespace pbdval {

class HarmonicOscillatorModel : public AnalyticModel {
 public:
  HarmonicOscillatorModel(const ModelContext& context, const ReferenceParameters& parameters);
  std::string description() const override;
  std::vector<int> bodies() const override { return {body_}; }
  bool hasRotation() const override { return true; }
  void evaluate(State& state) override;

  double angularFrequency() const { return omega_; }      ///< ω, rad/s
  double equilibriumOffset() const { return offsetEq_; }  ///< s_eq, m
  /// s(t) along the direction (m).
  double offset(double t) const;

 private:
  int body_ = -1;
  std::string jointPath_;
  Vector3 direction_ = Vector3::UnitY();
  double omega_ = 0, offsetEq_ = 0, speed0_ = 0;
};

}  // namespace pbdval
