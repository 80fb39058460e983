// MuJoCo's contacts are soft: the solver drives the penetration r toward the reference
// acceleration a_ref = −b ṙ − k r (MuJoCo computation chapter, "solref"). With the direct
// format solref = (−stiffness, −damping) and a constant impedance d (solimp d₀ = d_width = d),
// the impedance-weighted law is exactly a damped oscillator
//   d · a_ref = −damping · ṙ − stiffness · r,
// so a contact is a mass-normalised Kelvin–Voigt spring: ω = √stiffness, ζ = damping / (2ω).
// The adapter fixes ω = 1/τ (τ the contact time constant) and chooses ζ from the pair's
// coefficient of restitution e.
//
// Restitution of a Kelvin–Voigt contact (Schwager & Pöschel 2007, "Coefficient of restitution
// and linear dashpot model revisited", Granular Matter 9): the contact ends when the force
// 2ζω ẋ + ω² x reaches zero (it cannot pull), and then
//   e(ζ) = exp(−ζ φ / √(1 − ζ²)),        φ = atan2(2ζ√(1 − ζ²), 2ζ² − 1)     (ζ < 1),
//   e(1) = e⁻²,
//   e(ζ) = exp(−ζ ψ / √(ζ² − 1)),        ψ = ln((ζ + √(ζ² − 1)) / (ζ − √(ζ² − 1)))   (ζ > 1).
// e falls monotonically from 1 (ζ = 0) to 0 (ζ → ∞), so ζ(e) is found by bisection. The
// damping is explicit in MuJoCo's time stepping; above damping · h = 1 a step would reverse
// the normal velocity, so ζ is capped at ζ_max = τ/(2h) and smaller e are clamped to e(ζ_max)
// (0.048 for τ = 4h; the rebound measured in discrete time is smaller still).
#pragma once

namespace pbdval::mujoco {

/// e(ζ) of a linear spring-dashpot contact that releases when its force vanishes.
double restitutionOfDampingRatio(double dampingRatio);

/// The damping ratio ζ ∈ [0, maxDampingRatio] with e(ζ) = restitution, or maxDampingRatio
/// when restitution < e(maxDampingRatio).
double dampingRatioForRestitution(double restitution, double maxDampingRatio);

/// solref in MuJoCo's direct format for one contact pair.
struct DirectSolref {
  double stiffness = 0;  ///< 1/τ² (1/s²)
  double damping = 0;    ///< 2ζ/τ (1/s)
  double dampingRatio = 0;
};

/// The contact law for time constant τ, step h and restitution e (see the file comment).
DirectSolref contactSolref(double timeConstant, double stepSize, double restitution);

}  // namespace pbdval::mujoco
