// XPBD contact (the `pbd.xpbd` method): a point of body 0 (a rigid body or a particle) against
// the surface of rigid body 1, solved at position level every substep with static friction,
// and dynamic friction and restitution in the velocity pass.
// Reference: Müller, Macklin, Chentanez, Jeschke, Kim 2020, "Detailed Rigid Body Simulation
// with Extended Position Based Dynamics", SCA, §3.5 (contacts), §3.6 (velocity level).
//
// Set up once per step from the collision detection (step start, speculative tolerance):
// the point r₀ fixed in body 0, its anchor r₁ on body 1's actual surface (the detector's shell
// point moved back by the tolerance: the closest surface point at detection) and the normal n
// fixed in body 1, all in the bodies' principal frames and re-evaluated every substep
// (p_k = x_k + R_k r_k, n = R₁ n₁).
//
// Position level, per substep (h the substep size), one pass:
//   C = n·(p₀ − p₁) ≥ 0;  active when C < 0:
//   Δλ_n = (−C − α̃ λ_n)/(w₀ + w₁ + α̃),  α̃ = α/h²,  w_k = m_k⁻¹ + (r_k × n)ᵀ I_k⁻¹ (r_k × n);
//   positional impulse P = Δλ_n n at p₀ on body 0 and −P at p₁ on body 1:
//   x₀ += m₀⁻¹ P, q₀ ← normalize(q₀ + ½ [0, I₀⁻¹ (r₀ × P)] ⊗ q₀), body 1 likewise with −P.
//   Evaluated in each body's principal frame (R_k the rotation q_k, D_k = diag(I_k⁻¹)):
//   u_k = R_kᵀ (r_k × n), w_k = m_k⁻¹ + u_kᵀ D_k u_k, and the turn as
//   q_k ← normalize(q_k + ½ q_k ⊗ [0, Δλ D_k u_k]) (the same update: [0, R v] ⊗ q = q ⊗ [0, v]),
//   one inverse rotation per body and row, none for body 1 of a normal row
//   (R₁ᵀ (R₁ a₁ × R₁ n₁) = a₁ × n₁, a₁ the anchor and n₁ the normal in its frame).
//   Static friction: d_t = the tangential part of p₀ − p₁, C_t = |d_t|, t = d_t / C_t,
//   Δλ_t = min(C_t / w_t, μ λ_n − λ_t) along −t. Unclamped, the point sticks to its anchor;
//   clamped, it slides (the Coulomb bound at position level) and the anchor moves under it
//   (p₁ ← p₀ − (n·(p₀ − p₁)) n); an inactive contact's anchor follows its point likewise.
// Velocity level, per substep, for contacts active in the substep (λ_n > 0):
//   u = (v₀ + ω₀ × r₀) − (v₁ + ω₁ × r₁), v_n = n·u, u_t = u − v_n n;
//   restitution: v_n → max(−e ṽ_n, 0), ṽ_n the normal velocity after the substep's prediction
//   (recorded only for contacts with e > 0; with e = 0 the target is 0);
//   e = 0 when |ṽ_n| ≤ 2|g|h (the paper's jitter threshold);
//   dynamic friction: an impulse against u_t of magnitude min((μ λ_n − λ_t)/h, |u_t|/w_t) —
//   what the Coulomb bound μ f_n h (f_n = λ_n/h²) leaves after the static friction.
//
// Deliberate differences from the paper (docs/methods.md, "pbd.xpbd"):
//   - the paper's static friction undoes the motion of the point over the substep,
//     Δp = (p₀ − p̄₀) − (p₁ − p̄₁), all or nothing (applied only if λ_t < μ_s λ_n). With one
//     Gauss–Seidel pass over the corners of a box, the first corner's normal correction turns
//     the box and slides that corner outwards by about 0.53 of the correction, so the test
//     fails for μ ≲ 0.5 and a box on an incline creeps (7 mm in 5 s, 5° below the friction
//     angle, μ = 0.5). Anchoring to the contact point of the step and clamping to the cone
//     instead of rejecting holds it (0.06 mm) and leaves the sliding friction Coulomb's;
//   - the paper writes the dynamic friction as Δv = −u_t/|u_t| min(h μ f_n, |u_t|), an
//     impulse compared with a velocity; here it is the impulse, bounded by Coulomb's law.
// One friction coefficient μ serves as static and dynamic (the scene has one per pair).
//
// Spheres (closed-form contacts, Simulation.contactGeometry "primitives"). A point fixed on a
// sphere leaves the contact as the sphere rolls: turned by θ = ω t it stands r (1 − cos θ)
// above the plane and moves along n at |ω| r sin θ, so a ball rolling at 8 m/s (r = 0.108 m,
// ω = 74 rad/s) had its only contact point 0.3 mm above the ground by the step's end, fell
// freely meanwhile, and the velocity pass measured the normal velocity of that turned point.
// A sphere's contact is therefore its support point, recomputed at every evaluation:
//   p₀ = c₀ − r₀ n (c₀ the centre, fixed in body 0), lever r₀ = p₀ − x₀;
//   when body 1 is a sphere too, n = (c₀ − c₁)/|c₀ − c₁| and p₁ = c₁ + r₁ n;
// so C = n·(p₀ − p₁) is the exact separation (plane: n·(c₀ − p₁) − r₀), a normal impulse acts
// through the centre, and the normal velocity at p₀ is the centre's (n·(ω × r₀) = 0).
// Static friction needs a material point instead (the support point of a ball rolling without
// slip moves at its speed, yet nothing slides): before each prediction the current support
// point becomes the friction point p₀ᵐ, fixed in body 0 for that substep, and the anchor moves
// with it tangentially, keeping the offset t(p₀ᵐ − p₁) that static friction has not yet undone.
// Within a substep the friction point of a ball rolling without slip moves by r (θ − sin θ)
// ≈ r θ³/6 along the motion (θ = |ω| h_s): what static friction sees, instead of v h_s.
#pragma once

