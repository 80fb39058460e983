// Bodies on a plane with Coulomb friction (models "sliding_block", "rolling_sphere",
// "bowling_ball").
//
// The plane has the unit normal n (pointing to the body); gravity splits into g_n = −g·n > 0
// pressing and g_t = g + g_n n along the plane. Motion is along the unit direction d in the
// plane (d = ĝ_t on an incline; on a flat plane d = the direction of the initial slip), with
// u = v·d, and for a sphere of radius r the spin w = ω·e about e = n × d; the contact point
// slips at σ = u − r w (a block: σ = u, no spin). With κ = m r² / I_e (0 for a block) and the
// friction acceleration f:
//   u′ = g_t + f,   w′ = −f κ / r,   σ′ = g_t + f (1 + κ),       (g_t = g·d ≥ 0 here)
//   sliding:              f = −μ g_n sign(σ)
//   rolling / sticking:   f = −g_t / (1 + κ), possible while |f| ≤ μ g_n, i.e. μ ≥ tan θ · κ/(1+κ)
// (θ the incline angle; a block sticks for μ ≥ tan θ; a solid sphere, κ = 5/2, rolls for
// μ ≥ (2/7) tan θ with u′ = (5/7) g sin θ). A sliding phase whose slip decreases ends at
// t* = |σ₀| / |σ′|; then the body rolls (sticks) or, if friction cannot hold it, slides on
// downhill. Each phase has constant accelerations, so x(t) = x₀ + v⊥ t + s(t) d with s, u
// piecewise quadratic/linear; ω(t) = ω₀ + (w(t) − w₀) e. Orientations are given when ω₀ ∥ e
// (R(t) = Rot(e, ∫w dt) R(0); a block: constant).
// Bowling ball (Drake multibody/benchmarks/bowling_ball; flat plane, any initial v₀ and ω₀):
// the slip keeps its direction, t* = ‖σ₀‖ / (μ g (1 + κ)) with κ = 5/2 for a solid sphere, then
// it rolls at constant velocity.
// Validity (checked): no initial velocity along n; the initial slip along d (on an incline; the
// friction direction would turn otherwise); a block does not spin. The body stays in contact
// and the block does not tip (not checked). Kinetic = static friction (the scenes have one μ).
// Parameters: "body", "ground" (scene id of the static support; default the only static
// body), "normal" [x,y,z] (default the ground's scene-frame +y axis), "friction" μ (default the
// pair's material, Scene::pairMaterial), "radius" (spheres; default the sphere collision
// radius).
// Literature: Goldsmith, Impact (1960), ch. 1 and Drake's inclined_plane / bowling_ball
// benchmarks; Kleppner & Kolenkow, An Introduction to Mechanics, §7.
#pragma once

#include <optional>
#include <vector>

#include "validation/measure/references/analytic_model.h"

namespace pbdval {

/// The 1D motion along d: piecewise-constant accelerations.
class CoulombLineMotion {
 public:
  /// gTangent = g·d ≥ 0, gNormal > 0, friction μ ≥ 0, kappa = m r²/I_e (0: no spin), radius r.
  CoulombLineMotion(double gTangent, double gNormal, double friction, double kappa, double radius,
                    double speed0, double spin0);
  double speed(double t) const;         ///< u(t)
  double displacement(double t) const;  ///< s(t) = ∫₀ᵗ u
  double spin(double t) const;          ///< w(t)
  double spinAngle(double t) const;     ///< ∫₀ᵗ w
  /// When the slip stops (rolling or sticking begins); none when it slides throughout.
  std::optional<double> slipEnd() const { return slipEnd_; }
  bool rollsOrSticks() const { return rolls_; }  ///< after slipEnd (or from the start)

 private:
  struct Phase {
    double start = 0;
    double du = 0, dw = 0;    ///< u′, w′
    double u = 0, w = 0;      ///< at start
    double s = 0, angle = 0;  ///< ∫u, ∫w at start
  };
  const Phase& phaseAt(double t) const;
  /// Appends a phase from `start`, continuing the previous one (the first starts at u₀, w₀).
  void addPhase(double start, double du, double dw, double speed0, double spin0);

  std::vector<Phase> phases_;
  std::optional<double> slipEnd_;
  bool rolls_ = false;
};

class PlaneContactModel : public AnalyticModel {
 public:
  enum class Kind { Block, Sphere, BowlingBall };
  PlaneContactModel(const ModelContext& context, const ReferenceParameters& parameters, Kind kind);
  std::string description() const override;
  std::vector<int> bodies() const override { return {body_}; }
  bool hasRotation() const override { return hasRotation_; }
  void evaluate(State& state) override;

  const CoulombLineMotion& lineMotion() const { return *motion_; }
  double inclineAngle() const { return incline_; }  ///< θ, rad

 private:
  Kind kind_;
  int body_ = -1;
  Vector3 direction_, spinAxis_, crossVelocity_;  ///< d, e, v⊥
  double incline_ = 0, friction_ = 0;
  bool hasRotation_ = false;
  std::optional<CoulombLineMotion> motion_;
};

}  // namespace pbdval
