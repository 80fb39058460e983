// The XPBD step (the `pbd.xpbd` method): Müller, Macklin, Chentanez, Jeschke, Kim 2020,
// "Detailed Rigid Body Simulation with Extended Position Based Dynamics", Algorithm 2.
//
// One step of size h with n = XpbdSettings::substeps substeps of h_s = h/n:
//   1. accelerations of dynamic bodies and particles := gravitation (torques are kept);
//   2. collision detection once, at the step's start poses (closed-form contacts for the
//      primitive pairs that have one with Simulation.contactGeometry "primitives", this
//      method's default: collision/primitive_contacts.h; samples against SDFs otherwise), for
//      points within
//      contactTolerance + speculativeMargin · h · max_i(|v_i| + |ω_i| ρ_i + h |a_i|) (ρ_i the
//      largest distance of body i's surface samples from its centre of mass, a_i its
//      acceleration; particles: |v| + h |a|) — the distance any point can travel in the step,
//      gravity's ½ (1 + 1/n) h² |a| included, so that no contact is missed (issue 24: without
//      the h |a| term a box resting with contactTolerance 0 fell through one step in five);
//   3. n times:
//      - motors take their set point for the end of the substep;
//      - predict: v ← v + h_s a, x ← x + h_s v; ω ← ω + h_s I_w⁻¹(τ − ω × I_w ω),
//        q ← normalize(q + ½ h_s [0, ω] ⊗ q); contacts with restitution record their approach
//        velocity ṽ_n;
//      - one position iteration: every joint (colouring order, joints/xpbd_joint.h) with
//        λ reset (swept XpbdSettings::jointIterations times, λ continued after the first
//        sweep), the particle distance and tet volume constraints (cloth and solid
//        edges, tets: constraints/), then every contact (detection order,
//        contacts/xpbd_contact.h): the normal
//        projection and static friction, contacts re-evaluated at the current poses;
//      - velocities from positions: v = (x − x_old)/h_s, ω = 2 vec(q ⊗ q_old⁻¹)/h_s (w ≥ 0);
//      - velocity pass: velocity motors, joint damping (when jointLinearDamping or
//        jointAngularDamping > 0: joints/xpbd_joint_damping.h), then every contact active in
//        the substep (restitution, dynamic friction);
//   4. t ← t + h.
// Nothing here allocates; the order of every loop is fixed (bitwise deterministic).
#pragma once

#include <vector>

#include "pbd/contacts/xpbd_contact.h"
#include "pbd/joints/xpbd_joint.h"
#include "pbd/joints/xpbd_joint_damping.h"

namespace pbd {

struct World;

/// What the XPBD step keeps between steps, sized when the world is built.
struct XpbdState {
  XpbdContactSet contacts;
  std::vector<XpbdJointMultipliers> jointMultipliers;  ///< λ of the last substep, per joint
  std::vector<Real> sampleRadius;                      ///< ρ_i per rigid body (m)
  std::vector<JointDampingAnchor> jointAnchors;        ///< per joint, in World::joints order
  XpbdJointSchedule jointSchedule;                     ///< World::joints by type, for the loops
};

/// Sizes `state` for `world` (joints, contact capacity, sample radii) and fixes the joints'
/// damping anchors from their descriptions (`scene`, in World::jointSceneIndex order).
void prepareXpbd(World& world, const Scene& scene);

void stepWorldXpbd(World& world);

}  // namespace pbd
