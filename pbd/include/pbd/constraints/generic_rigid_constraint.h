// Generic rigid-body constraints: a user-supplied constraint C(poses) ∈ R^dim over N rigid
// bodies, pose i = (xᵢ, qᵢ) — xᵢ the centre of mass, qᵢ the rotation principal frame → world
// (RigidBodyStates' convention: body-fixed points are xᵢ + Rᵢ aᵢ with aᵢ in the principal frame).
// The rigid-body counterpart of generic_constraint.h (the seed's
// PositionBasedGenericConstraints has only the particle version; this is our extension).
//
// Rotation convention: θᵢ is a world-frame rotation vector applied on the left,
// qᵢ ← exp(θᵢ/2) ⊗ qᵢ, so a body-fixed point moves by δθ × (p − xᵢ) (the joints' convention,
// joint_parts.h). The Jacobian of body i is Jᵢ = [∂C/∂xᵢ, ∂C/∂θᵢ] (dim × 6, at θ = 0) and its
// generalised inverse mass Wᵢ = diag(mᵢ⁻¹ 𝟙₃, I_w,ᵢ⁻¹) (world inverse inertia R D⁻¹ Rᵀ; zero for
// a static body). One projection (XPBD, Macklin, Müller, Chentanez 2016, eq. 18; with α = 0 the
// Gauss–Newton step of PBD, Deul, Charrier, Bender 2014 §4 for rigid bodies):
//   K = Σᵢ Jᵢ Wᵢ Jᵢᵀ + α̃ 𝟙   (α̃ = α/h², α the compliance, h the substep)
//   Δλ = K⁻¹ (−C − α̃ λ),      λ ← λ + k Δλ
//   Δxᵢ = k mᵢ⁻¹ J_x,ᵢᵀ Δλ,   Δθᵢ = k I_w,ᵢ⁻¹ J_θ,ᵢᵀ Δλ,   qᵢ ← normalise(qᵢ + ½ (0, Δθᵢ) ⊗ qᵢ)
// (k ∈ [0, 1] the PBD stiffness, an under-relaxation as in the particle version; λ collects what
// was applied). For C invariant under a common translation, Σᵢ J_x,ᵢ = 0 and the linear
// momentum Σ mᵢ Δxᵢ = k (Σᵢ J_x,ᵢ)ᵀ Δλ = 0; invariant under a common rotation about the origin
// (xᵢ ← δφ × xᵢ, θᵢ = δφ), Σᵢ (J_θ,ᵢ − J_x,ᵢ [xᵢ]×) = 0, so the angular momentum about the
// origin Σᵢ (mᵢ xᵢ × Δxᵢ + I_w,ᵢ Δθᵢ) = k Σᵢ ([xᵢ]× J_x,ᵢᵀ + J_θ,ᵢᵀ) Δλ = 0 to first order.
//
// Singular K — no correction — as in the particle version: trace(K without α̃) not positive and
// finite (every body static, or ∇C = 0), or a pivot of the pivoted LDLᵀ of K + α̃ 𝟙 at most
// kGenericSingularPivotFactor · ε · trace(K + α̃ 𝟙). Relative, hence free of units: every entry
// of K has the units of C²/kg (mᵢ⁻¹ |∂C/∂x|² and |∂C/∂θ|² / (kg m²) alike). The round-off of a
// zero pivot is about (6N + dim) ε trace(K) ≤ 30 ε trace(K); the factor 1000 leaves 30× margin.
//
// Without a user gradient J comes from central differences:
//   position coordinate j: step hⱼ = ε^(1/3) · max(1, |xⱼ|), the representable
//     (xⱼ + hⱼ) − (xⱼ − hⱼ) used as the step (metres; as generic_constraint.h);
//   rotation component k: qᵢ± = normalise(exp(±h_θ eₖ / 2) ⊗ qᵢ), the exact rotations by ±h_θ
//     about the world axis eₖ, h_θ = ε^(1/3) rad. The perturbation is about θ = 0, so there is
//     no magnitude to scale by, and C varies with θ on the scale of 1 rad times the lever arms —
//     as with x in metres — so ε^(1/3) balances the truncation O(h²) against the cancellation
//     O(ε/h) here too: an error of about ε^(2/3) (~4·10⁻¹¹ in double) relative to C's scale.
// That is 12 evaluations of C per body, static bodies included (their columns are unused).
//
// Limits (fixed sizes: a solve allocates nothing): at most kGenericRigidMaxBodies = 4 bodies and
// kGenericRigidMaxComponents = 6 components; bigger constraints are rejected at construction
// with std::invalid_argument. The callbacks receive the poses of bodies 0..N−1 in fixed-size
// arrays (GenericRigidPoses); the value callback writes rows 0..dim−1 of a 6-vector, the
// gradient callback the block (0..dim−1) × (0..6N−1) of a 6 × 24 matrix, columns 6i..6i+2 being
// ∂C/∂xᵢ and 6i+3..6i+5 ∂C/∂θᵢ (the rest is ignored). They must be deterministic and must not
// allocate if the step is to allocate nothing.
//
// In a World (model/world.h), add constraints to World::constraints.genericRigidConstraints in C++
// after buildWorld (scenes have no key for them: a C is code). They are solved right after the
// joints (and the stiff-rod trees), in every position iteration of the seed's step and once per
// substep in the XPBD step, as XPBD constraints in both: λ is reset at the start of every substep
// and accumulates over its iterations (with α = 0 and k = 1 a hard Gauss–Newton projection, as the
// seed's joints).
#pragma once

