// Generic particle constraints: a user-supplied constraint C: R^{3N} → R^dim over N particles
// (the seed's PositionBasedGenericConstraints::solve_GenericConstraint<nParticles, dim> for
// particles). The rigid-body version — C over the poses of up to 4 rigid bodies, with
// compliance — is generic_rigid_constraint.h.
//
// With Jᵢ = ∇_{xᵢ}C (dim × 3) and w the inverse masses, one PBD projection is the
// Gauss–Newton step of the constraint's linearisation:
//   K = Σᵢ wᵢ Jᵢ Jᵢᵀ   (dim × dim, symmetric positive semi-definite)
//   Δλ = K⁻¹ (−C),     Δxᵢ = k wᵢ Jᵢᵀ Δλ      (k ∈ [0, 1] the PBD stiffness, default 1)
// For a linear C and k = 1 one projection makes C = 0 exactly; for a C invariant under
// translation, Σᵢ Jᵢ = 0 and Σᵢ Δxᵢ/wᵢ = k (Σᵢ Jᵢ)ᵀ Δλ = 0 (linear momentum is conserved).
//
// K is factorised with Eigen's pivoted LDLᵀ. It is taken as singular — no correction — when
// its trace is not positive and finite (every particle static, or ∇C = 0) or when a pivot of
// the factorisation is at most kGenericSingularPivotFactor · ε · trace(K). The threshold is
// relative: K scales as w |∇C|², and so do its pivots and trace, so a constraint in millimetres
// and one in kilometres are judged alike (the seed rejects det K < 1e-6, an absolute test that
// depends on the units, on the masses and on dim). The round-off of a zero pivot is at most
// about (3N + dim) ε trace(K) ≤ 30 ε trace(K); the factor 1000 leaves 30× of margin, and with
// it K counts as singular when its condition number exceeds ~1/(1000 ε) (4.5·10¹² in double,
// 8·10³ in float). Redundant components (two rows of J parallel) are caught even with the
// central-difference J: their pivot is the square of its O(ε^(2/3)) error, ~ε^(4/3) trace(K).
//
// Without a user gradient, J comes from central differences, coordinate by coordinate, with the
// step hⱼ = ε^(1/3) · max(1, |xⱼ|) (positions in metres: 1 m is the scenes' length scale; ε^(1/3)
// balances the truncation error O(h²) against the cancellation O(ε/h)), the step used being
// the representable (xⱼ + hⱼ) − (xⱼ − hⱼ). Its error is O(h² C''') + O(ε C / h), about ε^(2/3)
// (~4·10⁻¹¹ in double) relative for C of size and curvature O(1).
//
// Limits (fixed sizes, so that a solve allocates nothing): at most kGenericMaxParticles = 8
// particles and kGenericMaxComponents = 6 components; bigger constraints are rejected at
// construction with std::invalid_argument. The callbacks receive the positions as the columns
// 0..N−1 of a 3 × 8 matrix; the value callback writes the rows 0..dim−1 of a 6-vector, the
// gradient callback the block (0..dim−1) × (0..3N−1) of a 6 × 24 matrix, column 3i + c being
// ∂C/∂(xᵢ)_c (the rest is ignored). The callbacks must not allocate if the step is to allocate
// nothing, and must be deterministic functions of the positions.
//
// In a World (model/world.h), add constraints to World::constraints.genericConstraints in C++ after
// buildWorld (scenes have no key for them); they are solved after every other particle
// constraint, once per position iteration in the seed's step and once per substep in the XPBD
// step (as PBD constraints there: k is per projection, not a compliance).
#pragma once

#include <array>
#include <functional>
#include <vector>

#include "pbd/math/types.h"
#include "pbd/model/body_states.h"

namespace pbd {

inline constexpr int kGenericMaxParticles = 8;
inline constexpr int kGenericMaxComponents = 6;
/// A pivot of K at most this · ε · trace(K) makes K singular (see above).
inline constexpr Real kGenericSingularPivotFactor = 1000;

/// Positions of a generic constraint's particles: column i is xᵢ (columns ≥ N unused).
using GenericPositions = Eigen::Matrix<Real, 3, kGenericMaxParticles>;
/// C: rows ≥ dim unused.
using GenericValue = Eigen::Matrix<Real, kGenericMaxComponents, 1>;
/// ∇C: row r, column 3i + c is ∂C_r/∂(xᵢ)_c; rows ≥ dim and columns ≥ 3N unused.
using GenericJacobian = Eigen::Matrix<Real, kGenericMaxComponents, 3 * kGenericMaxParticles>;

/// Writes C(x) into `value` (rows 0..dim−1).
using GenericValueFunction = std::function<void(const GenericPositions& x, GenericValue& value)>;
/// Writes ∇C(x) into `gradient` (rows 0..dim−1, columns 0..3N−1).
using GenericGradientFunction =
    std::function<void(const GenericPositions& x, GenericJacobian& gradient)>;

class GenericParticleConstraint {
 public:
  /// `particles`: 1 to 8 distinct, non-negative particle indices; `components`: dim, 1 to 6;
  /// `value` required; `gradient` optional (empty: central differences); `stiffness` in [0, 1].
  /// Throws std::invalid_argument otherwise.
  GenericParticleConstraint(const std::vector<int>& particles, int components,
                            GenericValueFunction value, GenericGradientFunction gradient = {},
                            Real stiffness = 1);

  int particleCount() const { return particleCount_; }
  int componentCount() const { return componentCount_; }
  int particle(int i) const { return particles_[std::size_t(i)]; }
  Real stiffness() const { return stiffness_; }
  bool hasGradient() const { return static_cast<bool>(gradient_); }

  void evaluate(const GenericPositions& x, GenericValue& value) const { value_(x, value); }
  /// The user's gradient, or central differences of the value (the step above).
  void jacobian(const GenericPositions& x, GenericJacobian& gradient) const;

 private:
  std::array<int, kGenericMaxParticles> particles_{};
  int particleCount_ = 0;
  int componentCount_ = 0;
  GenericValueFunction value_;
  GenericGradientFunction gradient_;
  Real stiffness_ = 1;
};

/// The corrections of one projection (columns 0..N−1), and whether K was regular.
struct GenericCorrection {
  GenericPositions delta = GenericPositions::Zero();
  bool applied = false;  ///< false: K singular (or C not finite), no correction
};

/// One PBD projection of `constraint` at positions `x` with inverse masses w (entries 0..N−1).
GenericCorrection genericConstraintPbd(const GenericParticleConstraint& constraint,
                                       const GenericPositions& x,
                                       const std::array<Real, kGenericMaxParticles>& inverseMasses);

/// One Gauss–Seidel sweep over `constraints` in order. Throws std::out_of_range for a particle
/// index beyond `particles` (an error of the caller; nothing is moved by that constraint).
void solveGenericConstraints(std::vector<GenericParticleConstraint>& constraints,
                             ParticleStates& particles);

}  // namespace pbd
