// Isometric bending of a cloth across each interior edge (clothBendingMethod 2: PBD, 3: XPBD),
// Bergou, Wardetzky, Harmon, Zorin, Grinspun 2006, "A quadratic bending model for inextensible
// surfaces". For an edge (x₀, x₁) shared by the triangles (x₀, x₁, x₂) and (x₀, x₁, x₃), with the
// angles α₀, β₀ at x₀, x₁ in the first triangle and α₁, β₁ in the second, at t = 0:
//   K = (cot β₀ + cot β₁, cot α₀ + cot α₁, −cot α₀ − cot β₀, −cot α₁ − cot β₁),
//   H = Σ_i K_i x_i  (zero for every flat configuration; Σ K_i = 0),
//   C = E = ½ Σ_ij Q_ij x_i·x_j = (3 / (2 (A₀ + A₁))) |H|²,  Q = (3/(A₀ + A₁)) K Kᵀ,
//   ∇_{x_i}C = (3/(A₀ + A₁)) K_i H.
// The energy is the constraint, as in the seed (PositionBasedDynamics' IsometricBendingConstraint):
// C ≥ 0 with its minimum, C = 0 and ∇C = 0, at every flat state, so the model assumes a flat
// rest state (the seed's too: docs/seed.md#flat-bending-rest-state). For a symmetric fold by the
// dihedral angle φ of an edge of length 1 whose opposite vertices stand d from it over one foot
// point, C = (6/d) sin²(φ/2) (tested). The gradients sum to zero (momentum is conserved).
//   PBD, k ∈ [0, 1] per iteration: s = C / Σ w_i |∇_iC|², Δx_i = −k s w_i ∇_iC.
//   XPBD, k the energy's stiffness, α̃ = 1/(k h_s²), λ reset every substep:
//     Δλ = (−C − α̃ λ) / (Σ w_i |∇_iC|² + α̃), Δx_i = w_i Δλ ∇_iC.
// Pure functions; nothing allocates.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "pbd/math/types.h"
#include "pbd/model/body_states.h"

namespace pbd {

struct Scene;

struct IsometricBendingConstraint {
  std::array<int, 4> particles{-1, -1, -1, -1};  ///< x₀, x₁ (the edge), x₂, x₃ (opposite)
  std::array<Real, 4> weights{0, 0, 0, 0};       ///< K
  Real scale = 0;                                ///< 3/(A₀ + A₁)
  bool xpbd = false;
  Real stiffness = 1;
  Real multiplier = 0;
  /// The seed's Q = −(3/(2(A₀ + A₁))) K Kᵀ (init_IsometricBendingConstraint), with which the
  /// PBD projection is evaluated in the seed's operation order: C_seed = ½ Σ Q_jk x_k·x_j =
  /// −C/4·…, ∇_j = Σ_k Q_jk x_k; the PBD step is the same as with C (the factor cancels).
  Eigen::Matrix<Real, 4, 4> seedQ = Eigen::Matrix<Real, 4, 4>::Zero();
  /// No PBD correction when the seed's Σ w_j |∇_j|² is not above it (femCutoffFor: the seed's
  /// 10⁻⁶ in `pbd`, 0 in `pbd.xpbd`).
  Real cutoff = 0;
};

/// K and 3/(A₀ + A₁) of the stencil at `rest` (x₀, x₁ the edge). False for a degenerate stencil
/// (a triangle of zero area).
bool isometricBendingStencil(const std::array<Vector3, 4>& rest, std::array<Real, 4>& weights,
                             Real& scale);

/// C = ½ scale |Σ K_i x_i|².
Real isometricBendingEnergy(const std::array<Vector3, 4>& x, const std::array<Real, 4>& weights,
                            Real scale);

struct BendingCorrection {
  std::array<Vector3, 4> positions{Vector3::Zero(), Vector3::Zero(), Vector3::Zero(),
                                   Vector3::Zero()};
  Real multiplier = 0;
};

BendingCorrection isometricBendingPbd(const std::array<Vector3, 4>& x,
                                      const std::array<Real, 4>& inverseMasses,
                                      const IsometricBendingConstraint& c);
BendingCorrection isometricBendingXpbd(const std::array<Vector3, 4>& x,
                                       const std::array<Real, 4>& inverseMasses,
                                       const IsometricBendingConstraint& c, Real substepSize);

/// One constraint per interior edge (shared by exactly two triangles) of every triangle model
/// when clothSimulationMethod is 1 to 4 (every method that models the cloth's stretch, as in the
/// seed) and clothBendingMethod is 2 (PBD) or 3 (XPBD), with
/// clothBendingStiffnessFor; edges in the order they first appear; none whose four particles
/// are static.
std::vector<IsometricBendingConstraint> clothBendingConstraints(const Scene& scene);

/// One Gauss–Seidel sweep; XPBD ones reset λ when `firstIteration`.
void solveIsometricBending(std::vector<IsometricBendingConstraint>& constraints,
                           ParticleStates& particles, Real substepSize, bool firstIteration,
                           std::size_t begin = 0, std::size_t end = SIZE_MAX);

}  // namespace pbd
