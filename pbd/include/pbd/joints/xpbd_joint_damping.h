// Joint damping of the XPBD method (Müller, Macklin, Chentanez, Jeschke, Kim 2020, "Detailed
// rigid body simulation with extended position based dynamics", §3.6, "joint damping"): in the
// velocity pass of every substep (h the substep size), for a joint between bodies 0 and 1,
//   Δv = (v₁(a₁) − v₀(a₀)) · min(μ_lin h, 1)     (the relative velocity of its anchor points)
//   Δω = (ω₁ − ω₀) · min(μ_ang h, 1)
// each removed by an impulse p along its direction n = Δ/|Δ| through the generalized inverse
// masses, p = |Δ| / (w₀ + w₁) with
//   linear:  w_k = 1/m_k + (r_k × n)ᵀ I_k⁻¹ (r_k × n)   (r_k from body k's centre to its anchor)
//   angular: w_k = nᵀ I_k⁻¹ n,
// applied +p n to body 0 and −p n to body 1 (velocities through 1/m_k and I_k⁻¹ (r_k × n), or
// angular velocities through I_k⁻¹ n). For two equal bodies with isotropic inertia the relative
// velocity along n falls by exactly the factor 1 − μ h per substep. μ_lin, μ_ang in 1/s:
// `jointLinearDamping`, `jointAngularDamping` of `pbd.xpbd` (default 0: nothing is done).
// Joints to a particle are not damped. Nothing here allocates.
#pragma once

#include "pbd/model/body_states.h"

namespace pbd {

/// A joint's damping anchor in each body's principal frame: the joint's point (its `position`,
/// the middle of `position1`/`position2`, else the middle of the bodies' centres of mass), fixed
/// at the start.
struct JointDampingAnchor {
  int body0 = -1, body1 = -1;  ///< body1 −1: a particle joint, not damped
  Vector3 local0 = Vector3::Zero(), local1 = Vector3::Zero();
};

/// Damps one joint's relative motion (see above) over a substep of size `h`.
void dampJoint(RigidBodyStates& bodies, const JointDampingAnchor& anchor, Real linearDamping,
               Real angularDamping, Real h);

}  // namespace pbd
