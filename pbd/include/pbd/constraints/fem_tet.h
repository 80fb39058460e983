// Linear FEM tetrahedra with the St. Venant–Kirchhoff material, the energy used as the
// constraint: the solids of solidSimulationMethod 2 (PBD, the seed's default) and 3 (XPBD)
// (Bender, Koschier, Charrier, Weber 2014, "Position-based simulation of continuous materials";
// docs/seed.md#fem-tets and #stiffness). For a tet (x₀, x₁, x₂, x₃) with D = [x₀ − x₃, x₁ − x₃, x₂
// − x₃] (the seed's edges, from x₃) and D_m the same at t = 0, V₀ = |det D_m| / 6 (every quantity
// is evaluated in the seed's operation order, so that the `pbd` method follows the original's
// round-off too):
//   F = D D_m⁻¹,  ε = ½ (FᵀF − I)  (Green strain),
//   ψ = μ ε:ε + ½ λ_L tr(ε)²,  μ = E / (2 (1 + ν)),  λ_L = E ν / ((1 + ν)(1 − 2ν)),
//   U = V₀ ψ,  P = F (2μ ε + λ_L tr(ε) I)  (first Piola–Kirchhoff stress),
//   [∇_{x₀}U ∇_{x₁}U ∇_{x₂}U] = V₀ P D_m⁻ᵀ,  ∇_{x₃}U = −(∇_{x₀}U + ∇_{x₁}U + ∇_{x₂}U).
// U ≥ 0 (ν ∈ [0, 0.49] makes λ_L ≥ 0), U = 0 and ∇U = 0 at every rigid motion of the rest state
// (up to round-off); the gradients sum to zero, so w-weighted corrections conserve linear momentum.
//
// Inversion (J = det F = V/V₀ with the signed volumes, J ≤ 0): F = U Σ Vᵀ by SVD with U, V made
// rotations (the smallest singular value takes the sign of J), every singular value clamped to
// ≥ 0.577 (≈ 1/√3, the seed's value), and U, ∇U evaluated at F̂ = U Σ̂ Vᵀ: P(F̂) pushes the tet
// back towards positive volume. ∇U is then the gradient of U(F̂) with Σ̂ held, not an exact
// gradient. The seed enters this path when V/V₀ < 0.2 and V ≤ 0 (docs/seed.md#fem-tets), i.e.
// J ≤ 0 for a positively listed tet; here J uses the signed V₀, so a tet listed with negative
// orientation is not taken as inverted at rest (cf. the volume constraint, §5.3 #11).
//
// Method 2, PBD with C = U and no stiffness factor (the seed's semantics, kept deliberately):
//   s = U / Σ w_i |∇_iU|²,  Δx_i = −s w_i ∇_iU.
// Scaling E scales U and ∇U alike, so the correction does not depend on E at all, only on ν,
// the iteration and substep counts (docs/seed.md#fem-modulus-scale): E = 1 (the forced default)
// is as stiff as E = 10⁹. The seed skips every correction with Σ w|∇U|² < 10⁻⁶ (and, for
// XPBD, Σ w|∇U′|² + α̃ C² < 10⁻⁶) and builds no element with |det D_m| ≤ 10⁻⁶:
// FemTetConstraint::cutoff and femTetRestState's minimumDeterminant, femCutoffFor(settings)
// (10⁻⁶ for the `pbd` method, 0 for `pbd.xpbd`, where only a state at rest is skipped). So
// small strains of small tets go uncorrected in the seed, and E's scale matters there after all.
// Method 3, XPBD with C = √(2U/E), so ½ E C² = U; α̃ = 1/(E h_s²), λ reset every substep:
//   Δλ = (−C − α̃ λ) / (Σ w_i |∇_iC|² + α̃),  Δx_i = w_i Δλ ∇_iC,  ∇C = ∇U / (E C);
// computed with g = ∇U/E (finite as C → 0) as Δλ = C² (−C − α̃ λ)/(Σ w|g|² + α̃ C²),
// Δx_i = w_i g_i C (−C − α̃ λ)/(Σ w|g|² + α̃ C²). λ accumulates the true Δλ; the seed
// accumulates Δλ/C (§5.3 #8), which differs from the second iteration of a substep on.
// The seed's FEM solve returns false for ν outside [0, 0.49]; here the scene loader rejects such
// a ν, the PBD engine adapter reports it unsupported, and solidFemConstraints makes no
// constraint for it (documented below) rather than an ill-posed material (ν = ½ divides by 0).
// Pure functions (positions in, corrections out); nothing allocates (fixed-size SVD).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "pbd/math/types.h"
#include "pbd/model/body_states.h"

