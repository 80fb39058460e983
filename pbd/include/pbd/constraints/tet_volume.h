// Volume of a tetrahedron of four particles: the solids of solidSimulationMethod 1 (PBD, with
// PBD distance constraints on the edges) and 6 (XPBD, with XPBD distance constraints).
//
//   C(p₁, p₂, p₃, p₄) = V − V₀,   V = ⅙ (p₂ − p₁) × (p₃ − p₁) · (p₄ − p₁)   (signed)
//   ∇_{p₂}C = ⅙ (p₃ − p₁) × (p₄ − p₁),   ∇_{p₃}C = ⅙ (p₄ − p₁) × (p₂ − p₁),
//   ∇_{p₄}C = ⅙ (p₂ − p₁) × (p₃ − p₁),   ∇_{p₁}C = −(∇_{p₂}C + ∇_{p₃}C + ∇_{p₄}C)
// (Müller, Heidelberger, Hennix, Ratcliff 2007, "Position based dynamics", §4.3; the gradients
// sum to zero, so w-weighted corrections conserve linear momentum, and C is invariant under
// rigid motions). V₀ is the signed rest volume: the seed takes |V₀| against the signed V, so a
// tet listed with negative orientation starts at C = −2|V₀| and is driven to invert
// (docs/seed.md#tet-orientation); here C = 0 at rest whatever the orientation.
//
// PBD, stiffness k ∈ [0, 1] per iteration:  s = C / Σ w_i |∇_iC|²,  Δp_i = −k s w_i ∇_iC.
// XPBD, stiffness k in N/m⁵ (½ k C² is the energy), α̃ = 1/(k h_s²), λ reset every substep:
//   Δλ = (−C − α̃ λ) / (Σ w_i |∇_iC|² + α̃),  Δp_i = w_i Δλ ∇_iC.
//
// The seed's form (the `pbd` method: TetVolumeConstraint::cutoff > 0, femCutoffFor), for its
// fidelity to PositionBasedDynamics (solve_VolumeConstraint, PBD and XPBD; docs/seed.md,
// "Volume constraint scale" and "Tet orientation"): the rest volume |V₀|, the gradients
// g_i = 6 ∇_iC (the cross products themselves, g₁ = (p₂ − p₃) × (p₄ − p₃) computed on its own),
// the same C = V − |V₀|, no correction when |Σ w_i |g_i|²| (+ α̃) is below the cut-off, every
// tet kept (four static particles too: they move nothing, but take a colour group), and the
// operations in the seed's order. So the PBD correction is ⅙ of the projection's and the XPBD
// one has Σ w |6∇V|² + α̃ in its denominator. k = 0 leaves an XPBD constraint out here as well
// (the seed's XPBD solve would take it as hard, α̃ = 0).
// Pure functions (positions in, corrections out); nothing allocates.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "pbd/math/types.h"
#include "pbd/model/body_states.h"

namespace pbd {

struct Scene;

struct TetVolumeConstraint {
  std::array<int, 4> particles{-1, -1, -1, -1};
  Real restVolume = 0;  ///< signed, at t = 0
  bool xpbd = false;    ///< false: PBD, stiffness ∈ [0, 1]; true: XPBD, stiffness in N/m⁵
  Real stiffness = 1;
  Real multiplier = 0;  ///< λ of the current substep (XPBD)
  /// > 0: the seed's form (see above) with this cut-off (femCutoffFor: 10⁻⁶ in the `pbd`
  /// method); 0: the projection of ∇V (pbd.xpbd, or a femCutoff of 0).
  Real cutoff = 0;
};

struct TetVolumeCorrection {
  std::array<Vector3, 4> positions{Vector3::Zero(), Vector3::Zero(), Vector3::Zero(),
                                   Vector3::Zero()};
  Real multiplier = 0;  ///< Δλ (XPBD; 0 for PBD)
};

/// The signed volume ⅙ (p₂ − p₁) × (p₃ − p₁) · (p₄ − p₁).
Real signedTetVolume(const std::array<Vector3, 4>& p);

/// ∇_{p_i}C for i = 1 … 4 (C = V − V₀).
std::array<Vector3, 4> tetVolumeGradients(const std::array<Vector3, 4>& p);

/// The PBD projection (k ∈ [0, 1]); no correction when every particle is static or the
/// gradients vanish (a degenerate tet).
TetVolumeCorrection tetVolumePbd(const std::array<Vector3, 4>& p,
                                 const std::array<Real, 4>& inverseMasses, Real restVolume,
                                 Real stiffness);

/// The XPBD projection (k > 0 in N/m⁵) at substep size h_s with the accumulated λ.
TetVolumeCorrection tetVolumeXpbd(const std::array<Vector3, 4>& p,
                                  const std::array<Real, 4>& inverseMasses, Real restVolume,
                                  Real stiffness, Real substepSize, Real multiplier);

/// The seed's rest volume |⅙ (p₄ − p₁) · ((p₃ − p₁) × (p₂ − p₁))|, in its operation order.
Real seedRestTetVolume(const std::array<Vector3, 4>& p);

/// The seed's PBD solve_VolumeConstraint (gradients 6 ∇V, see above): no correction when k = 0
/// or |Σ w_i |g_i|²| < cutoff.
TetVolumeCorrection seedTetVolumePbd(const std::array<Vector3, 4>& p,
                                     const std::array<Real, 4>& inverseMasses, Real restVolume,
                                     Real stiffness, Real cutoff);

/// The seed's XPBD::solve_VolumeConstraint (gradients 6 ∇V): no correction when k = 0 or
/// |Σ w_i |g_i|² + α̃| < cutoff.
TetVolumeCorrection seedTetVolumeXpbd(const std::array<Vector3, 4>& p,
                                      const std::array<Real, 4>& inverseMasses, Real restVolume,
                                      Real stiffness, Real substepSize, Real multiplier,
                                      Real cutoff);

/// The volume constraints of every tet of the scene's tet models whose solidSimulationMethod
/// is 1 (PBD) or 6 (XPBD), with solidVolumeStiffnessFor and cutoff femCutoffFor. In the seed's
/// form (cutoff > 0) every tet, with the rest volume |V₀|; otherwise tets of four static
/// particles are left out and the rest volume is signed.
std::vector<TetVolumeConstraint> solidVolumeConstraints(const Scene& scene);

/// One Gauss–Seidel sweep over `constraints` in order; the XPBD ones reset λ first when
/// `firstIteration` (the start of a substep of size `substepSize`).
void solveTetVolumes(std::vector<TetVolumeConstraint>& constraints, ParticleStates& particles,
                     Real substepSize, bool firstIteration, std::size_t begin = 0,
                     std::size_t end = SIZE_MAX);

}  // namespace pbd
