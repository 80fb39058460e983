// The joint-holding bound shared by the seed's step (test_joint_motion.cpp) and XPBD
// (test_xpbd_joints.cpp). Per substep, the prediction moves a joint off its constraint by at most
//   δ = h_s² (|a| + (|ω|² + |α|) ℓ) + (the change of a motor's set point between projections)·ℓ,
// where a, ω, α are body 1's linear acceleration, angular velocity and angular acceleration
// (measured from its motion, step to step — not from the joint) and ℓ ≥ 0.1 m is the distance
// of the joint point from its centre of mass. A projection with the exact Jacobian is a Newton
// step and leaves O(δ²/ℓ); a Jacobian wrong to first order would leave O(δ). We assert max
// error ≤ max δ/100 over 3 s, and the same for the angular error with δ/ℓ.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "pbd/model/world.h"

namespace pbd::test {

/// Runs `scene` (one joint between a static body 0 and body 1) for 3 s with `substeps` per
/// step and checks the bound above. `motorChangePerProjection`: the fraction of a step's
/// set-point change a motor makes between two projections (1 when the set point moves once
/// per step, 1/substeps when it moves every substep).
inline void expectJointHoldsBelowSubstepBound(const Scene& scene, JointType type, int substeps,
                                              Real motorChangePerProjection) {
  World world = buildWorld(scene);
  const Real h = scene.simulation.timeStepSize;
  const Real hs = h / static_cast<Real>(substeps);
  const Vector3 start = scene.rigidBodies[1].initialCenterOfMass();
  const Real lever = std::max(Real(0.1), (scene.joints[0].position - start).norm());
  const bool positionMotor =
      type == JointType::TargetAngleMotorHinge || type == JointType::TargetPositionMotorSlider;
  const auto& b = world.bodies.rigid;
  JointError worst;
  Real maxDelta = 0, maxTravel = 0;
  for (int n = 0; n < 600; ++n) {  // 3 s
    const Vector3 v = b.velocity[1], omega = b.angularVelocity[1];
    const Real targetBefore = scene.joints[0].target.valueAt(world.time);
    world.step();
    const Real accel = (b.velocity[1] - v).norm() / h;
    const Real angularAccel = (b.angularVelocity[1] - omega).norm() / h;
    const Real motorJump =
        positionMotor ? std::abs(scene.joints[0].target.valueAt(world.time) - targetBefore) *
                            motorChangePerProjection
                      : 0;
    maxDelta = std::max(maxDelta, hs * hs * (accel + (omega.squaredNorm() + angularAccel) * lever) +
                                      motorJump * lever);
    const JointError e = jointError(world.joints[0], world.bodies);
    worst.linear = std::max(worst.linear, e.linear);
    worst.angular = std::max(worst.angular, e.angular);
    maxTravel = std::max(maxTravel, (b.position[1] - start).norm());
  }
  ASSERT_TRUE(b.position[1].allFinite());
  // Plus a round-off floor: positions of a few metres carry ~100 ε·|x| after a step's updates.
  const Real roundOff = 100 * kEpsilon * std::max(Real(1), maxTravel + start.norm());
  EXPECT_LE(worst.linear, maxDelta / 100 + roundOff) << jointTypeName(type);
  EXPECT_LE(worst.angular, maxDelta / lever / 100 + roundOff) << jointTypeName(type);
  // The body did move (the bound is not met trivially by a body at rest).
  EXPECT_GT(maxTravel, 0.005) << jointTypeName(type);
  std::printf("  %-30s max linear %.3e m, max angular %.3e rad (bound %.1e m)\n",
              jointTypeName(type), double(worst.linear), double(worst.angular),
              double(maxDelta / 100));
}

}  // namespace pbd::test
