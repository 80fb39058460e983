// Strain-based triangles of a cloth (clothSimulationMethod 3; PBD), Müller, Chentanez, Kim,
// Macklin 2014, "Strain based dynamics": the components of the right Cauchy–Green tensor in the
// triangle's own plane held at their rest values, one scalar constraint at a time.
//
// Rest frame (once, from the positions at t = 0): x̂ along the first edge, x̂ = (x₁ − x₀)/|x₁ − x₀|,
// ŷ = n̂ × x̂ with n̂ the unit normal of (x₁ − x₀) × (x₂ − x₀). D_m = [X₁ − X₀, X₂ − X₀] holds the
// rest edges in (x̂, ŷ) coordinates, B = D_m⁻¹.
//   F = [x₁ − x₀, x₂ − x₀] B = [f_x, f_y]  (3 × 2),   S = FᵀF  (S = I at rest),
//   stretch along x:  C_xx = S_xx − 1 = |f_x|² − 1   (normalizeStretch: |f_x| − 1),
//   stretch along y:  C_yy = |f_y|² − 1               (normalizeStretch: |f_y| − 1),
//   shear:            C_xy = f_x · f_y                (normalizeShear: f_x·f_y / (|f_x| |f_y|)).
// With g_a = ∂C/∂f_a (a = x, y): ∇_{x_{k+1}}C = Σ_a B(k, a) g_a (k = 0, 1), ∇_{x₀}C = −∇_{x₁}C −
// ∇_{x₂}C (the gradients sum to zero: momentum is conserved; C depends on FᵀF only, so it is
// invariant under 3D rigid motions). For example ∂C_xx/∂f_x = 2 f_x, ∂C_xy/∂f_x = f_y,
// ∂C_xy/∂f_y = f_x; normalized: ∂(|f_x| − 1)/∂f_x = f_x/|f_x|, ∂C_xy/∂f_x = f_y/(|f_x||f_y|) −
// C_xy f_x/|f_x|².
// PBD, as the seed's solve_StrainTriangleConstraint: the three constraints in the seed's order
// xx, xy, yy, Gauss–Seidel within the element (each evaluated at the positions the previous ones
// corrected), each s = k C / Σ w_i |∇_iC|², Δx_i = −s w_i ∇_iC, with k = cloth_xxStiffness,
// cloth_xyStiffness, cloth_yyStiffness (dimensionless, [0, 1], per iteration); none when
// Σ w_i |∇_iC|² = 0.
//
// The seed's form (the `pbd` method: StrainTriangleConstraint::seedForm, set when femCutoffFor
// is above 0 as for the other seed forms), for its fidelity to PositionBasedDynamics: the rest
// matrix from the world x and z coordinates alone (the seed's StrainTriangleConstraint::
// initConstraint; a triangle whose xz projection has |det| < 10⁻⁶ gets no constraint, and one
// out of a y = const plane a distorted rest shape, docs/seed.md#sbd-triangle-rest-shape), every
// triangle kept (three static particles too: they take a colour group), and the seed's
// solve_StrainTriangleConstraint operation by operation (F's entries as dot products with B's
// columns padded to 3-vectors, a normalized stretch as 2 s (s − 1) / Σ w |∇S|² on ∇S, no
// correction when Σ w |∇C|² = 0).
//
// Deliberate differences from the seed (outside its form, pbd.xpbd or femCutoff 0):
//  - The rest frame is the triangle's own plane. The seed builds its rest matrix from two world
//    coordinates only (docs/seed.md#sbd-triangle-rest-shape), so triangles not in that plane get a
//    wrong rest state, and triangles perpendicular to it are dropped; here every non-degenerate
//    triangle gets its true rest shape, whatever its orientation (tested). The material x axis is
//    the first edge (the seed's is a world axis): the components, and so the corrections of one
//    Gauss–Seidel pass, depend on that frame; the rest shape they restore (S = I) does not.
//  - Each stiffness from its own key: the seed's setters write xx into yy and xy (§5.3 #4);
//    in the seed's form too.
// Pure functions (positions in, corrections out); nothing allocates.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "pbd/math/types.h"
#include "pbd/model/body_states.h"

namespace pbd {

struct Scene;

/// The strain components, in the seed's projection order.
enum class StrainComponent { Xx = 0, Xy = 1, Yy = 2 };

struct StrainTriangleConstraint {
  std::array<int, 3> particles{-1, -1, -1};
  Eigen::Matrix<Real, 2, 2> restInverse = Eigen::Matrix<Real, 2, 2>::Zero();  ///< B = D_m⁻¹
  Real xxStiffness = 1;
  Real yyStiffness = 1;
  Real xyStiffness = 1;
  bool normalizeStretch = false;
  bool normalizeShear = false;
  /// The seed's form (see above): restInverse from the x and z coordinates, the seed's solve.
  bool seedForm = false;
};

/// B of the rest triangle in the frame above. False for a degenerate triangle (zero area).
bool strainTriangleRest(const std::array<Vector3, 3>& rest, Eigen::Matrix<Real, 2, 2>& restInverse);

/// C of one component (with the constraint's normalize flags).
Real strainTriangleValue(const std::array<Vector3, 3>& x, const StrainTriangleConstraint& c,
                         StrainComponent component);

/// ∇_{x_i}C of one component, i = 0, 1, 2.
std::array<Vector3, 3> strainTriangleGradients(const std::array<Vector3, 3>& x,
                                               const StrainTriangleConstraint& c,
                                               StrainComponent component);

/// The PBD projection of the three components (Gauss–Seidel within the element): the summed
/// corrections.
std::array<Vector3, 3> strainTrianglePbd(const std::array<Vector3, 3>& x,
                                         const std::array<Real, 3>& inverseMasses,
                                         const StrainTriangleConstraint& c);

/// The seed's rest matrix (init_StrainTriangleConstraint on the x and z coordinates): false when
/// the projection's |det| < 10⁻⁶.
bool seedStrainTriangleRest(const std::array<Vector3, 3>& rest,
                            Eigen::Matrix<Real, 2, 2>& restInverse);

/// The seed's solve_StrainTriangleConstraint (see above): the summed corrections.
std::array<Vector3, 3> seedStrainTrianglePbd(const std::array<Vector3, 3>& x,
                                             const std::array<Real, 3>& inverseMasses,
                                             const StrainTriangleConstraint& c);

/// One constraint per triangle of every triangle model when clothSimulationMethod is 3, with
/// cloth_xxStiffness, cloth_yyStiffness, cloth_xyStiffness, cloth_normalizeStretch and
/// cloth_normalizeShear; in the models' triangle order. In the seed's form (femCutoffFor > 0)
/// every triangle seedStrainTriangleRest accepts; otherwise none whose three particles are
/// static or whose rest triangle is degenerate.
std::vector<StrainTriangleConstraint> strainTriangleConstraints(const Scene& scene);

/// One Gauss–Seidel sweep over `constraints` in order.
void solveStrainTriangles(const std::vector<StrainTriangleConstraint>& constraints,
                          ParticleStates& particles, std::size_t begin = 0,
                          std::size_t end = SIZE_MAX);

}  // namespace pbd
