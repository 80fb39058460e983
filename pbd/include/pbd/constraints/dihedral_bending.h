// Dihedral bending of a cloth across each interior edge (clothBendingMethod 1, PBD only, as in
// the seed), Bridson, Marino, Fedkiw 2003, "Simulation of clothing with folds and wrinkles", and
// Müller et al. 2007, "Position based dynamics", appendix A. For an edge e = x₁ − x₀ shared by
// the triangles (x₀, x₁, x₂) and (x₀, x₁, x₃), with the area-weighted normals
//   N_A = e × (x₂ − x₀),  N_B = (x₃ − x₀) × e   (parallel for a flat pair with x₂, x₃ apart),
//   θ = atan2((N̂_A × N̂_B)·ê, N̂_A·N̂_B) ∈ (−π, π],   C = wrap(θ − θ₀),  θ₀ the signed rest angle,
//   ∇₂θ = −|e| N_A/|N_A|²,  ∇₃θ = −|e| N_B/|N_B|²,
//   ∇₀θ = −((x₂ − x₁)·ê) N_A/|N_A|² − ((x₃ − x₁)·ê) N_B/|N_B|²,
//   ∇₁θ = ((x₂ − x₀)·ê) N_A/|N_A|² + ((x₃ − x₀)·ê) N_B/|N_B|²     (Σ ∇_iθ = 0).
// PBD, k ∈ [0, 1] per iteration: s = C / Σ w_i |∇_iθ|², Δx_i = −k s w_i ∇_iθ.
// Deliberate difference from the seed (pbdval's form: pbd.xpbd, or femCutoff 0): the seed measures
// the unsigned angle acos(N̂_A·N̂_B) and flips the correction's sign by orientation, so C is
// discontinuous at the flat state whenever θ₀ ≠ 0 (a fold with the mirror angle of its rest angle
// is not corrected towards it); here the angle is signed and C is continuous except at θ = ±π.
//
// The seed's form (the `pbd` method: DihedralBendingConstraint::seedForm, set when femCutoffFor is
// above 0 as for the other seed forms, docs/methods.md "The seed's forms"), for its fidelity to
// PositionBasedDynamics: its solve_DihedralConstraint operation by operation — with the seed's
// names p₀, p₁ the opposite vertices (x₂, x₃ here) and p₂, p₃ the edge (x₀, x₁): n₁ = (p₂ − p₀) ×
// (p₃ − p₀)/|·|², n₂ = (p₃ − p₁) × (p₂ − p₁)/|·|², the gradients |e| n₁, |e| n₂ and their edge
// terms, φ = acos(n̂₁·n̂₂) ∈ [0, π], C = φ − φ₀ with the unsigned rest angle φ₀, the correction's
// sign flipped when (n̂₁ × n̂₂)·e > 0, no correction when both opposite vertices are static or
// Σ w |∇C|² = 0 — and every interior edge kept whose edge is at least 10⁻⁶ long (static ones
// too: they take a colour group; a degenerate rest triangle, whose seed rest angle is NaN, gets
// none).
// Pure functions; nothing allocates.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "pbd/constraints/isometric_bending.h"
#include "pbd/math/types.h"
#include "pbd/model/body_states.h"

namespace pbd {

struct Scene;

struct DihedralBendingConstraint {
  std::array<int, 4> particles{-1, -1, -1, -1};  ///< x₀, x₁ (the edge), x₂, x₃ (opposite)
  Real restAngle = 0;                            ///< θ₀, signed
  Real stiffness = 1;                            ///< k ∈ [0, 1]
  /// The seed's form (see above): restAngle is then the seed's unsigned acos(n̂₁·n̂₂).
  bool seedForm = false;
};

/// θ of the stencil; NaN when a triangle or the edge is degenerate.
Real dihedralAngle(const std::array<Vector3, 4>& x);

/// ∇θ at x (zero when a triangle or the edge is degenerate).
std::array<Vector3, 4> dihedralAngleGradient(const std::array<Vector3, 4>& x);

BendingCorrection dihedralBendingPbd(const std::array<Vector3, 4>& x,
                                     const std::array<Real, 4>& inverseMasses,
                                     const DihedralBendingConstraint& c);

/// The seed's solve_DihedralConstraint (see above; x as in DihedralBendingConstraint::particles).
BendingCorrection seedDihedralBendingPbd(const std::array<Vector3, 4>& x,
                                         const std::array<Real, 4>& inverseMasses,
                                         const DihedralBendingConstraint& c);

/// The seed's rest angle (DihedralConstraint::initConstraint): acos(n̂₁·n̂₂) clamped, NaN when the
/// edge is shorter than 10⁻⁶ or a triangle degenerate.
Real seedDihedralRestAngle(const std::array<Vector3, 4>& x);

/// One constraint per interior edge of every triangle model when clothSimulationMethod is 1 to 4
/// (every method that models the cloth's stretch, as in the seed) and clothBendingMethod is 1,
/// with clothBendingStiffnessFor and the rest angle at t = 0; none whose triangles are
/// degenerate, and, outside the seed's form (femCutoffFor 0), none whose four particles are
/// static.
std::vector<DihedralBendingConstraint> clothDihedralConstraints(const Scene& scene);

/// One Gauss–Seidel sweep.
void solveDihedralBending(const std::vector<DihedralBendingConstraint>& constraints,
                          ParticleStates& particles, std::size_t begin = 0,
                          std::size_t end = SIZE_MAX);

}  // namespace pbd
