// A ball bouncing on a horizontal plane with a coefficient of restitution e (model
// "bouncing_ball").
//
// Along the plane's normal n (n = −ĝ by default) the centre of mass is at height h above the
// contact height h_c (where the ball touches the plane). Between impacts it flies ballistically
// (h″ = −g_n, g_n = ‖g‖); an impact at speed v_i reverses the normal velocity to e·v_i
// (Newton's law of restitution). Apex heights above h_c form the geometric sequence
//   h_k = e^{2k} h₀,   h₀ = v₁²/(2 g_n) (the apex of the arc ending in the first impact,
//                       the drop height for a ball released at rest),
// flight times 2 e^k v₁/g_n, and for e < 1 the ball comes to rest at
//   t_∞ = t₁ + 2 e v₁ / (g_n (1 − e))   (t₁ the first impact).
// After t_∞ (or once a flight would last less than 1e-12 s) it rests at h_c. The motion along
// the plane keeps the initial tangential velocity (frictionless, or no tangential velocity);
// orientations are given when the ball does not spin (they stay constant).
// Parameters: "body", "ground" (static support; default the only static body), "restitution"
// e ∈ [0, 1] (default the pair's material, Scene::pairMaterial), "contactHeight" h_c = n·x of
// the centre of mass at contact (m; default: the ground box's top face along n + the ball's
// radius), "radius" (default the sphere collision radius), "normal" (default −ĝ).
// Literature: Goldsmith, Impact (1960), ch. 1.
#pragma once

#include <vector>

#include "validation/measure/references/analytic_model.h"

namespace pbdval {

/// h₀ e^{2k}, k = 0 … count − 1.
std::vector<double> bounceApexHeights(double firstApex, double restitution, int count);

class BouncingBallModel : public AnalyticModel {
 public:
  BouncingBallModel(const ModelContext& context, const ReferenceParameters& parameters);
  std::string description() const override;
  std::vector<int> bodies() const override { return {body_}; }
  bool hasRotation() const override { return hasRotation_; }
  void evaluate(State& state) override;

  /// Apex heights above the contact height of the first `count` arcs (the first ends in the
  /// first impact).
  std::vector<double> apexHeights(int count) const;
  double firstImpactTime() const;
  /// t_∞ for e < 1; infinity for e = 1.
  double restTime() const;
  /// Height above h_c and normal velocity at time t ≥ 0.
  std::pair<double, double> normalMotion(double t);

 private:
  int body_ = -1;
  Vector3 normal_;
  double gravity_ = 0, restitution_ = 0, contactHeight_ = 0;
  double height0_ = 0, speed0_ = 0;  ///< initial height above h_c and normal velocity
  bool hasRotation_ = false;
  // The current flight (times are non-decreasing between calls): starts at flightStart_ from
  // flightHeight_ with normal velocity flightSpeed_; resting_ once the bounces die out.
  double flightStart_ = 0, flightHeight_ = 0, flightSpeed_ = 0;
  bool resting_ = false;
};

}  // namespace pbdval
