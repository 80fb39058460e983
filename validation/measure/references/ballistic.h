// Ballistic motion under constant gravity (models "projectile" and "free_fall").
//
// Continuous:           x(t) = x₀ + v₀ t + ½ g t²,          v(t) = v₀ + g t.
// Semi-implicit Euler with step h (v_{k+1} = v_k + h g, x_{k+1} = x_k + h v_{k+1}):
//   x_k = x₀ + k h v₀ + ½ g h² k (k + 1)  ⇔  x(t) = x₀ + v₀ t + ½ g t (t + h)  at t = k h,
//   v(t) = v₀ + g t: a bias of ½ g h t against the parabola (Hairer, Lubich, Wanner,
//   "Geometric Numerical Integration", 2nd ed., 2006, §I.1; docs/references.md, "projectile").
// The centre of mass of every described body (Validation.reference.bodies, else every dynamic
// body) follows it independently; no contact. Orientations are given only when every
// described body starts without spin (they then stay constant); a spinning body's rotation is
// the torque-free models' business.
// Parameters: "form": "continuous" (default) | "semi_implicit_euler" (h = the run's effective
// integration step: timeStepSize / subSteps for PBD).
// Literature: any mechanics text; Erez, Tassa, Todorov 2015 (ballistic sanity check).
#pragma once

#include "validation/measure/references/analytic_model.h"

namespace pbdval {

class BallisticModel : public AnalyticModel {
 public:
  BallisticModel(const ModelContext& context, const ReferenceParameters& parameters);
  std::string description() const override;
  std::vector<int> bodies() const override { return bodies_; }
  bool hasRotation() const override { return hasRotation_; }
  void evaluate(State& state) override;

  /// x(t) of a point mass from x₀, v₀ under g; `step` = 0: continuous, else semi-implicit Euler.
  static Vector3 position(const Vector3& x0, const Vector3& v0, const Vector3& g, double t,
                          double step);

 private:
  std::vector<int> bodies_;
  Vector3 gravity_;
  double step_ = 0;  ///< 0: continuous
  bool hasRotation_ = false;
};

}  // namespace pbdval
