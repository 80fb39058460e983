// Plane pendulum about a fixed axis (models "pendulum" and "simple_pendulum").
//
// A body swings about the axis a through the pivot p. With r⊥ the offset of its centre of
// mass from the axis (d = ‖r⊥‖), g⊥ = g − (g·a) a and θ the angle of r⊥ from g⊥ about a:
//   I_p θ″ = −m d ‖g⊥‖ sin θ,   Ω₀² = m d ‖g⊥‖ / I_p,
//   physical pendulum:  I_p = aᵀ I_w a + m d² (parallel-axis theorem; the Scene's inertia),
//   simple pendulum:    I_p = m d² (a point mass on a massless rod).
// θ(t) is integrated with classical RK4 at a step of 1/10⁴ of the fastest time scale,
// 2π/max(Ω₀, |θ′|_max) (parameter rk4Step overrides it); RK4's global error is O(h⁴), here
// ~10⁻¹² rad per period. The body turns rigidly about the axis:
//   R(t) = Rot(a, θ − θ₀) R(0),  x(t) = p + Rot(a, θ − θ₀)(x₀ − p),  ω = θ′ a,  v = ω × (x − p).
// Period of libration with amplitude θ_max (cos θ_max = cos θ₀ − θ′₀²/(2Ω₀²) > −1):
//   T = 4 K(k) / Ω₀,  k = sin(θ_max/2),  K the complete elliptic integral of the first kind,
//   K(k) = π / (2 AGM(1, √(1 − k²)))  (Abramowitz & Stegun 17.6; Landau & Lifshitz,
//   Mechanics §11, problem 1 for the pendulum).
// Parameters: "body" (scene id), "pivot" [x,y,z] and "axis" [x,y,z] (world, t = 0) — both
// default to the one hinge (its position and axis), ball joint (its position; axis ω̂₀, or
// the normal of the plane of r and g when at rest) or rigid-body–particle ball joint on a
// static particle that ties the body to something static; "rk4Step" (s).
// Validity: the initial motion must be a rotation about the axis (ω₀ ∥ a, v₀ = ω₀ × (x₀ − p),
// checked); for a ball joint the motion stays planar only when a is a principal axis of the
// body's inertia about the pivot (not checked: the reference then describes the planar case).
#pragma once

#include <optional>

#include "validation/measure/references/analytic_model.h"

namespace pbdval {

/// K(k) = ∫₀^{π/2} dφ / √(1 − k² sin²φ), 0 ≤ k < 1, by the arithmetic–geometric mean.
double completeEllipticK(double modulus);

/// Period of a pendulum of small-amplitude angular frequency Ω₀ swinging to ±θ_max (< π).
double pendulumPeriod(double naturalFrequency, double amplitude);

class PendulumModel : public AnalyticModel {
 public:
  PendulumModel(const ModelContext& context, const ReferenceParameters& parameters, bool pointMass);
  std::string description() const override;
  std::vector<int> bodies() const override { return {body_}; }
  bool hasRotation() const override { return true; }
  void evaluate(State& state) override;

  double naturalFrequency() const { return omega0_; }  ///< Ω₀, rad/s
  double initialAngle() const { return theta0_; }      ///< θ₀, rad (from the downward g⊥)
  /// The libration period, or none when the pendulum goes over the top (or has no g⊥).
  std::optional<double> period() const;
  double angle() const { return theta_; }  ///< θ at the last evaluated time

 private:
  void advanceTo(double time);

  bool pointMass_ = false;
  int body_ = -1;
  Vector3 pivot_, axis_, offset0_;  ///< p, a, x₀ − p
  Quaternion rotation0_;
  double omega0_ = 0;                       ///< Ω₀
  double theta0_ = 0, rate0_ = 0;           ///< θ₀, θ′₀
  double maxStep_ = 0;                      ///< RK4 step bound
  double time_ = 0, theta_ = 0, rate_ = 0;  ///< integrated state
};

}  // namespace pbdval
