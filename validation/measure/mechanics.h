// Mechanical quantities of a state, from the Scene's masses and inertias only (never from an
// engine): energy terms, momenta, the initial state, and the default scales of the drift
// metrics. Formulas: docs/metrics.md §Energy and §Momentum.
//
// Conventions: State::bodies are in Scene::rigidBodies order; BodyState::rotation maps the
// body's scene frame to the world; a body's world inertia about its centre of mass is
//   I_w = R R_p diag(I₁, I₂, I₃) R_pᵀ Rᵀ,
// R the read-back rotation, R_p = massProperties.principalRotation (principal → scene frame).
// Static bodies carry no energy or momentum; particles of mass 0 are static. Rod segments
// (State::segments, when read back) carry the rotational kinetic energy ½ |ω|²/(4 w_q) and no
// momentum here.
#pragma once

#include "adapters/engine.h"
#include "validation/measure/deformation.h"
#include "validation/run/case_spec.h"

namespace pbdval {

using pbd::Matrix3;

/// I_w of `body` when its scene frame is at `sceneRotation`.
Matrix3 worldInertia(const pbd::RigidBodyDesc& body, const Quaternion& sceneRotation);

/// The state at t = 0 as the Scene describes it (centre of mass, scene-frame rotation and
/// velocities of every body; particle positions and velocities; rod segments in their rest
/// frames, at rest).
State initialState(const pbd::Scene& scene);

/// Throws std::invalid_argument unless `state` holds the Scene's bodies (count and ids, in
/// order), either no particles or all of them, and either no rod segments or all of them.
void checkStateMatchesScene(const pbd::Scene& scene, const State& state);

struct EnergyTerms {
  double translational = 0;  ///< Σ ½ m ‖v‖² (bodies and particles), J
  double rotational = 0;  ///< Σ ½ ωᵀ I_w ω (bodies) + Σ ½ |ω|²/(4 w_q) (rod segments), J
  double gravitational = 0;  ///< Σ −m g·x (bodies' centres of mass and particles), J
  double spring = 0;  ///< RigidBodySprings ½ k (ℓ − ℓ₀)², DamperJoints ½ k s², stiff rods, J
  double elastic = 0;  ///< the XPBD particle constraints' and rods' energy (ElasticEnergy), J
  double kinetic() const { return translational + rotational; }
  double total() const { return translational + rotational + gravitational + spring + elastic; }
};

/// The energy of `state`; g = Simulation.gravitation. Particles enter only when the state
/// holds them. The first form collects the scene's particle constraints on every call; pass
/// an ElasticEnergy built once when measuring many states.
EnergyTerms energyOf(const pbd::Scene& scene, const State& state);
EnergyTerms energyOf(const pbd::Scene& scene, const State& state, const ElasticEnergy& elastic);

struct Momenta {
  double mass = 0;                         ///< M, kg (dynamic bodies and particles)
  Vector3 centerOfMass = Vector3::Zero();  ///< c = Σ m x / M
  Vector3 linear = Vector3::Zero();        ///< P = Σ m v, kg m/s
  /// L = Σ [(x − c) × m v + I_w ω] about the system centre of mass c, kg m²/s.
  Vector3 angular = Vector3::Zero();
};

Momenta momentaOf(const pbd::Scene& scene, const State& state);

/// The largest principal moment of the system's inertia tensor about its centre of mass,
/// Σ [I_w + m (‖r‖² 𝟙 − r rᵀ)], r = x − c (kg m²).
double systemInertia(const pbd::Scene& scene, const State& state);

/// Default E_ref (J): the kinetic energy of the Scene's initial state + M ‖g‖ · 1 m + the
/// spring energy at t = 0 (zero for springs at rest). Never E(0) alone, which may be ~0.
/// Returns 0 when all three vanish (the caller then falls back to 1 J).
double defaultEnergyScale(const pbd::Scene& scene);

/// E_ref used by the drift metrics: Validation.energyScale, else defaultEnergyScale, else
/// 1 J. `note` (when given) receives how it was chosen.
double energyScale(const pbd::Scene& scene, const CaseSpec& spec, std::string* note = nullptr);

struct MomentumScales {
  double linear = 0;   ///< max(‖P₀‖, √(2 M E_ref)), kg m/s
  double angular = 0;  ///< max(‖L₀‖, √(2 I_sys E_ref)), kg m²/s
};

/// The normalisation of the momentum drifts, from the Scene's initial state.
MomentumScales momentumScales(const pbd::Scene& scene, double energyScale);

}  // namespace pbdval
