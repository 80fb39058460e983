// Torque-free rigid bodies (models "torque_free_symmetric" and "torque_free_asymmetric").
// Gravity acts on the centre of mass only: x(t) = x₀ + v₀ t + ½ g t² for both.
//
// Symmetric body (principal moments I₁ = I₂ ≠ I₃ about the symmetry axis e₃ of the principal
// frame; any axis for a sphere). With the principal frame's orientation P(0), body-frame
// angular velocity ω_b(0) = P(0)ᵀ ω₀, world angular momentum L = P(0) I ω_b(0) (constant):
//   ω_b(t) = Rot(e₃, Ω t) ω_b(0),  Ω = (I₃ − I₁)/I₁ · ω₃  (body-frame ω precesses about e₃),
//   P(t)   = Rot(L̂, ‖L‖ t / I₁) · P(0) · Rot(e₃, −Ω t)   (the symmetry axis precesses about L
//            at ‖L‖/I₁ while the body spins relative to it),
//   scene-frame rotation R(t) = P(t) R_pᵀ (R_p: principal → scene frame), ω(t) = P(t) ω_b(t).
// Derivation: with P = A P(0) B, A = Rot(L̂, φ̇ t), B = Rot(e₃, ψ̇ t), the body-frame momentum
// I (φ̇ P⁻¹L̂ + ψ̇ e₃) = ‖L‖ P⁻¹L̂ gives φ̇ = ‖L‖/I₁ and ψ̇ = −Ω. Literature: Landau & Lifshitz,
// Mechanics §33 (free symmetric top); Kane & Levinson, Spacecraft Dynamics §1.13 (Drake's
// free_body benchmark). The two equal moments must agree to the relative tolerance
// "symmetryTolerance" (default 1e-6; their mean is used), else the model refuses the body.
//
// Asymmetric body: no elementary closed form for the orientation (ω_b(t) is given by Jacobi
// elliptic functions, the orientation needs theta functions). The reference gives the centre
// of mass exactly and no orientation; the checks for the rotation are the conserved-quantity
// metrics (energy_drift_*, momentum_angular_drift_max with Validation.energyConserved and
// angularMomentumConserved). With "integrateRotation": true it integrates Euler's equations
// I ω̇_b = (I ω_b) × ω_b and Ṗ = P [ω_b]× with RK4 at 1/10⁴ of 2π I_min/‖L‖ ("rk4Step"
// overrides) and gives that orientation — near the intermediate axis the motion is unstable
// (Dzhanibekov), so long horizons amplify any error, the reference's included.
// Parameters: "symmetryTolerance" (symmetric); "integrateRotation", "rk4Step" (asymmetric).
// The models describe Validation.reference.bodies, else every dynamic body.
#pragma once

#include "validation/measure/references/analytic_model.h"

namespace pbdval {

/// Principal-frame orientation of a symmetric top at time t (see the header comment).
/// `moments` are the principal moments, `symmetryAxis` the index (0–2) of e₃.
Quaternion symmetricTopOrientation(const Quaternion& principal0, const Vector3& moments,
                                   int symmetryAxis, const Vector3& bodyOmega0, double t);

class SymmetricTorqueFreeModel : public AnalyticModel {
 public:
  SymmetricTorqueFreeModel(const ModelContext& context, const ReferenceParameters& parameters);
  std::string description() const override;
  std::vector<int> bodies() const override { return bodies_; }
  bool hasRotation() const override { return true; }
  void evaluate(State& state) override;

 private:
  struct Top {
    int body = -1;
    int symmetryAxis = 2;
    Vector3 moments;              ///< with the two equal ones replaced by their mean
    Quaternion principal0;        ///< P(0)
    Quaternion principalInScene;  ///< R_p
    Vector3 bodyOmega0;
    double precessionRate = 0;  ///< Ω
  };
  Vector3 gravity_;
  std::vector<int> bodies_;
  std::vector<Top> tops_;
};

class AsymmetricTorqueFreeModel : public AnalyticModel {
 public:
  AsymmetricTorqueFreeModel(const ModelContext& context, const ReferenceParameters& parameters);
  std::string description() const override;
  std::vector<int> bodies() const override { return bodies_; }
  bool hasRotation() const override { return integrateRotation_; }
  void evaluate(State& state) override;

 private:
  struct Spinner {
    int body = -1;
    Vector3 moments;
    Quaternion principalInScene;
    double maxStep = 0;
    double time = 0;
    Quaternion principal;  ///< P(time)
    Vector3 bodyOmega;     ///< ω_b(time)
    Quaternion principal0;
    Vector3 bodyOmega0;
  };
  void advance(Spinner& s, double time) const;

  Vector3 gravity_;
  std::vector<int> bodies_;
  bool integrateRotation_ = false;
  std::vector<Spinner> spinners_;
};

}  // namespace pbdval
