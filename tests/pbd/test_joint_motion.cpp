// Joints in motion: each joint type holds its constraint over seconds of motion within a bound
// derived from the step size; compliant joints follow the closed form of their discrete scheme;
// motors track their targets.
#include <gtest/gtest.h>

#include <cmath>

#include "common/joint_hold.h"
#include "common/scene_fixtures.h"
#include "pbd/model/world.h"

namespace pbd {
namespace {

constexpr Real kGravity = Real(9.81);

using test::sequence;
using test::singleJointScene;

class JointMotion : public ::testing::TestWithParam<int> {};

// The seed's step: the motor's set point moves once per step (common/joint_hold.h).
TEST_P(JointMotion, ConstraintErrorStaysBelowStepBound) {
  const auto type = static_cast<JointType>(GetParam());
  if (type == JointType::RigidBodySpring) GTEST_SKIP() << "compliant: see SpringRecurrence";
  const Scene scene = singleJointScene(type);
  test::expectJointHoldsBelowSubstepBound(scene, type, scene.simulation.subSteps, 1);
}

INSTANTIATE_TEST_SUITE_P(AllJointTypes, JointMotion, ::testing::Range(0, kJointTypeCount),
                         [](const ::testing::TestParamInfo<int>& param) {
                           return std::string(jointTypeName(static_cast<JointType>(param.param)));
                         });

// An XPBD spring (or the damper joint's axial row) with one iteration per substep and λ reset
// every substep is implicit Euler on x'' = −ω² x, ω² = k/m, for a body moving along the spring:
//   (1 + h_s² ω²) x_{n+1} = x_n + h_s v_n,   v_{n+1} = (x_{n+1} − x_n)/h_s.
// The test iterates this scalar recurrence independently and compares the trajectories.
void expectImplicitEulerOscillation(JointType type) {
  Scene s;
  s.simulation.timeStepSize = Real(0.01);
  s.simulation.subSteps = 4;
  s.simulation.gravitation.setZero();
  s.rigidBodies.push_back(test::boxBody(0, Vector3(0.2, 0.2, 0.2), Vector3::Zero(), 1, false));
  const Real length = 1;
  RigidBodyDesc body = test::boxBody(1, Vector3(0.1, 0.1, 0.1), Vector3(length, 0, 0), 500);
  s.rigidBodies.push_back(body);
  JointDesc j = test::makeJointDesc(type, 0, 1);
  j.stiffness = 200;
  j.axis = Vector3::UnitX();
  j.position1 = Vector3::Zero();
  j.position2 = Vector3(length, 0, 0);
  s.joints.push_back(j);
  // Start displaced by 0.1 m along the axis, at rest (the rest length is the initial one, so
  // displace after building).
  World world = buildWorld(s);
  world.bodies.rigid.position[1].x() += Real(0.1);

  const Real mass = body.massProperties.mass;
  const Real omega2 = j.stiffness / mass;
  const Real hs = s.simulation.timeStepSize / s.simulation.subSteps;
  Real x = Real(0.1), v = 0;
  Real maxDeviation = 0;
  for (int n = 0; n < 300; ++n) {
    world.step();
    for (int k = 0; k < s.simulation.subSteps; ++k) {
      const Real next = (x + hs * v) / (1 + hs * hs * omega2);
      v = (next - x) / hs;
      x = next;
    }
    maxDeviation =
        std::max(maxDeviation, std::abs(world.bodies.rigid.position[1].x() - length - x));
  }
  // Round-off only: ~1200 substeps, each with a 1×1 (spring) or 6×6 (damper) solve on O(1)
  // numbers: 10 ε per substep.
  EXPECT_LE(maxDeviation, 1200 * 10 * kEpsilon) << jointTypeName(type);
  // And the oscillation is not trivially zero: implicit Euler damps by 1/√(1 + h_s²ω²) per
  // substep, so after 3 s the amplitude is 0.1 (1 + h_s²ω²)^(−600) ≈ 0.1·e^(−600 h_s² ω²).
  EXPECT_GT(std::abs(x), 1e-3);
  EXPECT_LE(world.bodies.rigid.position[1].tail<2>().norm(), 1200 * 10 * kEpsilon);
}

TEST(SpringRecurrence, RigidBodySpringIsImplicitEuler) {
  expectImplicitEulerOscillation(JointType::RigidBodySpring);
}
TEST(SpringRecurrence, DamperAxialRowIsImplicitEuler) {
  expectImplicitEulerOscillation(JointType::Damper);
}

// The angle motor holds a hard constraint on the relative rotation: the hinge angle equals the
// interpolated target at the end of every step (to the constraint bound above).
TEST(Motors, TargetAngleTracksItsSequence) {
  // The corrected schedule: the set point of the step's end (the seed's, two steps late, is
  // checked against the original's recording in test_seed_reference.cpp).
  Scene scene = singleJointScene(JointType::TargetAngleMotorHinge);
  scene.simulation.jointModel = JointModel::Corrected;
  World world = buildWorld(scene);
  const Quaternion q0 = scene.rigidBodies[1].initialPrincipalRotation();
  Real worst = 0;
  for (int n = 0; n < 600; ++n) {
    world.step();
    const Quaternion relative = world.bodies.rigid.rotation[1] * q0.conjugate();
    const Real angle = 2 * std::atan2(relative.vec().dot(Vector3::UnitZ()), relative.w());
    worst = std::max(worst, std::abs(angle - scene.joints[0].target.valueAt(world.time)));
  }
  // δ/100 of the test above (5e-3·3/100 + 5e-7), plus the round-off of angles: 100 ε.
  EXPECT_LE(worst, 1e-6 + 100 * kEpsilon);
}

// The velocity motor drives ω about the axis to the set point at the end of every step; the
// pendulum's weight acts against it, but the velocity pass sets it exactly (hard rows).
TEST(Motors, TargetVelocityHingeHoldsItsRate) {
  // The corrected schedule, as above.
  Scene scene = singleJointScene(JointType::TargetVelocityMotorHinge);
  scene.simulation.jointModel = JointModel::Corrected;
  World world = buildWorld(scene);
  for (int n = 0; n < 600; ++n) {
    world.step();
    const Real rate = world.bodies.rigid.angularVelocity[1].z();
    // Round-off of a 6×6 solve on O(1) values.
    ASSERT_NEAR(rate, scene.joints[0].target.valueAt(world.time), 1e4 * kEpsilon)
        << "t=" << world.time;
  }
}

TEST(Motors, SequenceInterpolationHoldsAndRepeats) {
  MotorTarget t = sequence({1, 0, 2, 1, 4, -1});
  EXPECT_EQ(t.valueAt(0), 0);      // before the first sample: hold the first value
  EXPECT_EQ(t.valueAt(1.5), 0.5);  // linear interpolation
  EXPECT_EQ(t.valueAt(3), 0);
  EXPECT_EQ(t.valueAt(9), -1);  // after the last: hold the last value
  t.repeat = true;              // period 3 from t = 1
  EXPECT_DOUBLE_EQ(t.valueAt(5.5), 0.5);
  EXPECT_DOUBLE_EQ(t.valueAt(7), 0);
  EXPECT_EQ(t.valueAt(0.5), 0);
}

}  // namespace
}  // namespace pbd