#include <array>
#include <functional>
#include <vector>

#include "pbd/constraints/generic_constraint.h"
#include "pbd/joints/constraint_rows.h"
#include "pbd/math/types.h"
#include "pbd/model/body_states.h"

namespace pbd {

inline constexpr int kGenericRigidMaxBodies = 4;
inline constexpr int kGenericRigidMaxComponents = 6;

/// The poses of a generic rigid constraint's bodies: entries 0..N−1 (the rest unused).
struct GenericRigidPoses {
  std::array<Vector3, kGenericRigidMaxBodies> position;     ///< centre of mass, world
  std::array<Quaternion, kGenericRigidMaxBodies> rotation;  ///< principal frame → world

  GenericRigidPoses() {
    position.fill(Vector3::Zero());
    rotation.fill(Quaternion::Identity());
  }
};

/// C: rows ≥ dim unused.
using GenericRigidValue = Eigen::Matrix<Real, kGenericRigidMaxComponents, 1>;
/// ∇C: row r, column 6i + c is ∂C_r/∂(xᵢ)_c for c < 3 and ∂C_r/∂(θᵢ)_{c−3} for c ≥ 3.
using GenericRigidJacobian =
    Eigen::Matrix<Real, kGenericRigidMaxComponents, 6 * kGenericRigidMaxBodies>;

/// Writes C(poses) into `value` (rows 0..dim−1).
using GenericRigidValueFunction =
    std::function<void(const GenericRigidPoses& poses, GenericRigidValue& value)>;
/// Writes ∇C(poses) into `gradient` (rows 0..dim−1, columns 0..6N−1).
using GenericRigidGradientFunction =
    std::function<void(const GenericRigidPoses& poses, GenericRigidJacobian& gradient)>;

class GenericRigidConstraint {
 public:
  /// `bodies`: 1 to 4 distinct, non-negative rigid-body indices (World::bodies.rigid);
  /// `components`: dim, 1 to 6; `value` required; `gradient` optional (empty: central
  /// differences); `stiffness` in [0, 1]; `compliance` α ≥ 0 (m/N for a C in metres; 0: hard).
  /// Throws std::invalid_argument otherwise.
  GenericRigidConstraint(const std::vector<int>& bodies, int components,
                         GenericRigidValueFunction value,
                         GenericRigidGradientFunction gradient = {}, Real stiffness = 1,
                         Real compliance = 0);

  int bodyCount() const { return bodyCount_; }
  int componentCount() const { return componentCount_; }
  int body(int i) const { return bodies_[std::size_t(i)]; }
  Real stiffness() const { return stiffness_; }
  Real compliance() const { return compliance_; }
  bool hasGradient() const { return static_cast<bool>(gradient_); }

  void evaluate(const GenericRigidPoses& poses, GenericRigidValue& value) const {
    value_(poses, value);
  }
  /// The user's gradient, or central differences of the value (the steps above).
  void jacobian(const GenericRigidPoses& poses, GenericRigidJacobian& gradient) const;

  /// λ accumulated in the current substep (rows 0..dim−1).
  const GenericRigidValue& multiplier() const { return multiplier_; }
  GenericRigidValue& multiplier() { return multiplier_; }

 private:
  std::array<int, kGenericRigidMaxBodies> bodies_{};
  int bodyCount_ = 0;
  int componentCount_ = 0;
  GenericRigidValueFunction value_;
  GenericRigidGradientFunction gradient_;
  Real stiffness_ = 1;
  Real compliance_ = 0;
  GenericRigidValue multiplier_ = GenericRigidValue::Zero();
};

/// Inverse masses of the bodies 0..N−1 of a constraint: linear mᵢ⁻¹ and angular I_w,ᵢ⁻¹ (world).
using GenericRigidInverseMasses = std::array<EndInverseMass, kGenericRigidMaxBodies>;

/// The corrections of one projection (entries 0..N−1), and whether K was regular.
struct GenericRigidCorrection {
  std::array<Vector3, kGenericRigidMaxBodies> linear;        ///< Δxᵢ
  std::array<Vector3, kGenericRigidMaxBodies> angular;       ///< Δθᵢ (world rotation vector)
  GenericRigidValue multiplier = GenericRigidValue::Zero();  ///< k Δλ, what λ gains
  bool applied = false;  ///< false: K singular (or C not finite), no correction

  GenericRigidCorrection() {
    linear.fill(Vector3::Zero());
    angular.fill(Vector3::Zero());
  }
};

/// One projection of `constraint` at `poses` (see above): α̃ = α/h² (0: PBD) and the λ
/// accumulated so far (rows 0..dim−1).
GenericRigidCorrection genericRigidProjection(const GenericRigidConstraint& constraint,
                                              const GenericRigidPoses& poses,
                                              const GenericRigidInverseMasses& inverseMasses,
                                              Real complianceTilde,
                                              const GenericRigidValue& multiplier);

/// One Gauss–Seidel sweep over `constraints` in order, each with α̃ = α/substepSize²; λ is reset
/// first when `firstIteration` (the start of a substep). Throws std::out_of_range for a body
/// index beyond `bodies` (an error of the caller; nothing is moved by that constraint).
void solveGenericRigidConstraints(std::vector<GenericRigidConstraint>& constraints,
                                  RigidBodyStates& bodies, Real substepSize, bool firstIteration);

}  // namespace pbd
