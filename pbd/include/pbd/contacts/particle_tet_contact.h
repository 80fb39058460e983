// Particle–tet contact: a particle p of one tet model inside a tet T of another
// (deformable–deformable; the seed's ParticleTetContactConstraint,
// docs/seed.md#particle-tet-contacts). Detection: collision/tet_contact_detection.h gives T (the
// tet of the closest point of the other model's boundary), the weights b (barycentrics of that
// point in T, Σ b_i = 1, b_i ≥ 0) and the unit normal n out of the other model (its contact face's;
// the seed's points from the particle to the contact point). Capacity: sized at world build for the
// detector's worst case; contacts beyond it are dropped at detection and counted in
// geometry.droppedContacts.
//
//   C = n·(x_p − Σ_i b_i x_i) ≥ 0           (n fixed at detection)
//   ∇C: ∂C/∂x_p = nᵀ,  ∂C/∂x_i = −b_i nᵀ     (Σ of the gradients = n (1 − Σ b_i) = 0:
//                                             w-weighted corrections conserve momentum)
//   W = w_p + Σ b_i² w_i,  Δλ = (−C − α̃ λ)/(W + α̃),  λ ← λ + Δλ  (α̃ = α/h², XPBD; 0 else)
//   Δx_p = w_p Δλ n,  Δx_i = −w_i b_i Δλ n.
// Reference: Bender, Müller, Macklin, "Position-based simulation methods in computer
// graphics", Eurographics tutorial 2017 (contacts as inequality constraints C ≥ 0); Müller,
// Macklin, Chentanez, Jeschke, Kim 2020, §3.5 (contacts inside the substeps, static friction
// at position level); the seed's PositionBasedDynamics::solve_ParticleTetContactConstraint.
//
// Two schedules, chosen by the step:
//  - Seed (the `pbd` step with contactModel "seed"): as the seed. Contacts are detected once
//    per step after the substeps, and solved in every position iteration of the *next* step's
//    substeps ("one frame late"), against the tet positions snapshotted at detection (the tet
//    side does not see its own motion), bilaterally (λ = −C/W unclamped: a particle that has
//    left the tet is pulled back to the snapshot surface point). The seed's velocity pass
//    applies friction −μ λ t limited to p_max, but reads λ before any position solve of the
//    same contacts (detection replaces the contacts just before it; λ is uninitialised in the
//    seed): its particle–tet friction never acts, and here it is zero.
//  - Current (the `pbd` step with contactModel "corrected", and the `pbd.xpbd` step): the
//    contacts are detected after every substep's prediction and solved in that substep, against
//    the current tet positions, as an inequality (λ ≥ 0, accumulated over the substep's
//    iterations). Friction at position level (Müller et al. 2020, static friction; the same
//    clamp as xpbd_contact.h): after the normal row, the tangential part d_t of the relative
//    displacement over the substep d = (x_p − x̄_p) − Σ b_i (x_i − x̄_i) (x̄ at the substep's
//    start) is undone, Δλ_t = min(|d_t|/W, μ λ − λ_t), Δx_p = −w_p Δλ_t t̂,
//    Δx_i = w_i b_i Δλ_t t̂ (t̂ = d_t/|d_t|): sticking inside the Coulomb cone, sliding with
//    the Coulomb bound on it. The seed has no working friction here.
// μ: the two tet models' `friction` by the combination rule (seed: μ_a + μ_b). There is no
// restitution (nor in the seed): a position-level contact is perfectly inelastic.
#pragma once

#include <array>
#include <vector>

#include "pbd/collision/tet_contact_detection.h"
#include "pbd/contacts/contact_materials.h"
#include "pbd/model/body_states.h"

namespace pbd {

struct ParticleTetContact {
  int particle = -1;
  std::array<int, 4> vertices{-1, -1, -1, -1};
  std::array<Real, 4> weights{0, 0, 0, 0};  ///< b
  Vector3 normal = Vector3::UnitY();        ///< n, out of the tet side
  std::array<Vector3, 4> snapshot{Vector3::Zero(), Vector3::Zero(), Vector3::Zero(),
                                  Vector3::Zero()};  ///< tet positions at detection (seed)
  Real friction = 0;                                 ///< μ
  Real normalMultiplier = 0;   ///< λ, accumulated over the substep's iterations
  Real tangentMultiplier = 0;  ///< λ_t (current schedule)
};

struct ParticleTetCorrection {
  Vector3 particle = Vector3::Zero();
  std::array<Vector3, 4> tet{Vector3::Zero(), Vector3::Zero(), Vector3::Zero(), Vector3::Zero()};
  Real multiplier = 0;  ///< Δλ
};

/// C = n·(x_p − Σ b_i x_i).
Real particleTetContactValue(const Vector3& particle, const std::array<Vector3, 4>& tet,
                             const std::array<Real, 4>& weights, const Vector3& normal);

/// ∂C/∂x_p and ∂C/∂x_i (i = 0..3), n fixed.
std::array<Vector3, 5> particleTetContactGradients(const std::array<Real, 4>& weights,
                                                   const Vector3& normal);

/// The normal projection: Δλ = (−C − α̃ λ)/(W + α̃) with `alphaTilde` α̃ ≥ 0 and the
/// accumulated `multiplier` λ; `unilateral` keeps λ + Δλ ≥ 0 (no correction while C ≥ 0 and
/// λ = 0). No correction when every end is static.
ParticleTetCorrection particleTetContactCorrection(
    const Vector3& particle, const std::array<Vector3, 4>& tet, Real particleInverseMass,
    const std::array<Real, 4>& tetInverseMasses, const std::array<Real, 4>& weights,
    const Vector3& normal, Real alphaTilde, Real multiplier, bool unilateral);

/// Position-level friction for a relative displacement `displacement` over the substep:
/// undoes its tangential part up to the Coulomb bound μ λ − λ_t (`remainingBound`).
ParticleTetCorrection particleTetFrictionCorrection(const Vector3& displacement,
                                                    Real particleInverseMass,
                                                    const std::array<Real, 4>& tetInverseMasses,
                                                    const std::array<Real, 4>& weights,
                                                    const Vector3& normal, Real remainingBound);

enum class ParticleTetSchedule : int { Seed, Current };

/// The particle–tet contacts of the world, sized at build; a step allocates nothing.
struct ParticleTetContactSet {
  ParticleTetGeometryBuffer geometry;
  std::vector<ParticleTetContact> contacts;

  void reserve(const TetContactDetector& detector);
  /// Builds the contacts from `geometry` (snapshots the tet positions; λ = 0).
  void initialise(const ParticleStates& particles, const ContactMaterials& materials);
  /// Starts a substep: λ = λ_t = 0.
  void beginSubstep();
  /// One pass over every contact, in detection order. `alphaTilde` = compliance/h² (0: rigid).
  void solvePositions(ParticleStates& particles, ParticleTetSchedule schedule, Real alphaTilde);
};

}  // namespace pbd
