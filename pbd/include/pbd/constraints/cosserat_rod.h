// Cosserat rods (Kugelstadt & Schömer 2016, "Position and orientation based Cosserat rods",
// SCA): a chain of particles p₀ … p_N and one orientation quaternion q_k per segment
// (p_k, p_{k+1}); the director frame of a segment is (d₁, d₂, d₃) = R(q_k) (e₁, e₂, e₃) with d₃
// along the segment at rest. Two constraint families.
//
// Stretch–shear (one per segment, rest length ℓ; paper eq. 31–37):
//   C_ss(p₀, p₁, q) = (p₁ − p₀)/ℓ − d₃(q),   d₃(q) = q e₃ q̄   (a world vector, 3 rows)
//   ∇_{p₀}C = −I/ℓ,  ∇_{p₁}C = I/ℓ,  ∇_q C: (∇_q C)ᵀ v = −2 [0, v] q ē₃  (4-vector per row v)
//   With q treated as a 4-vector of inverse "mass" w_q, Σ w ∇C ∇Cᵀ = ((w₀ + w₁)/ℓ² + 4 w_q) I,
//   a multiple of the identity, so the 3 rows decouple in any orthonormal frame.
// Bend–twist (one per pair of neighbouring segments; paper eq. 38–40):
//   Ω = q̄₀ q₁ (the discrete Darboux quaternion, expressed in the frame of q₀),
//   C_bt(q₀, q₁) = Im(Ω − s Ω₀),  s = ±1 whichever makes |Ω − s Ω₀| smaller (q and −q are the
//   same rotation; the seed's "sign closest to identity"), Ω₀ the rest value.
//   (∇_{q₀}C)ᵀ v = −q₁ [0, v],  (∇_{q₁}C)ᵀ v = q₀ [0, v];  Σ w ∇C ∇Cᵀ = (w_{q0} + w_{q1}) I.
//   Rows 1, 2 are bending about d₁, d₂ of q₀; row 3 is twist about d₃.
// Quaternion corrections are added to the coefficients and the quaternion is renormalised.
// A quaternion of 4-vector inverse mass w_q has the kinetic energy ½ (1/(4 w_q)) |ω|²: its
// rotational inertia is I = 1/(4 w_q), isotropic (the seed integrates orientations with an
// isotropic inertia and no torque; docs/seed.md#the-step).
//
// Two variants:
//  PBD (the seed's PositionBasedCosseratRods): per-iteration fractions k ∈ [0, 1],
//    Δλ = −k ∘ C / (Σ w|∇C|²) row by row; the stretch–shear fractions (k_shear1, k_shear2,
//    k_stretch) act in the director frame of q (the seed after its PR #65), the bend–twist ones
//    (k_bend1, k_bend2, k_twist) in the frame of q₀. Stiffness depends on iterations/substeps.
//  XPBD (pbdval's; physical moduli): the discrete elastic energy
//    E_ss = ½ ℓ Σ_i k_i (d_iᵀ C_ss)²,  k = (κGA, κGA, EA)   [N]
//    E_bt = ½ ℓ̄ Σ_i K_i ((2/ℓ̄) C_bt,i)²,  K = (EI, EI, GJ)  [N m²], ℓ̄ the mean length of the
//    two segments, (2/ℓ̄) Im(q̄₀ q₁) ≈ the curvature/twist per metre (paper eq. 12),
//  i.e. per-row compliances α_ss,i = 1/(ℓ k_i) and α_bt,i = ℓ̄/(4 K_i), α̃ = α/h_s²,
//    Δλ_i = −(C_i + α̃_i λ_i)/(Σ w|∇C|² + α̃_i),  λ accumulated over the iterations of a
//  substep (reset at its first), the stretch–shear rows in the director frame of q (held fixed
//  during one projection).
// Differences from the seed: the XPBD variant and its moduli are pbdval's; the seed's ε in
// the denominators is replaced by "no correction when every weight is 0". Pure functions;
// nothing allocates.
#pragma once

