// FEM triangles of a cloth (clothSimulationMethod 2, the seed's default; PBD), Bender, Koschier,
// Charrier, Weber 2014, "Position-based simulation of continuous materials": an orthotropic
// St. Venant–Kirchhoff membrane in the triangle's own plane whose energy is the constraint.
//
// Rest frame (built once from the positions at t = 0): n̂ the unit normal of (x₁ − x₀) × (x₂ − x₀),
// the material y axis ŷ along the first edge, ŷ = (x₁ − x₀)/|x₁ − x₀|, and the material x axis
// x̂ = n̂ × ŷ, in the plane and perpendicular to the first edge. This is the seed's orthotropic
// frame (init_FEMTriangleConstraint): cloth_xxStiffness acts across the first edge,
// cloth_yyStiffness along it. D_m = [X₀ − X₂, X₁ − X₂] holds the rest edges in (x̂, ŷ)
// coordinates (X_i = (x̂·x_i, ŷ·x_i), the seed's choice of edges), B = D_m⁻¹, A the rest area.
//   F = [x₀ − x₂, x₁ − x₂] B  (3 × 2),   E = ½ (FᵀF − I)  (Green strain, 2 × 2),
//   normal stiffness (plane stress, the inverse of the compliance ε_xx = σ_xx/E_x − ν_yx σ_yy/E_y,
//   ε_yy = −ν_xy σ_xx/E_x + σ_yy/E_y):  c_xx = E_x/(1 − ν_xy ν_yx), c_yy = E_y/(1 − ν_xy ν_yx),
//   c_xy = ½ (E_x ν_yx + E_y ν_xy)/(1 − ν_xy ν_yx),
//   S = [[c_xx E_xx + c_xy E_yy, G E_xy], [G E_xy, c_xy E_xx + c_yy E_yy]]  (second
//   Piola–Kirchhoff), ψ = ½ E : S = ½ (c_xx E_xx² + 2 c_xy E_xx E_yy + c_yy E_yy²) + G E_xy², C = A
//   ψ ≥ 0,   [∇_{x₀}C, ∇_{x₁}C] = A F S Bᵀ,   ∇_{x₂}C = −∇_{x₀}C − ∇_{x₁}C
// (the gradients sum to zero, so w-weighted corrections conserve linear momentum; C is invariant
// under rigid motions in 3D, out of the plane too, since it depends on FᵀF only).
// The shear term G E_xy² is the seed's (its stress is G E_xy with the tensor shear strain E_xy):
// it is ½ G' γ² with the engineering shear γ = 2 E_xy and G' = G/2.
//
// PBD projection, as the seed's solve_FEMTriangleConstraint: s = C / Σ w_i |∇_iC|²,
// Δx_i = −s w_i ∇_iC, with NO stiffness factor (docs/seed.md#stiffness). Every quantity is
// evaluated in the seed's operation order, so that the `pbd` method follows the original's
// round-off too (tests/data/seed_reference). The seed corrects only when Σ w_i |∇_iC|² > 10⁻⁶
// and builds an element only when |det D_m| > 10⁻⁶: FemTriangleConstraint::cutoff and
// femTriangleRest's minimumDeterminant, both femCutoffFor(settings) (10⁻⁶ for the `pbd`
// method; 0 for `pbd.xpbd`: then only Σ w_i |∇_iC|² = 0 is skipped). The absolute threshold
// makes a dead zone that depends on the moduli and the mesh size: a 1 m triangle of the
// default moduli is left alone below a strain of about 2·10⁻³ (tests/pbd/test_seed_fidelity.cpp).
// Scaling E_x, E_y and G together scales C and ∇C alike, so the correction does not depend on the
// moduli's absolute scale (research §5.3 #7, tested): only their ratios and the Poisson ratios
// matter; stiffness comes from the iteration and substep counts. Near rest C ∝ δ² (δ the strain),
// so a step to the linearised C = 0 roughly halves δ and leaves at least ¼ of C (0.26–0.33
// measured): cloth converges geometrically, and iterations matter (tested).
//
// Deliberate differences from the seed:
//  - c_xy is the mean of the seed's two off-diagonal entries E_x ν_yx and E_y ν_xy (over
//    1 − ν_xy ν_yx). They are equal for every reciprocal material (ν_xy/E_x = ν_yx/E_y, the
//    defaults included), so nothing changes there; otherwise the seed's stress is not the
//    gradient of its energy, and here ∇C stays the exact gradient of C.
//  - Each modulus from its own key (cloth_xx/yy/xyStiffness): the seed's setters write xx into
//    yy and xy (research §5.3 #4).
// Pure functions (positions in, corrections out); nothing allocates.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "pbd/math/types.h"
#include "pbd/model/body_states.h"

