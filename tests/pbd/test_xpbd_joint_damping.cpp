// Joint damping of pbd.xpbd (joints/xpbd_joint_damping.h, Müller et al. 2020 §3.6) against its
// closed form: for two equal spheres (isotropic inertia) the relative angular velocity, and the
// relative velocity of a slider's bodies along its axis, fall by exactly the factor 1 − μ h_s
// per substep, so after N substeps they are (1 − μ h_s)^N of their start. Zero damping leaves a
// run bit for bit as it was.
#include <gtest/gtest.h>

#include <cmath>

#include "common/scene_fixtures.h"
#include "common/tolerances.h"
#include "pbd/model/world.h"

namespace pbd {
namespace {

/// Two equal spheres 2 m apart on the x axis, no gravity, no collision, joined by `type` with
/// its point (ball) or axis (slider) on the x axis.
Scene twoSpheres(JointType type, Real linearDamping, Real angularDamping) {
  Scene s;
  s.simulation.timeStepSize = Real(0.01);
  s.simulation.gravitation = Vector3::Zero();
  s.simulation.stepMethod = StepMethod::Xpbd;
  s.simulation.xpbd.substeps = 10;
  s.simulation.xpbd.jointLinearDamping = linearDamping;
  s.simulation.xpbd.jointAngularDamping = angularDamping;
  s.rigidBodies.push_back(test::sphereBody(0, Real(0.3), Vector3(-1, 0, 0), 1000));
  s.rigidBodies.push_back(test::sphereBody(1, Real(0.3), Vector3(1, 0, 0), 1000));
  for (RigidBodyDesc& b : s.rigidBodies)
    b.collision.type = CollisionObjectType::None;
  JointDesc j = test::makeJointDesc(type, 0, 1);
  j.position = Vector3::Zero();
  j.axis = Vector3::UnitX();
  s.joints.push_back(j);
  return s;
}

// Opposite spins about the line through both centres and the joint point: the ball joint holds
// without correcting anything (the anchors lie on the spin axis), so only the damping acts on
// the relative angular velocity, -2w, which must decay as (1 − μ h_s)^N. The spin is slow
// (θ = w h_s = 1e-5 rad per substep) because the step's own quaternion update and read-back,
// ω = 2 vec(q q_old⁻¹)/h_s, change ω by O(θ²/24) per substep: 4e-12 here, 4e-10 over 100
// substeps; with the read-back's round-off (ε over θ/2 per substep, ~2e-11, 2e-10 over 100
// random) the tolerance is 2e-9 relative.
TEST(XpbdJointDamping, RelativeSpinDecaysGeometricallyPerSubstep) {
  // Double-only: the spin is made slow to keep the O(θ²) term small, which makes the
  // read-back's round-off ε/(θ/2) per substep; with float's ε that is 1.2e-7/5e-6 = 2.4 % per
  // substep (~24 % over 100), so the 2e-9 bound has no float counterpart.
  if (sizeof(Real) < 8)
    GTEST_SKIP() << "needs double precision: the angular-velocity read-back rounds by "
                    "eps/(theta/2) = 1.2e-7/5e-6 = 2.4 % per substep in float";
  const Real mu = 4, w = Real(0.01), hs = Real(0.001);
  Scene s = twoSpheres(JointType::Ball, 0, mu);
  s.rigidBodies[0].angularVelocity = Vector3(w, 0, 0);
  s.rigidBodies[1].angularVelocity = Vector3(-w, 0, 0);
  World world = buildWorld(s);
  for (int n = 0; n < 10; ++n)
    world.step();  // 100 substeps
  const Real expected = -2 * w * std::pow(1 - mu * hs, 100);
  const Vector3 relative =
      world.bodies.rigid.angularVelocity[1] - world.bodies.rigid.angularVelocity[0];
  EXPECT_NEAR(double(relative.x()), double(expected), 2e-9 * std::abs(double(expected)));
  EXPECT_NEAR(double(relative.tail<2>().norm()), 0, 1e-15);
  // The impulses are internal: the total angular momentum (equal inertias: the sum of the
  // angular velocities) stays 0 to the same round-off.
  const Vector3 total =
      world.bodies.rigid.angularVelocity[0] + world.bodies.rigid.angularVelocity[1];
  EXPECT_NEAR(double(total.norm()), 0, 2e-9 * w);
}

// Two spheres separating along a slider's axis at relative speed u: the linear damping removes
// (1 − μ h_s) of it per substep, and the centre of mass keeps its velocity (internal impulses).
// Tolerance 5e-11 m/s: velocities are read back from positions, v = (x − x_old)/h_s, whose
// round-off is ε |x| / h_s ≈ 2.2e-13 m/s per substep (|x| ≈ 1 m), at most 2.2e-11 over 100.
// Precision-aware: the same 225 ε |x| / h_s (test::roundOffBound), 2.7e-2 m/s in float, where
// one substep's read-back rounds by 1.2e-4 m/s; the damping's effect (0.09 m/s) stays above it.
TEST(XpbdJointDamping, SlidingDecaysGeometricallyPerSubstep) {
  const Real mu = 2, u = Real(0.5), hs = Real(0.001);
  Scene s = twoSpheres(JointType::Slider, mu, 0);
  s.rigidBodies[0].velocity = Vector3(-u / 2 + Real(0.1), 0, 0);
  s.rigidBodies[1].velocity = Vector3(u / 2 + Real(0.1), 0, 0);
  World world = buildWorld(s);
  for (int n = 0; n < 10; ++n)
    world.step();
  const RigidBodyStates& b = world.bodies.rigid;
  const double readBack = double(test::roundOffBound(5e-11));
  EXPECT_NEAR(double((b.velocity[1] - b.velocity[0]).x()), double(u * std::pow(1 - mu * hs, 100)),
              readBack);
  EXPECT_NEAR(double(Real(0.5) * (b.velocity[0] + b.velocity[1]).x()), 0.1, readBack);
}

// Damping acts only when given: the same hinge scene with and without angular damping parts.
// (That zero damping leaves every pbd.xpbd result bit for bit as before is checked on the case
// library's state hashes: docs/methods.md.)
TEST(XpbdJointDamping, ActsOnlyWhenGiven) {
  Scene a = twoSpheres(JointType::Hinge, 0, 0);
  a.rigidBodies[1].angularVelocity = Vector3(1, 2, 3);
  a.rigidBodies[1].velocity = Vector3(0, 1, 0);
  Scene c = a;
  c.simulation.xpbd.jointAngularDamping = 1;
  World wa = buildWorld(a), wc = buildWorld(c);
  for (int n = 0; n < 50; ++n) {
    wa.step();
    wc.step();
  }
  EXPECT_NE(wa.stateHash(), wc.stateHash());
}

}  // namespace
}  // namespace pbd
