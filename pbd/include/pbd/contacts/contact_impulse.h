// The velocity-level contact impulse shared by every contact family (rigid–rigid and
// particle–rigid): the seed's model and the corrected one (docs/seed.md#rigid-contacts;
// docs/contacts.md).
//
// A contact joins end 0 (the tested point) and end 1 (the SDF body) at world points c₀, c₁
// with lever arms r_k = c_k − x_k, unit normal n out of body 1, and d = n·(c₀ − c₁) < 0 (the
// depth inside the tolerance shell). Relative velocity u = (v₀ + ω₀ × r₀) − (v₁ + ω₁ × r₁),
// K = K₀ + K₁ with K_k = w_k 𝟙 − [r_k]× J_k [r_k]× (w inverse mass, J world inverse inertia;
// a particle has K = w 𝟙). Once per step, at detection, from the velocities u⁰ then:
//   m_n = 1/(nᵀ K n)                               normal effective mass
//   ū   = −e u⁰_n if u⁰_n < 0, else 0             target normal velocity (seed)
//         −e u⁰_n if u⁰_n < −v_th, else 0         (corrected; v_th = 2|g|h, below which a
//                                                  contact is resting: gravity alone brings
//                                                  |g|h of approach per step)
//   t   = tangential part of u⁰, normalised if |t|² > 10⁻⁶ (seed: frozen for the step)
//   p_max = (u⁰·t)/(tᵀ K t)                        impulse that stops the sliding (seed)
//   K_t = Tᵀ K T, T = [t₁ t₂] an orthonormal tangent basis (corrected)
// Each of the maxIterationsV velocity iterations, at the current u:
//   Δp_n = max(m_n (ū − u_n), −P_n) + k_c m_n max(−d, 0),   P_n ← P_n + Δp_n ≥ 0
// (the accumulated normal impulse stays non-negative; the penalty term k_c |d| — k_c the
// contact stiffness, in 1/s — pushes out of the shell), then friction:
//   seed:      Δp_t = −clamp(μ Δp_n, −p_max, p_max) t     per iteration, frozen t
//   corrected: s = Tᵀ(u + K n Δp_n) the slip after the normal impulse, ŝ = s/|s|,
//              λ_t ← Π_{|λ| ≤ μ P_n}(λ_t − |s|/(ŝᵀ K_t ŝ) ŝ),  Δp_t = T (λ_t − λ_t,old)
//              (Coulomb cone on the accumulated impulse; friction along the current slip,
//              re-evaluated every iteration)
// and the impulse p = Δp_n n + Δp_t is applied: +p at c₀, −p at c₁.
// Corrected model only, warm start: a contact found again in the next step (the same point of
// the same body against the same SDF) starts from its previous accumulated impulses,
// P_n and the projection of the previous tangential impulse onto the new tangent plane
// (clamped to the cone), applied before the first iteration. Five Gauss–Seidel sweeps do not
// converge the coupled normal and friction rows of a body resting on several points; without
// the warm start the residual leaves a box on four corners rocking (ω ≈ 3·10⁻³ rad/s) and
// walking sideways (≈ 30 µm/s at k_c = 100/s). The seed has no warm start, and no friction at
// rest (its tangent is not normalised below 1 mm/s), so it shows neither.
// References: Bender, Erleben, Trinkle, "Interactive simulation of rigid body dynamics in
// computer graphics", CGF 33(1), 2014, §4 (velocity-level impulses, K matrix); Catto,
// "Iterative dynamics with temporal coherence", GDC 2005 (accumulated impulses, clamping the
// friction on the accumulated value).
#pragma once

#include "pbd/math/types.h"
#include "pbd/model/scene.h"

namespace pbd {

using Matrix2 = Eigen::Matrix<Real, 2, 2>;

/// Settings that change with the step, shared by all contacts of one detection.
struct ContactSolveSettings {
  ContactModel model = ContactModel::Seed;
  /// Corrected model: approach speeds at or below this get no restitution (2|g|h).
  Real restitutionThreshold = 0;
};

struct ContactImpulse {
  Vector3 normal = Vector3::UnitY();
  Real normalMass = 0;            ///< m_n = 1/(nᵀKn)
  Real targetNormalVelocity = 0;  ///< ū
  Real penaltyVelocity = 0;       ///< k_c max(−d, 0)
  Real friction = 0;              ///< μ
  // Seed friction.
  Vector3 tangent = Vector3::Zero();  ///< frozen sliding direction
  Real maxFrictionImpulse = 0;        ///< p_max
  // Corrected friction.
  Vector3 tangent1 = Vector3::UnitX(), tangent2 = Vector3::UnitZ();
  Matrix2 tangentInverseMass = Matrix2::Zero();     ///< K_t = TᵀKT
  Vector2 tangentNormalCoupling = Vector2::Zero();  ///< TᵀKn: slip caused by a normal impulse
  // Accumulated over the iterations.
  Real normalImpulse = 0;                    ///< P_n
  Vector2 tangentImpulse = Vector2::Zero();  ///< λ_t (corrected)
};

/// K of one end at lever arm r: w 𝟙 − [r]× J [r]×.
Matrix3 pointInverseMass(Real inverseMass, const Matrix3& inverseInertiaWorld, const Vector3& r);

/// Fills `c` from the normal, K, the relative velocity at detection u⁰ and the material.
void initContactImpulse(ContactImpulse& c, const Vector3& normal, const Matrix3& k,
                        const Vector3& initialRelativeVelocity, const ContactMaterial& material,
                        Real penaltyVelocity, const ContactSolveSettings& settings);

/// Corrected model: starts from the previous step's impulses of the same contact; returns the
/// impulse to apply (+ at end 0, − at end 1) before the iterations.
Vector3 warmStartContactImpulse(ContactImpulse& c, Real previousNormalImpulse,
                                const Vector3& previousTangentImpulse);

/// The accumulated tangential impulse in world coordinates (corrected model).
inline Vector3 tangentImpulseWorld(const ContactImpulse& c) {
  return c.tangentImpulse.x() * c.tangent1 + c.tangentImpulse.y() * c.tangent2;
}

/// One iteration at the current relative velocity u: returns p, to apply +p at end 0 and −p
/// at end 1, and updates the accumulated impulses.
Vector3 contactIterationImpulse(ContactImpulse& c, const Vector3& relativeVelocity,
                                ContactModel model);

}  // namespace pbd
