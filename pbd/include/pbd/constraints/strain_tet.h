// Strain-based tetrahedra (solidSimulationMethod 4; PBD), Müller, Chentanez, Kim, Macklin 2014,
// "Strain based dynamics": the six components of the right Cauchy–Green tensor of a tet held at
// their rest values, one scalar constraint at a time (the tet version of strain_triangle.h).
//
// Rest state (once, from the positions at t = 0): D_m = [X₁ − X₀, X₂ − X₀, X₃ − X₀] in world
// coordinates, B = D_m⁻¹ (a degenerate tet, det D_m ≈ 0, gets no constraint).
// clang-format off
//   F = [x₁ − x₀, x₂ − x₀, x₃ − x₀] B = [f₀, f₁, f₂],   S = FᵀF  (S = I at rest),
//   stretch along a:  C_aa = S_aa − 1 = |f_a|² − 1          (normalizeStretch: |f_a| − 1),
//   shear of a < b:   C_ab = S_ab = f_a · f_b               (normalizeShear: f_a·f_b / (|f_a||f_b|)).
// clang-format on
// With g_a = ∂C/∂f_a: ∇_{x_{k+1}}C = Σ_a B(k, a) g_a (k = 0, 1, 2), ∇_{x₀}C = −Σ_k ∇_{x_{k+1}}C
// (the gradients sum to zero: w-weighted corrections conserve linear momentum; C depends on FᵀF
// only, so it is invariant under rigid motions). ∂C_aa/∂f_a = 2 f_a (normalized: f_a/|f_a|),
// ∂C_ab/∂f_a = f_b, ∂C_ab/∂f_b = f_a (normalized: f_b/(|f_a||f_b|) − C_ab f_a/|f_a|², and
// symmetrically).
// PBD, as the seed's solve_StrainTetraConstraint: the three stretches (00, 11, 22) then the three
// shears (01, 02, 12), Gauss–Seidel within the element (each evaluated at the positions the
// previous ones corrected), each s = k C / Σ w_i |∇_iC|², Δx_i = −s w_i ∇_iC, k = solid_stiffness
// (solidStiffnessFor: 1 unless set) for both stretch and shear (as the seed); none when
// Σ w_i |∇_iC|² = 0. No inversion handling (as the seed): an inverted tet has the same S as its
// mirror image, so the constraints cannot tell it from the rest state's reflection.
//
// The seed's form (the `pbd` method: StrainTetConstraint::cutoff > 0, femCutoffFor), for its
// fidelity to PositionBasedDynamics: the seed's solve_StrainTetraConstraint operation by
// operation. It projects the components in its loop order i = 0…2, j = 0…i — xx, xy, yy, xz,
// yz, zz: stretches and shears interleaved —, with f_i = P B.col(i), ∇_{x_{k+1}}C =
// f_j B(k, i) + f_i B(k, j), ∇_{x₀}C accumulated by subtraction, a normalized stretch as
// 2 s (s − 1) / Σ w |∇S|² on ∇S (s = √S_ii), no correction when |Σ w_i |∇_iC|²| is below the
// cut-off (10⁻⁶), and keeps every tet whose |det D_m| exceeds the cut-off (four static
// particles too: they take a colour group).
//
// Deliberate difference from the seed: solid_normalizeStretch normalizes the stretches and
// solid_normalizeShear the shears; the seed passes normalizeStretch for both flags, so
// solid_normalizeShear is ignored there (docs/seed.md#sbd-tet-flags).
// Pure functions (positions in, corrections out); nothing allocates.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "pbd/math/types.h"
#include "pbd/model/body_states.h"

namespace pbd {

struct Scene;

/// The strain components, in the seed's projection order: stretches, then shears.
enum class TetStrainComponent { Xx = 0, Yy = 1, Zz = 2, Xy = 3, Xz = 4, Yz = 5 };

inline constexpr std::array<TetStrainComponent, 6> kTetStrainComponents = {
    TetStrainComponent::Xx, TetStrainComponent::Yy, TetStrainComponent::Zz,
    TetStrainComponent::Xy, TetStrainComponent::Xz, TetStrainComponent::Yz};

struct StrainTetConstraint {
  std::array<int, 4> particles{-1, -1, -1, -1};
  Matrix3 restInverse = Matrix3::Identity();  ///< B = D_m⁻¹
  Real stretchStiffness = 1;
  Real shearStiffness = 1;
  bool normalizeStretch = false;
  bool normalizeShear = false;
  /// > 0: the seed's form (see above) with this cut-off (femCutoffFor: 10⁻⁶ in the `pbd`
  /// method); 0: pbdval's (stretches, then shears; pbd.xpbd, or a femCutoff of 0).
  Real cutoff = 0;
};

/// B of the rest tet. False for a degenerate tet (|det D_m| no larger than the round-off of the
/// product of its edge lengths).
bool strainTetRest(const std::array<Vector3, 4>& rest, Matrix3& restInverse);

/// C of one component (with the constraint's normalize flags).
Real strainTetValue(const std::array<Vector3, 4>& x, const StrainTetConstraint& c,
                    TetStrainComponent component);

/// ∇_{x_i}C of one component, i = 0 … 3.
std::array<Vector3, 4> strainTetGradients(const std::array<Vector3, 4>& x,
                                          const StrainTetConstraint& c,
                                          TetStrainComponent component);

/// The PBD projection of the six components (Gauss–Seidel within the element): the summed
/// corrections.
std::array<Vector3, 4> strainTetPbd(const std::array<Vector3, 4>& x,
                                    const std::array<Real, 4>& inverseMasses,
                                    const StrainTetConstraint& c);

/// The seed's solve_StrainTetraConstraint (see above; c.cutoff > 0): the summed corrections.
std::array<Vector3, 4> seedStrainTetPbd(const std::array<Vector3, 4>& x,
                                        const std::array<Real, 4>& inverseMasses,
                                        const StrainTetConstraint& c);

/// One constraint per tet of every tet model when solidSimulationMethod is 4, with
/// solidStiffnessFor (stretch and shear), solid_normalizeStretch and solid_normalizeShear and
/// cutoff femCutoffFor; in the models' tet order. In the seed's form (cutoff > 0) every tet
/// whose |det D_m| exceeds the cut-off, with the seed's D_m⁻¹; otherwise none whose four
/// particles are static or whose rest tet is degenerate (strainTetRest).
std::vector<StrainTetConstraint> strainTetConstraints(const Scene& scene);

/// One Gauss–Seidel sweep over `constraints` in order.
void solveStrainTets(const std::vector<StrainTetConstraint>& constraints, ParticleStates& particles,
                     std::size_t begin = 0, std::size_t end = SIZE_MAX);

}  // namespace pbd
