// Distance between two particles: the edges of a cloth (clothSimulationMethod 1: PBD, 4: XPBD)
// and of a solid (solidSimulationMethod 1: PBD, 6: XPBD, with tet_volume.h).
//
//   C(p₁, p₂) = |p₁ − p₂| − L,   n = (p₁ − p₂)/|p₁ − p₂|,   ∇_{p₁}C = n,   ∇_{p₂}C = −n
// (L the rest length at t = 0; the gradients sum to zero, so w-weighted corrections conserve
// linear momentum, and C is invariant under rigid motions).
//
// PBD (Müller, Heidelberger, Hennix, Ratcliff 2007, "Position based dynamics", eq. 8–9), with a
// dimensionless stiffness k ∈ [0, 1] applied in every iteration (its effect depends on the
// iteration and substep counts, docs/seed.md#stiffness):
//   s = C / (w₁ + w₂),   Δp₁ = −k w₁ s n,   Δp₂ = +k w₂ s n.
// XPBD (Macklin, Müller, Chentanez 2016, "XPBD", eq. 18), with a stiffness k in N/m, its
// compliance α̃ = 1/(k h_s²) per substep h_s, and the multiplier λ reset at every substep's
// first iteration (as the seed's XPBD::solve_DistanceConstraint):
//   Δλ = (−C − α̃ λ) / (w₁ + w₂ + α̃),   λ ← λ + Δλ,   Δp₁ = w₁ Δλ n,   Δp₂ = −w₂ Δλ n.
// The constraint's force on p₁ is λ n / h_s²: its tension, positive when stretched, is −λ/h_s².
// The functions are pure (positions in, corrections out) so that they can be tested alone;
// nothing allocates.
#pragma once

#include <cstdint>
#include <vector>

#include "pbd/math/types.h"
#include "pbd/model/body_states.h"

namespace pbd {

struct Scene;

struct ParticleDistanceConstraint {
  int particle1 = -1;
  int particle2 = -1;
  Real restLength = 0;
  bool xpbd = false;    ///< false: PBD, stiffness ∈ [0, 1]; true: XPBD, stiffness in N/m
  Real stiffness = 1;   ///< of the family that made it (cloth or solid stiffness)
  Real multiplier = 0;  ///< λ of the current substep (XPBD)
};

struct DistanceCorrection {
  Vector3 first = Vector3::Zero();   ///< Δp₁
  Vector3 second = Vector3::Zero();  ///< Δp₂
  Real multiplier = 0;               ///< Δλ (XPBD; 0 for PBD)
};

/// C = |p₁ − p₂| − L.
Real particleDistanceValue(const Vector3& p1, const Vector3& p2, Real restLength);

/// The PBD projection with stiffness k ∈ [0, 1]. No correction when both particles are static
/// or coincide (the direction is undefined).
DistanceCorrection particleDistancePbd(const Vector3& p1, const Vector3& p2, Real inverseMass1,
                                       Real inverseMass2, Real restLength, Real stiffness);

/// The XPBD projection with stiffness k (N/m) > 0 at substep size h_s and accumulated λ.
DistanceCorrection particleDistanceXpbd(const Vector3& p1, const Vector3& p2, Real inverseMass1,
                                        Real inverseMass2, Real restLength, Real stiffness,
                                        Real substepSize, Real multiplier);

/// The distance constraints along every edge of the scene's triangle models whose
/// clothSimulationMethod is 1 (PBD) or 4 (XPBD), with clothStiffnessFor, then of its tet models
/// whose solidSimulationMethod is 1 (PBD) or 6 (XPBD), with solidStiffnessFor (each family its
/// own stiffness: the seed writes one into all). Rest lengths at t = 0; per model, each edge once
/// in the seed's order and orientation (uniqueEdges), edges between two static particles
/// included (they move nothing, but the seed colours them).
std::vector<ParticleDistanceConstraint> deformableDistanceConstraints(const Scene& scene);

/// One Gauss–Seidel sweep over `constraints` in order; the XPBD ones reset λ first when
/// `firstIteration` (the start of a substep of size `substepSize`).
void solveParticleDistances(std::vector<ParticleDistanceConstraint>& constraints,
                            ParticleStates& particles, Real substepSize, bool firstIteration,
                            std::size_t begin = 0, std::size_t end = SIZE_MAX);

/// The tension (N, positive when stretched) of an XPBD distance constraint whose substep
/// multiplier is λ: −λ/h_s².
inline Real particleDistanceTension(Real multiplier, Real substepSize) {
  return -multiplier / (substepSize * substepSize);
}

}  // namespace pbd