#include <array>
#include <vector>

#include "pbd/math/types.h"
#include "pbd/model/body_states.h"

namespace pbd {

struct Scene;

using Matrix34 = Eigen::Matrix<Real, 3, 4>;

/// d₃(q) = q e₃ q̄ written bilinearly in the coefficients (exact for non-unit q too, which the
/// finite-difference tests need): (2(xz + wy), 2(yz − wx), w² − x² − y² + z²).
Vector3 rodTangentDirector(const Quaternion& q);

/// C_ss = (p₁ − p₀)/ℓ − d₃(q).
Vector3 stretchShearValue(const Vector3& p0, const Vector3& p1, const Quaternion& q,
                          Real restLength);
/// ∂C_ss/∂q as a 3×4 matrix, columns in Eigen's coefficient order (x, y, z, w).
Matrix34 stretchShearQuaternionJacobian(const Quaternion& q);

/// C_bt = Im(q̄₀ q₁ − s Ω₀) with s = ±1 minimising |q̄₀ q₁ − s Ω₀|.
Vector3 bendTwistValue(const Quaternion& q0, const Quaternion& q1, const Quaternion& restDarboux);
/// ∂C_bt/∂q₀ and ∂C_bt/∂q₁ (3×4, coefficient order x, y, z, w) at fixed s.
Matrix34 bendTwistJacobianFirst(const Quaternion& q1);
Matrix34 bendTwistJacobianSecond(const Quaternion& q0);

/// The rest Darboux quaternion q̄₀ q₁ of two rest frames, with the sign whose scalar part is
/// non-negative (closest to the identity).
Quaternion restDarbouxQuaternion(const Quaternion& q0, const Quaternion& q1);

struct StretchShearCorrection {
  Vector3 position0 = Vector3::Zero();
  Vector3 position1 = Vector3::Zero();
  Vector4 quaternion = Vector4::Zero();  ///< added to q.coeffs() (x, y, z, w), then normalise
  Vector3 multiplier = Vector3::Zero();  ///< Δλ in the director frame (XPBD; 0 for PBD)
};

struct BendTwistCorrection {
  Vector4 quaternion0 = Vector4::Zero();
  Vector4 quaternion1 = Vector4::Zero();
  Vector3 multiplier = Vector3::Zero();  ///< Δλ (XPBD; 0 for PBD)
};

/// PBD stretch–shear; `fractions` = (k_shear1, k_shear2, k_stretch) ∈ [0, 1]³ in the director
/// frame. w₀, w₁: particle inverse masses; wq: the quaternion's (4-vector) inverse mass.
StretchShearCorrection stretchShearPbd(const Vector3& p0, Real w0, const Vector3& p1, Real w1,
                                       const Quaternion& q, Real wq, Real restLength,
                                       const Vector3& fractions);
/// XPBD stretch–shear; `stiffness` = (κGA, κGA, EA) in N, λ the accumulated multiplier (director
/// frame) of the current substep of size h.
StretchShearCorrection stretchShearXpbd(const Vector3& p0, Real w0, const Vector3& p1, Real w1,
                                        const Quaternion& q, Real wq, Real restLength,
                                        const Vector3& stiffness, Real substepSize,
                                        const Vector3& multiplier);

/// PBD bend–twist; `fractions` = (k_bend1, k_bend2, k_twist) ∈ [0, 1]³.
BendTwistCorrection bendTwistPbd(const Quaternion& q0, Real wq0, const Quaternion& q1, Real wq1,
                                 const Quaternion& restDarboux, const Vector3& fractions);
/// XPBD bend–twist; `stiffness` = (EI, EI, GJ) in N m², `meanLength` ℓ̄ in m.
BendTwistCorrection bendTwistXpbd(const Quaternion& q0, Real wq0, const Quaternion& q1, Real wq1,
                                  const Quaternion& restDarboux, const Vector3& stiffness,
                                  Real meanLength, Real substepSize, const Vector3& multiplier);

/// Elastic energies of the XPBD variant (½ Σ α_i⁻¹ C_i², the energy the XPBD rows minimise).
Real stretchShearEnergy(const Vector3& p0, const Vector3& p1, const Quaternion& q, Real restLength,
                        const Vector3& stiffness);
Real bendTwistEnergy(const Quaternion& q0, const Quaternion& q1, const Quaternion& restDarboux,
                     const Vector3& stiffness, Real meanLength);

struct RodStretchShearConstraint {
  int model = 0;  ///< the line model's index in scene order
  std::array<int, 2> particles{-1, -1};
  int segment = -1;
  Real restLength = 0;
  bool xpbd = false;
  Vector3 stiffness = Vector3::Ones();  ///< PBD fractions, or (κGA, κGA, EA) in N
  Vector3 multiplier = Vector3::Zero();
};

struct RodBendTwistConstraint {
  int model = 0;  ///< the line model's index in scene order
  std::array<int, 2> segments{-1, -1};
  Quaternion restDarboux = Quaternion::Identity();
  Real meanLength = 0;  ///< ℓ̄, the mean rest length of the two segments
  bool xpbd = false;
  Vector3 stiffness = Vector3::Ones();  ///< PBD fractions, or (EI, EI, GJ) in N m²
  Vector3 multiplier = Vector3::Zero();
};

/// The rods of a world: their constraints, and the order in which a sweep solves them.
struct RodConstraints {
  std::vector<RodStretchShearConstraint> stretchShear;
  std::vector<RodBendTwistConstraint> bendTwist;
  /// The seed's solve order (set by orderRodsAsTheSeed): k ≥ 0 is stretchShear[k], k < 0 is
  /// bendTwist[−k − 1]. Empty: all stretch–shear, then all bend–twist, each in model and
  /// segment order.
  std::vector<int> seedOrder;
};

/// Puts the rods' constraints in PositionBasedDynamics' Gauss–Seidel order: its constraint list
/// (per line model, every stretch–shear constraint, then every bend–twist constraint) split
/// greedily into groups (SimulationModel::initConstraintGroups: a constraint joins the first
/// group in which none of its indices is marked), solved group by group. The seed marks a
/// constraint's `m_bodies` in one index space: a stretch–shear constraint marks its two particle
/// indices and its quaternion's index, a bend–twist constraint its two quaternions' indices, so
/// quaternion k and particle k block each other. On a rod of N segments (particles and
/// quaternions numbered from 0) that solves the stretch–shear constraints of even segments, then
/// those of odd segments, then the bend–twist constraints of even, then odd pairs. The rods are
/// coloured among themselves (the seed colours them with every other constraint of its list).
void orderRodsAsTheSeed(RodConstraints& rods);

/// The constraints of every line model of the scene, segments numbered across the models in
/// scene order (as World::bodies.segments). A model with youngsModulus and shearModulus gets
/// the XPBD variant (stretch κGA and EA, bend EI, twist GJ with I = πr⁴/4, J = πr⁴/2, κ the
/// model's shearFactor); otherwise the PBD one with the Simulation block's rod_* fractions.
RodConstraints rodConstraints(const Scene& scene);

/// One Gauss–Seidel sweep: in the seed's order when rods.seedOrder is set, else every
/// stretch–shear constraint, then every bend–twist constraint; XPBD multipliers are reset when
/// `firstIteration`. As the seed, a correction is applied to a particle or quaternion of nonzero
/// inverse mass only (a static segment's quaternion is not renormalised).
void solveRods(RodConstraints& rods, ParticleStates& particles, SegmentStates& segments,
               Real substepSize, bool firstIteration);

/// Σ of the XPBD rods' elastic energies at the current state (0 for PBD rods, which have none
/// in physical units).
Real rodElasticEnergy(const RodConstraints& rods, const ParticleStates& particles,
                      const SegmentStates& segments);

}  // namespace pbd