#include "pbd/collision/collision_detection.h"
#include "pbd/contacts/contact_materials.h"
#include "pbd/model/body_states.h"
#include "pbd/model/scene.h"

namespace pbd {

struct XpbdContact {
  int point = -1;  ///< body 0: rigid body index, or global particle index
  bool pointIsParticle = false;
  int body = -1;                           ///< body 1 (the SDF side), rigid body index
  Vector3 pointLocal = Vector3::Zero();    ///< r₀ in body 0's principal frame (particle: unused)
  Vector3 surfaceLocal = Vector3::Zero();  ///< the anchor r₁ in body 1's principal frame
  Vector3 normalLocal = Vector3::UnitY();  ///< n in body 1's principal frame
  /// Closed-form sphere contacts (ContactPointGeometry::vertexRadius, sdfRadius): body 0 is a
  /// sphere of radius pointRadius > 0 centred at pointCenterLocal (its principal frame); body 1
  /// too when bodyRadius > 0. See "Spheres" above.
  Real pointRadius = 0, bodyRadius = 0;
  Vector3 pointCenterLocal = Vector3::Zero(), bodyCenterLocal = Vector3::Zero();
  Real friction = 0, restitution = 0;
  Real normalMultiplier = 0;   ///< λ_n of the current substep
  Real tangentMultiplier = 0;  ///< |λ_t| of the static friction, current substep
  Real approachVelocity = 0;   ///< ṽ_n of the current substep

  /// Sets the contact up from its geometry at the current poses.
  void init(const ContactPointGeometry& geometry, bool particle, const BodyStates& bodies,
            const ContactMaterial& material, Real contactTolerance);
  /// Sphere contacts: makes the current support point the friction point and moves the anchor
  /// with it, keeping the slip not yet undone (call before the prediction). Others: nothing.
  void followSupportPoint(const BodyStates& bodies);
  /// Resets λ and, when the contact has restitution, records ṽ_n (call after the prediction,
  /// `rotations` the bodies' rotation matrices at the predicted poses, when any contact has
  /// restitution: XpbdContactSet::formRotations).
  void beginSubstep(const BodyStates& bodies, const std::vector<Matrix3>& rotations);
  /// Normal projection and static friction (moves the anchor when the point slides).
  void solvePosition(BodyStates& bodies, Real substepSize, Real compliance);
  /// Restitution and dynamic friction; `rotations` the bodies' rotation matrices at the current
  /// poses (XpbdContactSet::formRotations after the position pass: the velocity pass does not
  /// move the bodies).
  void solveVelocity(BodyStates& bodies, const std::vector<Matrix3>& rotations, Real substepSize,
                     Real restitutionThreshold) const;
};

/// The XPBD contacts of one step, in detection order (rigid points, then particles). Sized
/// once at world build; a step allocates nothing.
struct XpbdContactSet {
  std::vector<XpbdContact> contacts;
  /// R_k of every rigid body, formed once for a pass that does not move the bodies (the
  /// approach velocities, the velocity pass): a matrix rotates a vector in 15 operations, a
  /// quaternion in 30, and each contact row rotates several.
  std::vector<Matrix3> rotations;

  void reserve(const ContactGeometryBuffer& geometry, std::size_t rigidBodies);
  void formRotations(const RigidBodyStates& bodies);
  bool anyRestitution() const;  ///< of the step's contacts
  bool anyActive() const;       ///< λ_n > 0 in the current substep
  void initialise(const ContactGeometryBuffer& geometry, const BodyStates& bodies,
                  const ContactMaterials& materials, Real contactTolerance);
};

}  // namespace pbd