namespace pbd {

struct Scene;

/// The in-plane stiffness of an orthotropic membrane (see above).
struct OrthotropicStiffness {
  Real xx = 0;     ///< c_xx = E_x/(1 − ν_xy ν_yx)
  Real yy = 0;     ///< c_yy = E_y/(1 − ν_xy ν_yx)
  Real xy = 0;     ///< c_xy = ½ (E_x ν_yx + E_y ν_xy)/(1 − ν_xy ν_yx)
  Real shear = 0;  ///< G
};

/// From E_x, E_y, G and the Poisson ratios ν_xy, ν_yx (ν_xy ν_yx < 1, checked by the loader).
OrthotropicStiffness orthotropicStiffness(Real youngsX, Real youngsY, Real shear, Real poissonXY,
                                          Real poissonYX);

struct FemTriangleConstraint {
  std::array<int, 3> particles{-1, -1, -1};
  Real area = 0;                                                              ///< A, at t = 0
  Eigen::Matrix<Real, 2, 2> restInverse = Eigen::Matrix<Real, 2, 2>::Zero();  ///< B = D_m⁻¹
  OrthotropicStiffness stiffness;
  /// No correction when Σ w_i |∇_iC|² ≤ cutoff (femCutoffFor: the seed's 10⁻⁶ in `pbd`).
  Real cutoff = 0;
};

/// A and B of the rest triangle in the frame above. False for a degenerate triangle (zero area)
/// and for |det D_m| ≤ minimumDeterminant (the seed's builder: 10⁻⁶).
bool femTriangleRest(const std::array<Vector3, 3>& rest, Real& area,
                     Eigen::Matrix<Real, 2, 2>& restInverse, Real minimumDeterminant = 0);

/// The Green strain E = ½ (FᵀF − I) in the material frame.
Eigen::Matrix<Real, 2, 2> femTriangleStrain(const std::array<Vector3, 3>& x,
                                            const FemTriangleConstraint& c);

/// C = A ψ.
Real femTriangleEnergy(const std::array<Vector3, 3>& x, const FemTriangleConstraint& c);

/// ∇_{x_i}C, i = 0, 1, 2.
std::array<Vector3, 3> femTriangleGradients(const std::array<Vector3, 3>& x,
                                            const FemTriangleConstraint& c);

/// The PBD projection (no stiffness factor); no correction when Σ w_i |∇_iC|² is 0 (every
/// particle static, or C = 0 at its minimum) or not above c.cutoff.
std::array<Vector3, 3> femTrianglePbd(const std::array<Vector3, 3>& x,
                                      const std::array<Real, 3>& inverseMasses,
                                      const FemTriangleConstraint& c);

/// One constraint per triangle of every triangle model when clothSimulationMethod is 2, with
/// cloth_xxStiffness (E_x), cloth_yyStiffness (E_y), cloth_xyStiffness (G),
/// cloth_xyPoissonRatio, cloth_yxPoissonRatio; in the models' triangle order; none whose three
/// particles are static or whose rest triangle is degenerate.
std::vector<FemTriangleConstraint> femTriangleConstraints(const Scene& scene);

/// One Gauss–Seidel sweep over `constraints` in order.
void solveFemTriangles(const std::vector<FemTriangleConstraint>& constraints,
                       ParticleStates& particles, std::size_t begin = 0,
                       std::size_t end = SIZE_MAX);

}  // namespace pbd
