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
// Deliberate difference from the seed: the seed measures the unsigned angle acos(N̂_A·N̂_B) and
// flips the correction's sign by orientation, so C is discontinuous at the flat state whenever
// θ₀ ≠ 0 (a fold with the mirror angle of its rest angle is not corrected towards it); here the
// angle is signed and C is continuous except at θ = ±π.
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
};

/// θ of the stencil; NaN when a triangle or the edge is degenerate.
Real dihedralAngle(const std::array<Vector3, 4>& x);

/// ∇θ at x (zero when a triangle or the edge is degenerate).
std::array<Vector3, 4> dihedralAngleGradient(const std::array<Vector3, 4>& x);

BendingCorrection dihedralBendingPbd(const std::array<Vector3, 4>& x,
                                     const std::array<Real, 4>& inverseMasses,
                                     const DihedralBendingConstraint& c);

/// One constraint per interior edge of every triangle model when clothSimulationMethod is 1 to 4
/// (every method that models the cloth's stretch, as in the seed) and clothBendingMethod is 1,
/// with clothBendingStiffnessFor and the rest angle at t = 0; none
/// whose four particles are static or whose triangles are degenerate.
std::vector<DihedralBendingConstraint> clothDihedralConstraints(const Scene& scene);

/// One Gauss–Seidel sweep.
void solveDihedralBending(const std::vector<DihedralBendingConstraint>& constraints,
                          ParticleStates& particles, std::size_t begin = 0,
                          std::size_t end = SIZE_MAX);

}  // namespace pbd
