// Time integration and the step controller against closed forms of the discrete method.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "common/scene_fixtures.h"
#include "pbd/math/quaternion.h"
#include "pbd/model/world.h"

namespace pbd {
namespace {

Scene projectileScene(int subSteps, int velocityUpdateMethod) {
  Scene s;
  s.simulation.timeStepSize = Real(0.01);
  s.simulation.subSteps = subSteps;
  s.simulation.velocityUpdateMethod = velocityUpdateMethod;
  s.simulation.gravitation = Vector3(0.5, -9.81, 0.25);
  RigidBodyDesc b = test::boxBody(7, Vector3(0.1, 0.2, 0.3), Vector3(1, 2, 3), 10);
  b.velocity = Vector3(3, 4, -1);
  s.rigidBodies.push_back(b);
  return s;
}

// Semi-implicit Euler with substep h_s under constant g, after k substeps:
//   v_k = v₀ + k h_s g,   x_k = x₀ + k h_s v₀ + h_s² g k(k+1)/2.
// The seed's first-order velocity update v = (x − x_old)/h_s reproduces v_k up to round-off.
TEST(Integration, ProjectileWithSubstepsMatchesDiscreteClosedForm) {
  for (int subSteps : {1, 5, 8}) {
    const Scene scene = projectileScene(subSteps, 0);
    World world = buildWorld(scene);
    const Real hs = scene.simulation.timeStepSize / subSteps;
    const Vector3 g = scene.simulation.gravitation;
    const Vector3 x0 = world.bodies.rigid.position[0];
    const Vector3 v0 = world.bodies.rigid.velocity[0];
    const int steps = 200;
    for (int n = 0; n < steps; ++n)
      world.step();
    const Real k = static_cast<Real>(steps * subSteps);
    const Vector3 expectedX = x0 + k * hs * v0 + hs * hs * g * k * (k + 1) / 2;
    const Vector3 expectedV = v0 + k * hs * g;
    // Round-off bound: each velocity update (x − x_old)/h_s carries a relative error of
    // ~2ε|x|/(h_s|v|), i.e. an absolute velocity error ≤ 2ε|x|_max/h_s per substep; it enters the
    // position through later substeps, so |Δx| ≤ k² · 2ε|x|_max and |Δv| ≤ k · 2ε|x|_max/h_s.
    const Real xMax = std::max(expectedX.norm(), x0.norm());
    EXPECT_LE((world.bodies.rigid.position[0] - expectedX).norm(), k * k * 2 * kEpsilon * xMax)
        << "subSteps " << subSteps;
    EXPECT_LE((world.bodies.rigid.velocity[0] - expectedV).norm(), k * 2 * kEpsilon * xMax / hs)
        << "subSteps " << subSteps;
    EXPECT_NEAR(world.time, steps * scene.simulation.timeStepSize, 10 * kEpsilon);
  }
}

// The seed's "second-order" update v_{k+1} = (1.5 x_{k+1} − 2 x_k + 0.5 x_{k−1})/h after a
// semi-implicit Euler prediction x_{k+1} = x_k + h (v_k + h g) obeys the recurrence
//   v_{k+1} = 1.5 v_k − 0.5 v_{k−1} + h g   (x_{−1} = x₀, so v₀ = 0 ⇒ v₁ = 1.5 h g),
// whose solution from rest is v_k = h g (2k − 1 + 2^{−k}): free fall under velocityUpdateMethod
// 1 accelerates at 2g asymptotically. This is the seed's behaviour, kept (docs/methods.md).
TEST(Integration, SecondOrderVelocityUpdateFollowsItsRecurrence) {
  Scene scene = projectileScene(4, 1);
  scene.rigidBodies[0].velocity.setZero();
  World world = buildWorld(scene);
  const Real hs = scene.simulation.timeStepSize / 4;
  const Vector3 g = scene.simulation.gravitation;
  for (int n = 0; n < 25; ++n)
    world.step();
  const Real k = 100;
  const Vector3 expected = hs * g * (2 * k - 1 + std::pow(Real(2), -k));
  // 100 substeps of cancellation-prone differences, as in the test above.
  EXPECT_LE((world.bodies.rigid.velocity[0] - expected).norm(), k * 8 * kEpsilon * 10 / hs);
}

TEST(Integration, StaticBodiesDoNotMove) {
  Scene scene = projectileScene(5, 0);
  scene.rigidBodies[0].isDynamic = false;
  World world = buildWorld(scene);
  const Vector3 x0 = world.bodies.rigid.position[0];
  for (int n = 0; n < 10; ++n)
    world.step();
  EXPECT_EQ(world.bodies.rigid.position[0], x0);
  EXPECT_EQ(world.bodies.rigid.velocity[0], Vector3::Zero());
}

// Torque-free rotation about a principal axis: the gyroscopic term ω × Iω vanishes, so each
// substep turns the body by the normalised first-order update q ← normalize(q + ½h[0,ω]q),
// an angle of exactly 2 atan(h|ω|/2) about ω, and the first-order velocity update then reads
// ω back as 2 vec(q q_old⁻¹)/h = ω/√(1 + (h|ω|/2)²). So the seed's scheme slowly spins the
// body down: ω_{k+1} = ω_k/√(1 + (h ω_k/2)²), θ_{k+1} = θ_k + 2 atan(h ω_k/2). The test
// iterates this scalar recurrence independently and compares.
TEST(Integration, SpinAboutPrincipalAxisFollowsDiscreteRecurrence) {
  Scene scene = projectileScene(5, 0);
  scene.simulation.gravitation.setZero();
  scene.rigidBodies[0].velocity.setZero();
  scene.rigidBodies[0].angularVelocity = Vector3(0, 3, 0);
  World world = buildWorld(scene);
  const Real hs = scene.simulation.timeStepSize / 5;
  Real omega = 3, angle = 0;
  for (int k = 0; k < 500; ++k) {
    angle += 2 * std::atan(hs * omega / 2);
    omega /= std::sqrt(1 + (hs * omega / 2) * (hs * omega / 2));
  }
  for (int n = 0; n < 100; ++n)
    world.step();
  // Round-off: ~10 operations per substep on O(1) values, 500 substeps; the angle read-back
  // 2 vec(q q_old⁻¹)/h amplifies the quaternion's round-off by 2/h.
  EXPECT_NEAR(world.bodies.rigid.angularVelocity[0].y(), omega, 500 * 10 * kEpsilon * 2 / hs);
  EXPECT_LT(omega, 3 * (1 - 1e-3));  // the decay is real, not round-off
  const Quaternion expected(AngleAxis(angle, Vector3::UnitY()));
  EXPECT_LE(rotationAngleBetween(world.sceneFrameState(0).rotation, expected), 500 * 10 * kEpsilon);
}

TEST(Integration, SceneFrameStateUndoesPrincipalAxes) {
  Scene scene = projectileScene(1, 0);
  // A body whose principal frame differs from its scene frame.
  scene.rigidBodies[0].rotation = Quaternion(AngleAxis(0.4, Vector3(1, 1, 0).normalized()));
  scene.rigidBodies[0].massProperties.principalRotation =
      Quaternion(AngleAxis(1.1, Vector3(0, 1, 1).normalized()));
  scene.rigidBodies[0].massProperties.centerOfMass = Vector3(0.1, 0.2, -0.3);
  const World world = buildWorld(scene);
  const SceneFrameState state = world.sceneFrameState(0);
  EXPECT_LE(rotationAngleBetween(state.rotation, scene.rigidBodies[0].rotation), 1e-14);
  EXPECT_TRUE(state.centerOfMass.isApprox(scene.rigidBodies[0].translation +
                                          scene.rigidBodies[0].rotation * Vector3(0.1, 0.2, -0.3)));
}

// rotateVector / rotateVectorInverse claim Eigen's own operations in Eigen's order (they exist
// to be inlined where Eigen's call is not): compared bit for bit, not within a tolerance, on
// random unit quaternions and vectors of mixed magnitudes; also R v against the rotation
// matrix's product to a round-off bound, so that an agreement of two wrong formulas fails too.
TEST(Integration, InlinedQuaternionRotationIsBitwiseEigens) {
  std::mt19937_64 random(20261129);
  std::normal_distribution<Real> normal(0, 1);
  std::uniform_real_distribution<Real> exponent(-6, 3);
  for (int trial = 0; trial < 10000; ++trial) {
    const Quaternion q =
        Quaternion(normal(random), normal(random), normal(random), normal(random)).normalized();
    const Vector3 v = std::pow(Real(10), exponent(random)) *
                      Vector3(normal(random), normal(random), normal(random));
    const Vector3 rotated = rotateVector(q, v), back = rotateVectorInverse(q, v);
    const Vector3 eigenRotated = q * v, eigenBack = q.conjugate() * v;
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(rotated[k], eigenRotated[k]) << "trial " << trial;
      EXPECT_EQ(back[k], eigenBack[k]) << "trial " << trial;
    }
    // A product of a unit quaternion's rotation and its matrix's: a few ulps of |v| each.
    EXPECT_LE((rotated - q.toRotationMatrix() * v).norm(), 64 * kEpsilon * v.norm());
    EXPECT_LE((back - q.toRotationMatrix().transpose() * v).norm(), 64 * kEpsilon * v.norm());
  }
}

}  // namespace
}  // namespace pbd