namespace pbd {

struct Scene;

/// The seed's clamp of the singular values of F on the inversion path.
inline constexpr Real kFemInversionMinimumSingularValue = Real(0.577);

struct FemTetConstraint {
  std::array<int, 4> particles{-1, -1, -1, -1};
  Matrix3 inverseRestMatrix = Matrix3::Identity();  ///< D_m⁻¹, at t = 0
  Real restVolume = 0;                              ///< V₀ = |det D_m| / 6 > 0
  Real youngsModulus = 1;                           ///< E (solidStiffnessFor)
  Real poissonRatio = Real(0.3);                    ///< ν ∈ [0, 0.49]
  bool xpbd = false;                                ///< false: method 2 (PBD); true: 3 (XPBD)
  Real multiplier = 0;                              ///< λ of the current substep (XPBD)
  /// No correction when Σ w_i |∇_iC|² (+ α̃ C² for XPBD) < cutoff (femCutoffFor: the
  /// seed's 10⁻⁶ in `pbd`).
  Real cutoff = 0;
};

struct LameParameters {
  Real mu = 0;      ///< shear modulus μ = E / (2 (1 + ν))
  Real lambda = 0;  ///< λ_L = E ν / ((1 + ν)(1 − 2ν))
};

LameParameters lameParameters(Real youngsModulus, Real poissonRatio);

/// D_m⁻¹ and V₀ of the tet `rest`; false for a degenerate tet (|det D_m| no larger than the
/// round-off of the product of its edge lengths, or than minimumDeterminant: the seed's 10⁻⁶).
bool femTetRestState(const std::array<Vector3, 4>& rest, Matrix3& inverseRestMatrix,
                     Real& restVolume, Real minimumDeterminant = 0);

/// F = D D_m⁻¹.
Matrix3 femDeformationGradient(const std::array<Vector3, 4>& x, const Matrix3& inverseRestMatrix);

struct FemTetEnergy {
  Real energy = 0;  ///< U = V₀ ψ (at F̂ on the inversion path)
  std::array<Vector3, 4> gradients{Vector3::Zero(), Vector3::Zero(), Vector3::Zero(),
                                   Vector3::Zero()};  ///< ∇_{x_i}U
  bool inverted = false;                              ///< det F ≤ 0: the inversion path
};

/// U and ∇U of the constraint's tet at `x` (the inversion path when det F ≤ 0).
FemTetEnergy femTetEnergy(const std::array<Vector3, 4>& x, const FemTetConstraint& c);

struct FemTetCorrection {
  std::array<Vector3, 4> positions{Vector3::Zero(), Vector3::Zero(), Vector3::Zero(),
                                   Vector3::Zero()};
  Real multiplier = 0;  ///< Δλ (XPBD; 0 for PBD)
};

/// Method 2: the PBD projection of C = U (no stiffness factor); none when Σ w|∇U|² ≤ ε² or
/// < c.cutoff.
FemTetCorrection femTetPbd(const std::array<Vector3, 4>& x,
                           const std::array<Real, 4>& inverseMasses, const FemTetConstraint& c);

/// Method 3: the XPBD projection of C = √(2U/E) at substep size h_s with λ = c.multiplier.
FemTetCorrection femTetXpbd(const std::array<Vector3, 4>& x,
                            const std::array<Real, 4>& inverseMasses, const FemTetConstraint& c,
                            Real substepSize);

/// One FEM constraint per tet of every tet model when solidSimulationMethod is 2 (PBD) or 3
/// (XPBD), with E = solidStiffnessFor and ν = solid_poissonRatio; none for tets of four static
/// particles or degenerate rest tets; none at all when ν is outside [0, 0.49] (the seed's solve
/// rejects it; the PBD engine adapter reports such a scene unsupported before building it).
std::vector<FemTetConstraint> solidFemConstraints(const Scene& scene);

/// One Gauss–Seidel sweep over `constraints` in order; the XPBD ones reset λ first when
/// `firstIteration` (the start of a substep of size `substepSize`).
void solveFemTets(std::vector<FemTetConstraint>& constraints, ParticleStates& particles,
                  Real substepSize, bool firstIteration, std::size_t begin = 0,
                  std::size_t end = SIZE_MAX);

}  // namespace pbd
