// Energy, momenta, the initial state and the default scales, against values computed by hand.
#include <gtest/gtest.h>

#include "tests/validation/fixtures.h"
#include "validation/measure/mechanics.h"

namespace pbdval {
namespace {

using pbd::JointType;
using pbd::test::boxBody;
using test::turn;

// A 0.2 × 0.4 × 0.6 m box of density 1000: m = 48 kg, principal moments
// I_x = m(0.4² + 0.6²)/12 = 2.08, I_y = m(0.2² + 0.6²)/12 = 1.6, I_z = m(0.2² + 0.4²)/12 = 0.8.
const Vector3 kExtents(0.2, 0.4, 0.6);
constexpr double kMass = 48;
// Hand values below are sums of a few products of short decimals: relative rounding ~1e-15.
constexpr double kRelative = 1e-13;

pbd::Scene oneBox(const Vector3& gravity = Vector3(0, -9.81, 0)) {
  pbd::Scene scene = test::emptyScene(gravity);
  scene.rigidBodies.push_back(boxBody(1, kExtents, Vector3(0, 3, 0), 1000));
  return scene;
}

State stateWith(const pbd::Scene& scene, const Vector3& v, const Vector3& w) {
  State s = initialState(scene);
  s.bodies[0].velocity = v;
  s.bodies[0].angularVelocity = w;
  return s;
}

TEST(Energy, OfABoxWithKnownVelocitiesAndHeight) {
  const pbd::Scene scene = oneBox();
  ASSERT_NEAR(scene.rigidBodies[0].massProperties.mass, kMass, 1e-12);
  const EnergyTerms e = energyOf(scene, stateWith(scene, Vector3(1, 2, 2), Vector3(1, 0, 2)));
  EXPECT_NEAR(e.translational, 216.0, 216 * kRelative);        // ½ · 48 · 9
  EXPECT_NEAR(e.rotational, 2.64, 2.64 * kRelative);           // ½ (2.08 · 1 + 0.8 · 4)
  EXPECT_NEAR(e.gravitational, 1412.64, 1412.64 * kRelative);  // 48 · 9.81 · 3
  EXPECT_EQ(e.spring, 0.0);
  EXPECT_NEAR(e.total(), 216 + 2.64 + 1412.64, 1632 * kRelative);
}

TEST(Energy, UsesTheReadBackRotationForTheWorldInertia) {
  const pbd::Scene scene = oneBox();
  State s = stateWith(scene, Vector3::Zero(), Vector3(1, 0, 2));
  // Turned 90° about z: the body's x axis (2.08) points along world y, its y axis (1.6) along
  // world x, so ½ ωᵀ I_w ω = ½ (1.6 · 1 + 0.8 · 4) = 2.4 J.
  s.bodies[0].rotation = turn(Vector3::UnitZ(), test::kPi / 2);
  EXPECT_NEAR(energyOf(scene, s).rotational, 2.4, 2.4 * kRelative);
}

TEST(Energy, ComposesThePrincipalRotation) {
  pbd::Scene scene = oneBox();
  // The same principal moments, but the principal frame turned 90° about z in the scene frame:
  // in the scene frame I = diag(1.6, 2.08, 0.8).
  scene.rigidBodies[0].massProperties.principalRotation = turn(Vector3::UnitZ(), test::kPi / 2);
  const State s = stateWith(scene, Vector3::Zero(), Vector3(1, 0, 2));
  EXPECT_NEAR(energyOf(scene, s).rotational, 2.4, 2.4 * kRelative);
  const Matrix3 inertia = worldInertia(scene.rigidBodies[0], Quaternion::Identity());
  EXPECT_NEAR((inertia - Vector3(1.6, 2.08, 0.8).asDiagonal().toDenseMatrix()).norm(), 0, 1e-14);
}

TEST(Energy, IgnoresStaticBodies) {
  pbd::Scene scene = oneBox();
  scene.rigidBodies.push_back(boxBody(2, kExtents, Vector3(0, 10, 0), 1000, false));
  State s = stateWith(scene, Vector3::Zero(), Vector3::Zero());
  s.bodies[1].velocity = Vector3(5, 0, 0);  // a static body's read-back never counts
  EXPECT_NEAR(energyOf(scene, s).total(), 1412.64, 1412.64 * kRelative);
}

TEST(Energy, AddsMovingParticlesOnly) {
  pbd::Scene scene = test::emptyScene(Vector3(0, -10, 0));
  scene.particles.push_back({Vector3(0, 2, 0), Vector3::Zero(), 1});
  scene.particles.push_back({Vector3(0, 5, 0), Vector3::Zero(), 0});  // static
  State s = initialState(scene);
  s.particles[0].velocity = Vector3(3, 4, 0);
  s.particles[1].velocity = Vector3(100, 0, 0);
  const EnergyTerms e = energyOf(scene, s);
  EXPECT_NEAR(e.translational, 12.5, 1e-13);  // ½ · 1 · 25
  EXPECT_NEAR(e.gravitational, 20.0, 1e-13);  // 1 · 10 · 2
}

pbd::Scene springScene(JointType type) {
  pbd::Scene scene = test::emptyScene();
  scene.rigidBodies.push_back(boxBody(0, Vector3(0.1, 0.1, 0.1), Vector3(0, 2, 0), 1000, false));
  scene.rigidBodies.push_back(boxBody(1, Vector3(0.2, 0.2, 0.2), Vector3(0, 1, 0), 1000));
  pbd::JointDesc j = pbd::test::makeJointDesc(type, 0, 1);
  j.position1 = Vector3(0, 2, 0);
  j.position2 = Vector3(0, 1.5, 0);  // rest length 0.5 m; connector 0.5 m above body 1's centre
  j.axis = Vector3(0, 1, 0);
  j.stiffness = 200;
  scene.joints.push_back(j);
  return scene;
}

TEST(Energy, OfAStretchedSpringFromTheT0Geometry) {
  const pbd::Scene scene = springScene(JointType::RigidBodySpring);
  State s = initialState(scene);
  EXPECT_EQ(energyOf(scene, s).spring, 0.0);
  s.bodies[1].position.y() -= 0.1;  // ℓ = 0.6: ½ · 200 · 0.1² = 1 J
  EXPECT_NEAR(energyOf(scene, s).spring, 1.0, 1e-12);
  // Turning body 1 by 90° about z swings its connector from (0, 0.5, 0) to (−0.5, 0, 0)
  // relative to its centre (0, 0.9, 0): ℓ = ‖(−0.5, 0.9, 0) − (0, 2, 0)‖ = √(0.25 + 1.21).
  s.bodies[1].rotation = turn(Vector3::UnitZ(), test::kPi / 2);
  const double stretch = std::sqrt(1.46) - 0.5;
  EXPECT_NEAR(energyOf(scene, s).spring, 100 * stretch * stretch, 1e-12);
}

TEST(Energy, OfADamperIsItsAxialOffsetOnly) {
  pbd::Scene scene = springScene(JointType::Damper);
  scene.joints[0].stiffness = 2000;
  State s = initialState(scene);
  s.bodies[1].position += Vector3(0.3, 0.05, 0);       // 0.05 along the axis, 0.3 across it
  EXPECT_NEAR(energyOf(scene, s).spring, 2.5, 1e-12);  // ½ · 2000 · 0.05²
}

TEST(Momenta, OfTwoBoxesAboutTheirCentreOfMass) {
  pbd::Scene scene = test::emptyScene(Vector3::Zero());
  scene.rigidBodies.push_back(boxBody(1, kExtents, Vector3(1, 0, 0), 1000));
  scene.rigidBodies.push_back(boxBody(2, kExtents, Vector3(-1, 0, 0), 1000));
  State s = initialState(scene);
  s.bodies[0].velocity = Vector3(1, 1, 0);
  s.bodies[1].velocity = Vector3(1, -1, 0);
  s.bodies[0].angularVelocity = Vector3(0, 0, 1);
  const Momenta p = momentaOf(scene, s);
  EXPECT_NEAR(p.mass, 96, 1e-12);
  EXPECT_NEAR((p.linear - Vector3(96, 0, 0)).norm(), 0, 1e-12);
  EXPECT_NEAR(p.centerOfMass.norm(), 0, 1e-15);
  // (1,0,0) × 48 (1,1,0) + (−1,0,0) × 48 (1,−1,0) = (0,0,48) + (0,0,48); spin I_z ω = 0.8.
  EXPECT_NEAR((p.angular - Vector3(0, 0, 96.8)).norm(), 0, 1e-12);
  // Composite inertia: 96 diag(0,1,1) + 2 diag(2.08, 1.6, 0.8); largest 99.2.
  EXPECT_NEAR(systemInertia(scene, s), 99.2, 1e-12);
}

TEST(Momenta, AngularIsTakenAboutTheMovingCentreOfMass) {
  pbd::Scene scene = test::emptyScene(Vector3::Zero());
  scene.rigidBodies.push_back(boxBody(1, kExtents, Vector3(5, 7, 0), 1000));
  State s = initialState(scene);
  s.bodies[0].velocity = Vector3(3, 0, 0);  // translating far from the origin: L = 0
  EXPECT_NEAR(momentaOf(scene, s).angular.norm(), 0, 1e-12);
}

TEST(InitialState, PlacesTheCentreOfMassAndKeepsTheSceneRotation) {
  pbd::Scene scene = oneBox();
  pbd::RigidBodyDesc& body = scene.rigidBodies[0];
  body.massProperties.centerOfMass = Vector3(0.1, 0, 0);
  body.rotation = turn(Vector3::UnitZ(), test::kPi / 2);
  body.velocity = Vector3(1, 0, 0);
  const State s = initialState(scene);
  // x = translation + R c = (0, 3, 0) + (0, 0.1, 0).
  EXPECT_NEAR((s.bodies[0].position - Vector3(0, 3.1, 0)).norm(), 0, 1e-15);
  EXPECT_EQ(s.bodies[0].rotation.coeffs(), body.rotation.coeffs());
  EXPECT_EQ(s.bodies[0].velocity, Vector3(1, 0, 0));
  EXPECT_EQ(s.bodies[0].id, 1);
}

TEST(CheckStateMatchesScene, RejectsMissingOrReorderedBodies) {
  pbd::Scene scene = oneBox();
  scene.rigidBodies.push_back(boxBody(2, kExtents, Vector3(0, 10, 0), 1000));
  State s = initialState(scene);
  EXPECT_NO_THROW(checkStateMatchesScene(scene, s));
  std::swap(s.bodies[0], s.bodies[1]);
  EXPECT_THROW(checkStateMatchesScene(scene, s), std::invalid_argument);
  s.bodies.pop_back();
  EXPECT_THROW(checkStateMatchesScene(scene, s), std::invalid_argument);
}

TEST(EnergyScale, DefaultIsInitialKineticEnergyPlusWeightTimesOneMetre) {
  pbd::Scene scene = oneBox();
  scene.rigidBodies[0].velocity = Vector3(1, 2, 2);
  scene.rigidBodies[0].angularVelocity = Vector3(1, 0, 2);
  // 216 + 2.64 + 48 · 9.81 · 1 = 689.52 J.
  EXPECT_NEAR(defaultEnergyScale(scene), 689.52, 689.52 * kRelative);
  CaseSpec spec;
  std::string note;
  EXPECT_NEAR(energyScale(scene, spec, &note), 689.52, 689.52 * kRelative);
  EXPECT_NE(note.find("default"), std::string::npos);
  spec.energyScale = 5.0;
  EXPECT_EQ(energyScale(scene, spec, &note), 5.0);
  EXPECT_NE(note.find("Validation.energyScale"), std::string::npos);
}

TEST(EnergyScale, FallsBackToOneJouleForAMotionlessWeightlessScene) {
  const pbd::Scene scene = oneBox(Vector3::Zero());
  std::string note;
  EXPECT_EQ(defaultEnergyScale(scene), 0.0);
  EXPECT_EQ(energyScale(scene, CaseSpec{}, &note), 1.0);
  EXPECT_NE(note.find("1 J"), std::string::npos);
}

TEST(MomentumScales, AreTheLargerOfTheInitialMomentumAndTheEnergyScale) {
  pbd::Scene scene = oneBox();
  scene.rigidBodies[0].velocity = Vector3(1, 2, 2);
  scene.rigidBodies[0].angularVelocity = Vector3(1, 0, 2);
  // ‖P₀‖ = 48 · 3 = 144 < √(2 · 48 · 689.52) = 257.29...
  const MomentumScales s = momentumScales(scene, 689.52);
  EXPECT_NEAR(s.linear, std::sqrt(2 * 48 * 689.52), 1e-10);
  // L₀ = (2.08, 0, 1.6), ‖L₀‖ = 2.62 < √(2 · 2.08 · 689.52) (I_sys = 2.08 for one body).
  EXPECT_NEAR(s.angular, std::sqrt(2 * 2.08 * 689.52), 1e-10);
  // A tiny E_ref: the initial momenta win.
  const MomentumScales small = momentumScales(scene, 1e-6);
  EXPECT_NEAR(small.linear, 144, 1e-10);
  EXPECT_NEAR(small.angular, std::sqrt(2.08 * 2.08 + 1.6 * 1.6), 1e-12);
}

}  // namespace
}  // namespace pbdval
