// The XPBD step (pbd.xpbd) with joints: every joint type holds its constraint; a hinge
// physical pendulum keeps the elliptic-integral period and its energy; a compliant distance
// joint is a spring of stiffness 1/α (period, the implicit-Euler amplitude decay, and the
// multiplier as the spring force); a chain with a 1:100 load holds its joints. Numbers are
// printed for docs/methods.md.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <variant>
#include <vector>

#include "common/joint_hold.h"
#include "common/scene_fixtures.h"
#include "common/tolerances.h"
#include "pbd/model/world.h"

namespace pbd {
namespace {

constexpr Real kGravity = Real(9.81);
constexpr Real kPi = Real(3.14159265358979323846);

void useXpbd(Scene& s, int substeps) {
  s.simulation.stepMethod = StepMethod::Xpbd;
  s.simulation.xpbd.substeps = substeps;
}

class XpbdJointHolds : public ::testing::TestWithParam<int> {};

// As the seed's step (common/joint_hold.h), with XPBD's compliance 0: one projection per
// substep is a Newton step; the motor's set point moves every substep.
TEST_P(XpbdJointHolds, ConstraintErrorStaysBelowSubstepBound) {
  const auto type = static_cast<JointType>(GetParam());
  if (type == JointType::RigidBodySpring) GTEST_SKIP() << "compliant: see CompliantDistance";
  Scene scene = test::singleJointScene(type);
  useXpbd(scene, 20);
  test::expectJointHoldsBelowSubstepBound(scene, type, 20, Real(1) / 20);
}

INSTANTIATE_TEST_SUITE_P(AllJointTypes, XpbdJointHolds, ::testing::Range(0, kJointTypeCount),
                         [](const ::testing::TestParamInfo<int>& param) {
                           return std::string(jointTypeName(static_cast<JointType>(param.param)));
                         });

/// K(k) = π / (2 AGM(1, √(1 − k²))), the complete elliptic integral of the first kind.
Real ellipticK(Real k) {
  Real a = 1, b = std::sqrt(1 - k * k);
  for (int i = 0; i < 30; ++i) {
    const Real mean = (a + b) / 2;
    b = std::sqrt(a * b);
    a = mean;
  }
  return kPi / (2 * a);
}

/// Kinetic plus potential energy of body `i` (y up, gravity −g y).
Real energy(const World& world, std::size_t i) {
  const auto& b = world.bodies.rigid;
  return Real(0.5) * b.mass[i] * b.velocity[i].squaredNorm() +
         Real(0.5) * b.angularVelocity[i].dot(b.inertiaWorld(i) * b.angularVelocity[i]) +
         b.mass[i] * kGravity * b.position[i].y();
}

struct PendulumRun {
  Real period = 0, expectedPeriod = 0;
  Real worstDrift = 0;  ///< max |E − E₀| / (m g d (1 − cos θ₀))
};

/// The hinge physical pendulum of test::pendulumScene at h = 5 ms for 10 s under pbd.xpbd.
PendulumRun runPendulum(int substeps) {
  Scene scene = test::pendulumScene(JointType::Hinge, Real(1e-3));
  useXpbd(scene, substeps);
  World world = buildWorld(scene);
  const auto& b = world.bodies.rigid;
  const Vector3 pivot = scene.joints[0].position;
  const Vector3 arm0 = b.position[1] - pivot;
  const Real d = arm0.norm();
  const Real theta0 = std::atan2(arm0.x(), -arm0.y());
  const Real m = b.mass[1];
  const Real inertiaPivot = b.inertiaWorld(1)(2, 2) + m * d * d;
  PendulumRun run;
  run.expectedPeriod =
      4 * std::sqrt(inertiaPivot / (m * kGravity * d)) * ellipticK(std::sin(theta0 / 2));
  const Real swingEnergy = m * kGravity * d * (1 - std::cos(theta0));
  const Real e0 = energy(world, 1);
  std::vector<Real> crossings;
  Real previousAngle = theta0;
  for (int n = 0; n < 2000; ++n) {  // 10 s
    const Real t0 = world.time;
    world.step();
    const Vector3 arm = b.position[1] - pivot;
    const Real angle = std::atan2(arm.x(), -arm.y());
    if ((previousAngle > 0) != (angle > 0))
      crossings.push_back(t0 + (world.time - t0) * previousAngle / (previousAngle - angle));
    previousAngle = angle;
    run.worstDrift = std::max(run.worstDrift, std::abs(energy(world, 1) - e0) / swingEnergy);
  }
  if (crossings.size() >= 2)
    run.period =
        2 * (crossings.back() - crossings.front()) / static_cast<Real>(crossings.size() - 1);
  return run;
}

// The hinge physical pendulum of test::pendulumScene at h = 5 ms (a 0.1 × 0.4 × 0.1 box whose
// centre of mass is d = 1 m from the pivot, released θ₀ = atan(0.6/0.8) off vertical):
//   T = 4 √(I_p / (m g d)) K(sin(θ₀/2)),  I_p = I_zz + m d².
// The targets: period within 0.1 %, energy drift ≤ 1 % over 10 s (relative to the
// swing energy m g d (1 − cos θ₀)), at a substep count we state: 80 (h_s = 62.5 µs). Period:
// from the first to the last zero crossing of the angle, each interpolated linearly between
// steps (the angle is nearly linear at θ = 0: the interpolation error is third order in h).
// XPBD's energy loss is first order in h_s (a projection after an explicit prediction): the
// drift at 40 substeps must be twice that at 80, within 10 %.
TEST(XpbdPendulum, HingePeriodAndEnergyOverTenSeconds) {
  // Double-only: at 80 substeps gravity moves the bob by g h_s² = 9.81 × (62.5 µs)² = 3.8e-8 m
  // per substep at the bob's height y = 1.2 m, below float's half-ulp there (1.2e-7 m): in
  // float the pendulum does not leave its start (no zero crossing), and at 40 substeps
  // (1.5e-7 m per substep, just above it) its energy drifts by 26 %.
  if (sizeof(Real) < 8)
    GTEST_SKIP() << "needs double precision: g h_s^2 = 3.8e-8 m per substep at y = 1.2 m is "
                    "below float's half-ulp 1.2e-7 m there, so the pendulum does not move";
  const PendulumRun fine = runPendulum(80);
  const PendulumRun coarse = runPendulum(40);
  std::printf(
      "  hinge pendulum, 80 substeps: T = %.6f s, elliptic %.6f s (%.4f %%), "
      "max energy drift %.4f %% of the swing energy (40 substeps: %.4f %%)\n",
      double(fine.period), double(fine.expectedPeriod),
      double(100 * (fine.period / fine.expectedPeriod - 1)), double(100 * fine.worstDrift),
      double(100 * coarse.worstDrift));
  EXPECT_NEAR(fine.period, fine.expectedPeriod, Real(1e-3) * fine.expectedPeriod);
  EXPECT_LE(fine.worstDrift, 0.01);
  EXPECT_NEAR(coarse.worstDrift / fine.worstDrift, 2, 0.2);
}

// A distance joint with compliance α between a static anchor and a 1 kg cube whose connector is
// its centre of mass, no gravity, the cube given a speed v₀ along the joint: a spring of
// stiffness k = 1/α, ω² = k/m (T = 1 s here). One XPBD iteration per substep on a linear
// constraint is implicit Euler: (1 + ω²h²) x' = x + h v, so
//   the period is 2π h / atan(ω h) = T (1 + (ω h)²/3 + …): 1e-6 relative at h = 0.25 ms;
//   the energy decays by (1 + ω²h²)⁻¹ per substep (E_N = E₀ (1 + ω²h²)^−N);
//   after every substep C + α̃ λ = 0 exactly (linear constraint): the force λ/h² is −C/α.
TEST(XpbdCompliance, CompliantDistanceJointIsASpringOfStiffnessOneOverAlpha) {
  if (sizeof(Real) < 8)
    GTEST_SKIP() << "a substep moves the cube by 25 um at x = 1 m: a few hundred float ulps";
  constexpr int kSubsteps = 20;
  Scene s;
  s.simulation.timeStepSize = Real(0.005);
  s.simulation.gravitation = Vector3::Zero();
  s.rigidBodies.push_back(
      test::boxBody(0, Vector3::Constant(Real(0.1)), Vector3::Zero(), 1, false));
  RigidBodyDesc cube = test::boxBody(1, Vector3::Constant(Real(0.1)), Vector3(1, 0, 0), 1000);
  const Real speed = Real(0.1);
  cube.velocity = Vector3(speed, 0, 0);
  s.rigidBodies.push_back(cube);
  JointDesc j = test::makeJointDesc(JointType::Distance, 0, 1);
  j.position1 = Vector3::Zero();
  j.position2 = Vector3(1, 0, 0);
  s.joints.push_back(j);
  useXpbd(s, kSubsteps);
  const Real m = 1, omega = 2 * kPi;  // T = 1 s
  const Real k = m * omega * omega;
  s.simulation.xpbd.jointLinearCompliance = 1 / k;
  World world = buildWorld(s);
  ASSERT_NEAR(double(world.bodies.rigid.mass[1]), 1.0, 1e-12);
  const Real hs = s.simulation.timeStepSize / kSubsteps;
  const auto& b = world.bodies.rigid;

  std::vector<Real> crossings;
  Real previous = 0, worstForceError = 0;
  const int steps = 400;  // 2 s
  for (int n = 0; n < steps; ++n) {
    const Real t0 = world.time;
    world.step();
    const Real extension = b.position[1].x() - 1;
    if (n > 0 && (previous > 0) != (extension > 0))
      crossings.push_back(t0 + (world.time - t0) * previous / (previous - extension));
    previous = extension;
    const Real force = world.xpbd.jointMultipliers[0](0) / (hs * hs);
    const Real c = jointError(world.joints[0], world.bodies).linear;  // |C|
    worstForceError =
        std::max(worstForceError, std::abs(std::abs(force) - k * c) / (k * speed / omega));
  }
  ASSERT_GE(crossings.size(), 3u);
  const Real period =
      2 * (crossings.back() - crossings.front()) / static_cast<Real>(crossings.size() - 1);
  const Real expectedPeriod = 2 * kPi / omega;
  const Real energyNow = Real(0.5) * m * b.velocity[1].squaredNorm() +
                         Real(0.5) * k * (b.position[1].x() - 1) * (b.position[1].x() - 1);
  const Real energy0 = Real(0.5) * m * speed * speed;
  const Real expectedRatio = std::pow(1 + omega * omega * hs * hs, -Real(steps * kSubsteps));
  std::printf(
      "  compliant distance: T = %.7f s (2 pi sqrt(m/k) = %.7f), E/E0 = %.6f "
      "(implicit Euler %.6f), force error %.2e of k A\n",
      double(period), double(expectedPeriod), double(energyNow / energy0), double(expectedRatio),
      double(worstForceError));
  // Period: the discrete period is 1e-6 relative off; the crossing interpolation O((ω h)²).
  EXPECT_NEAR(period, expectedPeriod, Real(1e-4) * expectedPeriod);
  // Energy: the discrete energy oscillates within a period by O(ω h) = 0.03 % around the decay.
  EXPECT_NEAR(energyNow / energy0, expectedRatio, Real(1e-3));
  // The decay itself is visible (1 − ratio = 2 %): the test can tell implicit Euler from
  // an energy-conserving scheme.
  EXPECT_LT(expectedRatio, 0.99);
  // λ/h² = −C/α to round-off (relative to the force at the amplitude, k A, A = v₀/ω): a
  // few operations on C ~ A, whose absolute round-off ε |x| is 60 ε of A (x = 1 m).
  EXPECT_LE(worstForceError, 1000 * kEpsilon);
}

// The substep's joint schedule (XpbdJointSchedule): ball joints in a typed array, the others
// through the variant, in runs that together are World::joints in its order; the motor targets
// and the velocity pass only for the joint types that declare them (the target motors, and the
// velocity motors: joints/xpbd_joint.h). Checked against the joints themselves, on a chain
// whose joint types alternate.
TEST(XpbdJointSchedule, KeepsTheJointOrderAndVisitsOnlyTheJointsThatNeedAPass) {
  Scene s;
  s.simulation.timeStepSize = Real(0.005);
  s.rigidBodies.push_back(
      test::boxBody(0, Vector3(0.2, 0.2, 0.2), Vector3(0, 2, 0), 1, /*dynamic=*/false));
  test::appendChain(s, 7, JointType::Ball);
  s.joints[2].type = JointType::Hinge;
  s.joints[4].type = JointType::TargetVelocityMotorHinge;
  s.joints[4].target = test::sequence({0, 0, 1, 3});
  s.joints[5].type = JointType::TargetAngleMotorHinge;
  s.joints[5].target = test::sequence({0, 0, 1, 1});
  useXpbd(s, 4);
  const World world = buildWorld(s);
  const XpbdJointSchedule& schedule = world.xpbd.jointSchedule;

  std::size_t next = 0, balls = 0;
  std::vector<std::size_t> targets, velocityPasses;
  for (std::size_t r = 0; r < schedule.runs.size(); ++r) {
    const XpbdJointSchedule::Run& run = schedule.runs[r];
    EXPECT_EQ(run.begin, next);  // contiguous, in World::joints order
    EXPECT_LT(run.begin, run.end);
    if (r > 0) {
      EXPECT_NE(run.ball, schedule.runs[r - 1].ball);  // maximal runs
    }
    for (std::size_t j = run.begin; j < run.end; ++j) {
      const bool ball = std::holds_alternative<BallJoint>(world.joints[j]);
      EXPECT_EQ(run.ball, ball) << "joint " << j;
      if (ball) {
        ASSERT_EQ(run.firstBall + (j - run.begin), balls);
        const XpbdJointSchedule::Ball& stored = schedule.balls[balls++];
        EXPECT_EQ(stored.body0, jointEnds(world.joints[j]).body0);
        EXPECT_EQ(stored.body1, jointEnds(world.joints[j]).body1);
      }
      const JointType type = jointType(world.joints[j]);
      if (type == JointType::TargetVelocityMotorHinge || type == JointType::TargetAngleMotorHinge)
        targets.push_back(j);
      if (type == JointType::TargetVelocityMotorHinge) velocityPasses.push_back(j);
    }
    next = run.end;
  }
  EXPECT_EQ(next, world.joints.size());
  EXPECT_EQ(balls, schedule.balls.size());
  EXPECT_EQ(balls, 4u);  // joints 0, 1, 3, 6
  EXPECT_EQ(schedule.withTarget, targets);
  EXPECT_EQ(schedule.withVelocityPass, velocityPasses);
  EXPECT_EQ(velocityPasses.size(), 1u);
}

// A chain of 10 links (0.1 m cubes, 10 g) from a static anchor holding a 1 kg cube (1:100),
// released 30° off vertical, without collision shapes (as cases/chain_mass_ratio.json). The
// issue's target is a joint error ≤ 1 mm; we report the cost. With one Gauss–Seidel pass per
// substep, each joint's residual is its neighbours' corrections of the same substep, O(h_s²):
// doubling the substeps must divide the error by about 4 (we require at least 3).
TEST(XpbdChain, MassRatioChainHoldsItsJoints) {
  Scene s;
  s.simulation.timeStepSize = Real(0.005);
  const Real link = Real(0.1);
  const Vector3 down(std::sin(kPi / 6), -std::cos(kPi / 6), 0);
  const Vector3 anchor(0, 2, 0);
  s.rigidBodies.push_back(test::boxBody(0, Vector3::Constant(link), anchor, 1, false));
  for (int i = 1; i <= 10; ++i)
    s.rigidBodies.push_back(test::boxBody(i, Vector3::Constant(link),
                                          anchor + (Real(i) - Real(0.5)) * link * down, 10));
  s.rigidBodies.push_back(
      test::boxBody(11, Vector3::Constant(Real(0.2)), anchor + Real(1.1) * down, 125));
  for (RigidBodyDesc& body : s.rigidBodies)
    body.collision.type = CollisionObjectType::None;
  for (int i = 0; i <= 10; ++i) {
    JointDesc j = test::makeJointDesc(JointType::Ball, i, i + 1);
    j.position = anchor + link * Real(i) * down;
    s.joints.push_back(j);
  }
  Real errors[2] = {0, 0};
  const int substeps[2] = {20, 40};
  for (int k = 0; k < 2; ++k) {
    useXpbd(s, substeps[k]);
    World world = buildWorld(s);
    // Precision-aware: 1e-9 = 45 ε relative on 100 in double (density × volume for both
    // bodies, then a quotient), the same multiple of ε in float.
    EXPECT_NEAR(double(world.bodies.rigid.mass[11] / world.bodies.rigid.mass[1]), 100,
                double(test::roundOffBound(1e-9)));
    const auto begin = std::chrono::steady_clock::now();
    for (int n = 0; n < 400; ++n) {  // 2 s
      world.step();
      for (const Joint& joint : world.joints)
        errors[k] = std::max(errors[k], jointError(joint, world.bodies).linear);
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
    std::printf("  chain 1:100, %d substeps: max joint error %.3e m, %.0f us per step\n",
                substeps[k], double(errors[k]), 1e6 * seconds / 400);
  }
  EXPECT_LE(errors[0], 1e-3);
  EXPECT_GE(errors[0] / errors[1], 3);
}

}  // namespace
}  // namespace pbd
