// XpbdSettings::jointDirections: joints projected along the constraint directions of the
// substep's start (SHAKE, Ryckaert, Ciccotti, Berendsen 1977) instead of the current poses'
// (PBD's implicit constraint direction, Goldenthal et al. 2007). Both are first order in the
// substep; the start directions have no numerical damping, hence a far smaller constant. A hinge
// physical pendulum is integrated against its equation of motion, every joint type keeps the
// Newton-step bound of its constraint, and both settings are bitwise deterministic. Numbers
// are printed for docs/methods.md and docs/convergence.md.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "common/joint_hold.h"
#include "common/scene_fixtures.h"
#include "common/tolerances.h"
#include "common/two_bodies.h"
#include "pbd/joints/point_constraint.h"
#include "pbd/model/world.h"

namespace pbd {
namespace {

constexpr Real kGravity = Real(9.81);

void useXpbd(Scene& s, int substeps, JointDirections directions) {
  s.simulation.stepMethod = StepMethod::Xpbd;
  s.simulation.xpbd.substeps = substeps;
  s.simulation.xpbd.jointDirections = directions;
}

struct PendulumErrors {
  Real position = 0;  ///< max |x − x_exact| of the centre of mass over the run (m)
  Real energy = 0;    ///< max |E − E₀| / (m g d (1 − cos θ₀))
};

/// The hinge physical pendulum of test::pendulumScene (a 0.1 × 0.4 × 0.1 box, centre of mass
/// d = 1 m from the pivot, θ₀ = atan(0.6/0.8)) at h = 5 ms for 3 s under pbd.xpbd, against
/// θ'' = −(m g d / I_p) sin θ, I_p = I_zz + m d², integrated by classical Runge–Kutta at h/100
/// (its error, ~ (h/100)⁴ θ⁽⁵⁾, is below 10⁻¹³ m here).
PendulumErrors runPendulum(int substeps, JointDirections directions) {
  Scene scene = test::pendulumScene(JointType::Hinge, Real(1e-3));
  useXpbd(scene, substeps, directions);
  World world = buildWorld(scene);
  const auto& b = world.bodies.rigid;
  const Vector3 pivot = scene.joints[0].position;
  const Vector3 arm0 = b.position[1] - pivot;
  const Real d = arm0.norm();
  const Real m = b.mass[1];
  const Real omega2 = m * kGravity * d / (b.inertiaWorld(1)(2, 2) + m * d * d);
  Real theta = std::atan2(arm0.x(), -arm0.y()), rate = 0;
  const Real swingEnergy = m * kGravity * d * (1 - std::cos(theta));
  const auto energy = [&] {
    return Real(0.5) * m * b.velocity[1].squaredNorm() +
           Real(0.5) * b.angularVelocity[1].dot(b.inertiaWorld(1) * b.angularVelocity[1]) +
           m * kGravity * b.position[1].y();
  };
  const Real e0 = energy();
  const Real h = scene.simulation.timeStepSize;
  const int fine = 100;
  const Real dt = h / fine;
  const auto acceleration = [&](Real angle) { return -omega2 * std::sin(angle); };
  PendulumErrors errors;
  for (int n = 0; n < 600; ++n) {  // 3 s
    world.step();
    for (int k = 0; k < fine; ++k) {
      const Real k1x = rate, k1v = acceleration(theta);
      const Real k2x = rate + dt / 2 * k1v, k2v = acceleration(theta + dt / 2 * k1x);
      const Real k3x = rate + dt / 2 * k2v, k3v = acceleration(theta + dt / 2 * k2x);
      const Real k4x = rate + dt * k3v, k4v = acceleration(theta + dt * k3x);
      theta += dt / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
      rate += dt / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
    }
    const Vector3 exact = pivot + d * Vector3(std::sin(theta), -std::cos(theta), 0);
    errors.position = std::max(errors.position, (b.position[1] - exact).norm());
    errors.energy = std::max(errors.energy, std::abs(energy() - e0) / swingEnergy);
  }
  return errors;
}

// Goldenthal et al. 2007, and 2-D pendulums worked out for this change with one projection per
// substep, 60°, 3 s: the damping of the implicit constraint direction is first order with a
// large constant, SHAKE's error first order with a smaller one — a factor 13–14 for a point
// mass (PBD 2.2e-2 m against SHAKE 1.57e-3 m at h_s = 1 ms), 31 for a box pivoted at its end
// (5.8e-3 against 1.85e-4 m at 0.25 ms). This bob (centre of mass 1 m from the pivot, radius of
// gyration 0.12 m) is close to the point mass. Asserted at 20 substeps (h_s = 0.25 ms): (a) the
// start directions' position error and (c) energy drift are at most a fifth of the current
// directions' (the point mass's factor 13 with a margin of 2.6 for the amplitude, 37° here,
// and the 3-D hinge rows); (b) both settings are first order: halving h_s halves the error
// within 22 % (ratios 1.55 … 2.45).
TEST(XpbdJointDirections, StartDirectionsCutThePendulumErrorFivefoldAtFirstOrder) {
  if (sizeof(Real) < 8)
    GTEST_SKIP() << "needs double precision: g h_s^2 = 6e-7 m per substep at 40 substeps is "
                    "a few ulps of the bob's height 1.2 m in float";
  const PendulumErrors start20 = runPendulum(20, JointDirections::Start);
  const PendulumErrors start40 = runPendulum(40, JointDirections::Start);
  const PendulumErrors predicted20 = runPendulum(20, JointDirections::Predicted);
  const PendulumErrors predicted40 = runPendulum(40, JointDirections::Predicted);
  std::printf(
      "  hinge pendulum 3 s, max position error (m) / energy drift (swing energy):\n"
      "    start      20 substeps %.3e / %.3e, 40 substeps %.3e / %.3e\n"
      "    predicted  20 substeps %.3e / %.3e, 40 substeps %.3e / %.3e\n",
      double(start20.position), double(start20.energy), double(start40.position),
      double(start40.energy), double(predicted20.position), double(predicted20.energy),
      double(predicted40.position), double(predicted40.energy));
  EXPECT_LE(start20.position, predicted20.position / 5);
  EXPECT_LE(start20.energy, predicted20.energy / 5);
  EXPECT_NEAR(start20.position / start40.position, 2, 0.45);
  EXPECT_NEAR(predicted20.position / predicted40.position, 2, 0.45);
}

class XpbdStartDirectionsHold : public ::testing::TestWithParam<int> {};

// The bound of common/joint_hold.h: SHAKE's step solves the linearisation of C along the start
// directions exactly (K = ∂C/∂λ at the current poses), so it is a Newton step like the current
// directions' projection and leaves O(δ²/ℓ) of the substep's drift δ.
TEST_P(XpbdStartDirectionsHold, ConstraintErrorStaysBelowSubstepBound) {
  const auto type = static_cast<JointType>(GetParam());
  if (type == JointType::RigidBodySpring) GTEST_SKIP() << "compliant: no hold bound";
  Scene scene = test::singleJointScene(type);
  useXpbd(scene, 20, JointDirections::Start);
  test::expectJointHoldsBelowSubstepBound(scene, type, 20, Real(1) / 20);
}

INSTANTIATE_TEST_SUITE_P(AllJointTypes, XpbdStartDirectionsHold,
                         ::testing::Range(0, kJointTypeCount),
                         [](const ::testing::TestParamInfo<int>& param) {
                           return std::string(jointTypeName(static_cast<JointType>(param.param)));
                         });

/// State hash of a 10-link hinge chain after 1 s under pbd.xpbd with `directions`.
std::uint64_t chainHash(JointDirections directions, JointType type) {
  Scene scene;
  scene.simulation.timeStepSize = Real(0.005);
  scene.rigidBodies.push_back(test::boxBody(0, Vector3(0.1, 0.1, 0.1), Vector3(0, 2, 0), 1, false));
  test::appendChain(scene, 10, type);
  useXpbd(scene, 20, directions);
  World world = buildWorld(scene);
  for (int n = 0; n < 200; ++n)
    world.step();
  return world.stateHash();
}

// Determinism: the same scene and build give the same bits with either setting, and the two
// settings do differ (the setting reaches the solve), for the ball joints' direct solve and the
// generic block solve (hinges).
TEST(XpbdJointDirections, BothSettingsAreBitwiseDeterministicAndDiffer) {
  for (JointType type : {JointType::Ball, JointType::Hinge}) {
    const std::uint64_t start = chainHash(JointDirections::Start, type);
    EXPECT_EQ(start, chainHash(JointDirections::Start, type)) << jointTypeName(type);
    const std::uint64_t predicted = chainHash(JointDirections::Predicted, type);
    EXPECT_EQ(predicted, chainHash(JointDirections::Predicted, type)) << jointTypeName(type);
    EXPECT_NE(start, predicted) << jointTypeName(type);
  }
}

RigidBodyStates twoTurnedBodiesWithStart() {
  RigidBodyStates b = test::twoTurnedBodies();
  // The substep's start: both bodies turned back by 0.04 rad (below the 0.1 rad limit).
  b.oldRotation[0] = Quaternion(AngleAxis(-0.04, Vector3(0, 0, 1))) * b.rotation[0];
  b.oldRotation[1] = Quaternion(AngleAxis(0.04, Vector3(1, 0, 0))) * b.rotation[1];
  return b;
}

// The point constraint's SHAKE step against its definition: the corrections act along the
// start directions — Δx₀ = −w₀ Δλ, Δθ₀ = −J₀ⁿ (r₀ⁿ × Δλ), Δθ₁ = J₁ⁿ (r₁ⁿ × Δλ) (body 0 takes
// the impulse −Δλ at its anchor, body 1 +Δλ), with J_kⁿ and r_kⁿ
// of oldRotation, computed here independently — and Δλ is the Newton step, so that C at the
// new poses is second order in the correction (|C_after| ≤ 10⁻² |C_before| for this 1 cm
// offset; a symmetric K of the start directions alone leaves about the 0.04 rad turn times
// |C_before|, a step that ignored the turn entirely O(1)).
TEST(XpbdJointDirections, PointConstraintStepActsAlongTheStartDirectionsAndClosesTheJoint) {
  RigidBodyStates b = twoTurnedBodiesWithStart();
  const Vector3 a0(0.25, -0.1, 0.4), a1(-0.3, 0.2, 0.05);
  const auto c = [&](const RigidBodyStates& s) -> Vector3 {
    return (s.position[1] + s.rotation[1] * a1) - (s.position[0] + s.rotation[0] * a0);
  };
  // Move body 1 so that the anchors are 1 cm apart.
  b.position[1] -= c(b) + Vector3(0.006, -0.008, 0);
  const RigidBodyStates before = b;
  const Real cBefore = c(before).norm();
  const Vector3 multiplier =
      projectPointConstraint(b, 0, 1, a0, a1, 0, Vector3::Zero(), JointDirections::Start);
  const Vector3 r0 = before.oldRotation[0] * a0, r1 = before.oldRotation[1] * a1;
  const Matrix3 j0 = before.oldRotation[0].toRotationMatrix() *
                     before.inverseInertia[0].asDiagonal() *
                     before.oldRotation[0].toRotationMatrix().transpose();
  const Matrix3 j1 = before.oldRotation[1].toRotationMatrix() *
                     before.inverseInertia[1].asDiagonal() *
                     before.oldRotation[1].toRotationMatrix().transpose();
  // The same few operations on O(1) numbers: round-off, 10⁻¹⁴ in double.
  const Real roundOff = test::roundOffBound(1e-14);
  EXPECT_LT((b.position[0] - (before.position[0] - before.inverseMass[0] * multiplier)).norm(),
            roundOff);
  EXPECT_LT((b.position[1] - (before.position[1] + before.inverseMass[1] * multiplier)).norm(),
            roundOff);
  // The applied rotation, ½-angle quaternion update then normalised: compare the turn vectors
  // to first order (their difference is O(|Δθ|²) ≈ 10⁻⁴ |Δθ| here).
  const Vector3 turn0 = 2 * (b.rotation[0] * before.rotation[0].conjugate()).vec();
  const Vector3 turn1 = 2 * (b.rotation[1] * before.rotation[1].conjugate()).vec();
  const Vector3 expected0 = -(j0 * r0.cross(multiplier));
  const Vector3 expected1 = j1 * r1.cross(multiplier);
  EXPECT_LT((turn0 - expected0).norm(), 1e-2 * expected0.norm());
  EXPECT_LT((turn1 - expected1).norm(), 1e-2 * expected1.norm());
  EXPECT_LT(c(b).norm(), 1e-2 * cBefore);
  std::printf("  SHAKE point step: |C| %.3e -> %.3e m\n", double(cBefore), double(c(b).norm()));
}

// With no turn in the substep (start = current poses) both settings are the same projection.
TEST(XpbdJointDirections, PointConstraintStepIsThePredictedOneWhenTheBodiesDidNotTurn) {
  RigidBodyStates start = twoTurnedBodiesWithStart();
  start.oldRotation = start.rotation;
  RigidBodyStates predicted = start;
  const Vector3 a0(0.25, -0.1, 0.4), a1(-0.3, 0.2, 0.05);
  const Vector3 m1 =
      projectPointConstraint(start, 0, 1, a0, a1, 0, Vector3::Zero(), JointDirections::Start);
  const Vector3 m2 = projectPointConstraint(predicted, 0, 1, a0, a1, 0, Vector3::Zero(),
                                            JointDirections::Predicted);
  // The same 3×3 system solved by L U and by L D Lᵀ (κ(K) < 10³): round-off, 10⁻¹¹ relative
  // (100 κ ε in double, the same multiple of ε in float).
  const Real tolerance = test::roundOffBound(1e-11);
  EXPECT_LT((m1 - m2).norm(), tolerance * m2.norm());
  for (std::size_t i = 0; i < 2; ++i)
    EXPECT_LT((start.position[i] - predicted.position[i]).norm(), tolerance) << "body " << i;
}

}  // namespace
}  // namespace pbd
