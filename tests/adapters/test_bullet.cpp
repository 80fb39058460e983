// Bullet adapter: how the Scene maps onto Bullet (mass properties, frames, materials, joints),
// what is reported unsupported, and what is recorded with a run. Expected values come from
// the Scene itself or from closed forms of Bullet's integrator (semi-implicit Euler).
#include <btBulletDynamicsCommon.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <set>
#include <tuple>

#include "adapters/bullet/bullet_engine.h"
#include "adapters/bullet/bullet_shapes.h"
#include "common/scene_fixtures.h"
#include "engines/selftest_engine.h"
#include "pbd/io/mesh_loader.h"
#include "pbd/io/scene_loader.h"
#include "validation/run/simulation.h"

namespace pbdval::test {
namespace {

using pbd::JointType;
using pbd::Quaternion;
using pbd::Scene;

constexpr double kEps = 2.220446049250313e-16;

Scene emptyScene(double stepSize = 0.005, const Vector3& gravity = Vector3::Zero()) {
  Scene s;
  s.simulation.timeStepSize = Real(stepSize);
  s.simulation.gravitation = gravity;
  return s;
}

using Overrides = std::map<std::string, std::string>;

std::unique_ptr<BulletEngine> loaded(const Scene& scene, const Overrides& overrides = {},
                                     const std::string& method = "bullet.si") {
  auto engine = std::make_unique<BulletEngine>();
  EXPECT_TRUE(engine->unsupported(scene, testRegistry().resolve(method)).empty());
  engine->load(scene, testRegistry().resolve(method, overrides));
  return engine;
}

std::vector<State> trajectory(const Scene& scene, double duration, const std::string& method,
                              const Overrides& overrides = {}) {
  std::vector<State> samples;
  BulletEngine engine;
  RunCallbacks callbacks;
  callbacks.onSample = [&](const State& s) { samples.push_back(s); };
  const RunOutcome outcome = runSimulation(engine, scene, testRegistry().resolve(method, overrides),
                                           {duration, 0}, callbacks);
  EXPECT_EQ(outcome.status, RunStatus::Ok) << outcome.reason;
  return samples;
}

State readState(const SteppingEngine& engine) {
  State s;
  engine.read(s);
  return s;
}

Quaternion asymmetricRotation() {
  return Quaternion(pbd::AngleAxis(Real(0.7), Vector3(1, 2, 3).normalized()));
}

// --- Bodies ----------------------------------------------------------------------------------

// Bullet stores the inverse mass and inverse principal inertia; both must be the Scene's (not
// calculateLocalInertia's). Two divisions: within 2 ulp.
TEST(BulletBodies, MassAndPrincipalInertiaAreTheScenes) {
  Scene s = emptyScene();
  auto box = pbd::test::boxBody(1, Vector3(0.1, 0.2, 0.3), Vector3::Zero(), 1);
  box.massProperties.mass = 2.5;  // not the box's 0.006 kg: proves nothing is recomputed
  box.massProperties.principalInertia = Vector3(0.11, 0.23, 0.31);
  s.rigidBodies = {box, pbd::test::boxBody(2, Vector3(1, 1, 1), Vector3(3, 0, 0), 7, false)};
  const auto engine = loaded(s);
  const btRigidBody& body = engine->body(0);
  EXPECT_NEAR(1 / body.getInvMass(), 2.5, 2 * kEps * 2.5);
  const btVector3 inverse = body.getInvInertiaDiagLocal();
  for (int i = 0; i < 3; ++i)
    EXPECT_NEAR(1 / inverse[i], box.massProperties.principalInertia[i], 2 * kEps);
  // A static body is a mass-0 Bullet object even though the Scene gives it a mass.
  EXPECT_EQ(engine->body(1).getInvMass(), 0);
  EXPECT_TRUE(engine->body(1).isStaticObject());
}

// The body frame is the principal frame at the centre of mass; read() must give back the
// scene frame. An asymmetric scene rotation, principal rotation and centre-of-mass offset make
// any wrong order of composition or a missing inverse visible.
TEST(BulletBodies, SceneFrameRoundTripsThroughThePrincipalFrame) {
  Scene s = emptyScene();
  auto body = pbd::test::sphereBody(4, 0.2, Vector3(0.5, -1, 2), 1000);
  body.rotation = asymmetricRotation();
  body.massProperties.centerOfMass = Vector3(0.1, -0.2, 0.05);
  body.massProperties.principalRotation =
      Quaternion(pbd::AngleAxis(Real(1.1), Vector3(0.3, -0.5, 0.8).normalized()));
  body.velocity = Vector3(0.3, -0.1, 0.2);
  body.angularVelocity = Vector3(-0.4, 0.5, 0.9);
  s.rigidBodies = {body};
  const auto engine = loaded(s);
  const BodyState read = readState(*engine).bodies[0];
  EXPECT_EQ(read.id, 4);
  EXPECT_LE((read.position - body.initialCenterOfMass()).norm(), 8 * kEps);
  EXPECT_LE(read.rotation.angularDistance(body.rotation), 16 * kEps);
  EXPECT_LE((read.velocity - body.velocity).norm(), 4 * kEps);
  EXPECT_LE((read.angularVelocity - body.angularVelocity).norm(), 4 * kEps);
  // Bullet's own pose is the principal frame.
  const btTransform& pose = engine->body(0).getCenterOfMassTransform();
  const Quaternion principal = bullet::toEigen(pose.getRotation());
  EXPECT_LE(principal.angularDistance(body.initialPrincipalRotation()), 16 * kEps);
  // The sphere sits at the scene origin, not at the centre of mass: its bounding box is
  // centred on `translation`.
  btVector3 low, high;
  engine->body(0).getAabb(low, high);
  EXPECT_LE((bullet::toEigen((low + high) / 2) - body.translation).norm(), 1e-12);
}

// A torque-free body keeps its read-back scene rotation consistent with the integrated
// principal frame: after n steps of a spin about a principal axis, the rotation is exactly
// that spin (Bullet integrates a constant ω with the exponential map).
TEST(BulletBodies, SpinAboutAPrincipalAxisIsReadBackInTheSceneFrame) {
  Scene s = emptyScene(0.01);
  auto body = pbd::test::boxBody(1, Vector3(0.1, 0.2, 0.3), Vector3::Zero(), 1000);
  body.rotation = asymmetricRotation();
  const Vector3 axis = body.rotation * Vector3::UnitZ();  // a principal axis, in the world
  body.angularVelocity = 2 * axis;
  s.rigidBodies = {body};
  const auto engine = loaded(s);
  for (int i = 0; i < 50; ++i)
    engine->step();
  const BodyState read = readState(*engine).bodies[0];
  const Quaternion expected = Quaternion(pbd::AngleAxis(Real(2 * 0.5), axis)) * body.rotation;
  // 50 quaternion products and renormalisations: round-off only.
  EXPECT_LE(read.rotation.angularDistance(expected), 1e-12);
}

// --- Materials -------------------------------------------------------------------------------

Scene sphereOnGround(Real frictionA, Real restitutionA, Real frictionB, Real restitutionB) {
  Scene s = emptyScene(0.001, Vector3(0, -9.81, 0));
  auto ground = pbd::test::boxBody(0, Vector3(2, 0.2, 2), Vector3(0, -0.1, 0), 1, false);
  auto ball = pbd::test::sphereBody(1, 0.1, Vector3(0, 0.1, 0), 1000);
  ground.friction = frictionA;
  ground.restitution = restitutionA;
  ball.friction = frictionB;
  ball.restitution = restitutionB;
  s.rigidBodies = {ground, ball};
  return s;
}

/// The combined friction and restitution of every contact point in the world.
std::vector<std::pair<double, double>> contactMaterials(const btDiscreteDynamicsWorld& world) {
  std::vector<std::pair<double, double>> materials;
  const btDispatcher& dispatcher = *world.getDispatcher();
  for (int i = 0; i < dispatcher.getNumManifolds(); ++i) {
    const btPersistentManifold& m =
        *const_cast<btDispatcher&>(dispatcher).getManifoldByIndexInternal(i);
    for (int k = 0; k < m.getNumContacts(); ++k)
      materials.push_back(
          {m.getContactPoint(k).m_combinedFriction, m.getContactPoint(k).m_combinedRestitution});
  }
  return materials;
}

// The seed's rule (μ_a + μ_b, e_a e_b) differs from Bullet's (μ_a μ_b): the contact points
// must carry the Scene's values.
TEST(BulletMaterials, ContactPointsCarryTheScenesPairMaterial) {
  const Scene s = sphereOnGround(0.3, 0.5, 0.4, 0.6);
  const pbd::ContactMaterial expected = s.pairMaterial(0, 1);
  ASSERT_NEAR(expected.friction, 0.7, 1e-15);  // the seed's sum, not Bullet's 0.12
  const auto engine = loaded(s);
  engine->step();
  const auto points = contactMaterials(engine->world());
  ASSERT_FALSE(points.empty()) << "the sphere rests on the ground: there must be contacts";
  for (const auto& [friction, restitution] : points) {
    EXPECT_EQ(friction, expected.friction);
    EXPECT_EQ(restitution, expected.restitution);
  }
}

TEST(BulletMaterials, ExplicitContactPairOverridesTheRule) {
  Scene s = sphereOnGround(0.3, 0.5, 0.4, 0.6);
  s.simulation.contactCombineRule = pbd::ContactCombineRule::Max;
  pbd::ContactPairDesc pair;
  pair.body1 = 1;
  pair.body2 = 0;
  pair.hasFriction = true;
  pair.friction = Real(0.9);
  s.contactPairs = {pair};
  const auto engine = loaded(s);
  engine->step();
  const auto points = contactMaterials(engine->world());
  ASSERT_FALSE(points.empty());
  for (const auto& [friction, restitution] : points) {
    EXPECT_EQ(friction, 0.9);     // the explicit pair
    EXPECT_EQ(restitution, 0.6);  // the rule (max) where the pair gives no value
  }
}

// --- Joints: signs and semantics of every mapping -------------------------------------------

/// A static anchor (index 0) and a dynamic 1 kg cube (index 1) at `position`.
Scene twoBodies(const Vector3& position, const Vector3& gravity = Vector3::Zero()) {
  Scene s = emptyScene(0.005, gravity);
  s.rigidBodies.push_back(pbd::test::boxBody(0, Vector3(0.1, 0.1, 0.1), Vector3::Zero(), 1, false));
  s.rigidBodies.push_back(pbd::test::boxBody(1, Vector3(0.1, 0.1, 0.1), position, 1000));
  for (auto& b : s.rigidBodies)
    b.collision.type = pbd::CollisionObjectType::None;
  return s;
}

pbd::JointDesc joint(JointType type, const Vector3& axis) {
  pbd::JointDesc j = pbd::test::makeJointDesc(type, 0, 1);
  j.axis = axis;
  return j;
}

const Vector3 kAxis = Vector3(1, 2, -2).normalized();  // not aligned with any frame axis

// ω_B − ω_A = ω* a: the motor's target is body 1's spin relative to body 0, right-handed.
TEST(BulletJoints, VelocityMotorHingeSpinsBodyTwoPositivelyAboutTheAxis) {
  Scene s = twoBodies(Vector3(0.5, 0, 0));
  pbd::JointDesc j = joint(JointType::TargetVelocityMotorHinge, kAxis);
  j.position = Vector3(0.5, 0, 0);
  j.target.constant = 3;
  s.joints = {j};
  const auto engine = loaded(s);
  for (int i = 0; i < 10; ++i)
    engine->step();
  const Vector3 w = readState(*engine).bodies[1].angularVelocity;
  EXPECT_NEAR(w.dot(kAxis), 3, 1e-9);  // unlimited motor impulse: exact up to the solver's
  EXPECT_LE((w - w.dot(kAxis) * kAxis).norm(), 1e-9);  // convergence on one row
}

// s* > 0 moves body 1 along +axis relative to body 0, reached at the end of each step.
TEST(BulletJoints, PositionMotorSliderFollowsItsSetPoint) {
  Scene s = twoBodies(Vector3(0.3, 0, 0));
  pbd::JointDesc j = joint(JointType::TargetPositionMotorSlider, kAxis);
  j.target.times = {0, 1};
  j.target.values = {0, 0.5};  // a ramp of 0.5 m/s
  s.joints = {j};
  const auto engine = loaded(s);
  const Vector3 start = s.rigidBodies[1].initialCenterOfMass();
  for (int n = 1; n <= 100; ++n) {
    engine->step();
    const Vector3 offset = readState(*engine).bodies[1].position - start;
    ASSERT_NEAR(offset.dot(kAxis), 0.5 * n * 0.005, 1e-9) << "step " << n;
    ASSERT_LE((offset - offset.dot(kAxis) * kAxis).norm(), 1e-9) << "step " << n;
  }
}

TEST(BulletJoints, VelocityMotorSliderMovesBodyTwoAlongPlusAxis) {
  Scene s = twoBodies(Vector3(0.3, 0, 0));
  pbd::JointDesc j = joint(JointType::TargetVelocityMotorSlider, kAxis);
  j.target.constant = 0.4;
  s.joints = {j};
  const auto engine = loaded(s);
  for (int i = 0; i < 10; ++i)
    engine->step();
  const Vector3 v = readState(*engine).bodies[1].velocity;
  EXPECT_NEAR(v.dot(kAxis), 0.4, 1e-9);
  EXPECT_LE((v - v.dot(kAxis) * kAxis).norm(), 1e-9);
}

// θ = θ*(t) at the end of every step: the hinge angle of body 1 relative to body 0.
TEST(BulletJoints, AngleMotorHingeReachesItsSetPointEveryStep) {
  Scene s = twoBodies(Vector3(0.5, 0, 0));
  pbd::JointDesc j = joint(JointType::TargetAngleMotorHinge, kAxis);
  j.position = Vector3(0.5, 0, 0);
  j.target.times = {0, 1};
  j.target.values = {0, 1.5};
  s.joints = {j};
  const auto engine = loaded(s);
  const Quaternion start = readState(*engine).bodies[1].rotation;
  for (int n = 1; n <= 100; ++n) {
    engine->step();
    const Quaternion relative = readState(*engine).bodies[1].rotation * start.conjugate();
    const Quaternion expected(pbd::AngleAxis(Real(1.5 * n * 0.005), kAxis));
    ASSERT_LE(relative.angularDistance(expected), 1e-9) << "step " << n;
  }
}

// Symplectic Euler on x″ = −ω² x from x₀ = 0, v₀: x_n = h v₀ sin(nθ)/sin θ with
// cos θ = 1 − (ωh)²/2 (Bullet applies the spring impulse k x_n h, then x_{n+1} = x_n + h v).
void expectDiscreteOscillation(const std::vector<double>& x, double omega, double h, double v0) {
  const double theta = std::acos(1 - omega * omega * h * h / 2);
  for (std::size_t n = 0; n < x.size(); ++n)
    ASSERT_NEAR(x[n], h * v0 * std::sin(double(n) * theta) / std::sin(theta), 1e-9) << "step " << n;
}

TEST(BulletJoints, DamperIsAnUndampedAxialSpringAtTheInitialOffset) {
  Scene s = twoBodies(Vector3(0.3, 0, 0));
  auto& bob = s.rigidBodies[1];
  bob.velocity = 0.2 * kAxis;
  pbd::JointDesc j = joint(JointType::Damper, kAxis);
  j.stiffness = 40;  // ω = √(k/m) = √40 rad/s for the 1 kg cube
  s.joints = {j};
  const auto engine = loaded(s);
  std::vector<double> x;
  for (int n = 0; n <= 400; ++n) {
    if (n > 0) engine->step();
    x.push_back((readState(*engine).bodies[1].position - bob.initialCenterOfMass()).dot(kAxis));
  }
  expectDiscreteOscillation(x, std::sqrt(40 / double(bob.massProperties.mass)), 0.005, 0.2);
}

TEST(BulletJoints, RigidBodySpringIsAForceAlongTheConnectorsLine) {
  Scene s = twoBodies(Vector3(0.8, 0, 0));
  auto& bob = s.rigidBodies[1];
  bob.velocity = Vector3(0.1, 0, 0);
  pbd::JointDesc j = pbd::test::makeJointDesc(JointType::RigidBodySpring, 0, 1);
  j.position1 = Vector3::Zero();
  j.position2 = Vector3(0.8, 0, 0);  // at the centre of mass: no torque, motion along x
  j.stiffness = 25;
  s.joints = {j};
  const auto engine = loaded(s);
  std::vector<double> x;
  for (int n = 0; n <= 400; ++n) {
    if (n > 0) engine->step();
    x.push_back(double(readState(*engine).bodies[1].position.x()) - 0.8);
  }
  expectDiscreteOscillation(x, std::sqrt(25 / double(bob.massProperties.mass)), 0.005, 0.1);
}

// The universal joint keeps axis1 (in body 0) ⟂ axis2 (in body 1) and leaves both rotations
// free: a spin about axis2 survives, and with gravity the body also swings about axis1.
// Solved by the direct MLCP solver, so that the error measures the mapping, not the
// convergence of 10 Gauss–Seidel sweeps (see the pendulum tests below).
TEST(BulletJoints, UniversalJointKeepsTheAxesPerpendicularAndBothRotationsFree) {
  Scene s = twoBodies(Vector3(0.4, -0.3, 0), Vector3(0, -9.81, 0));
  pbd::JointDesc j = pbd::test::makeJointDesc(JointType::Universal, 0, 1);
  j.position = Vector3(0, 0, 0);
  j.axis1 = Vector3::UnitZ();
  j.axis2 = Vector3(0.8, -0.6, 0);  // along the arm
  s.joints = {j};
  s.rigidBodies[1].angularVelocity = 4 * j.axis2;
  const auto engine = loaded(s, {}, "bullet.dantzig");
  double worstDot = 0, lowest = 0;
  const Quaternion start = readState(*engine).bodies[1].rotation;
  for (int n = 0; n < 200; ++n) {
    engine->step();
    const BodyState b = readState(*engine).bodies[1];
    const Vector3 axis2 = b.rotation * start.conjugate() * j.axis2;
    worstDot = std::max(worstDot, std::abs(double(axis2.dot(j.axis1))));
    lowest = std::min(lowest, double(b.position.y()));
  }
  // Baumgarte (ERP 0.2) keeps the drift at the order of h² |ω|² / erp = 2.5e-5 · 16 / 0.2.
  EXPECT_LE(worstDot, 2e-3);
  const BodyState end = readState(*engine).bodies[1];
  const Vector3 arm = end.position.normalized();
  EXPECT_GT(std::abs(end.angularVelocity.dot(arm)), 1.0) << "the spin about axis2 was locked";
  // From 53° off the vertical, an arm of 0.5 m swinging about axis1 passes y = −0.5.
  EXPECT_LT(lowest, -0.45) << "the arm did not swing about axis1";
}

// Ball on line: the anchor of body 1 stays on the line through `position` along `axis`
// (direct solver, as above). A horizontal line (not along a frame axis), the body hanging 0.3 m
// below it, moving along the line at 0.5 m/s and swinging across it at 0.3 m/s.
TEST(BulletJoints, BallOnLineKeepsTheAnchorOnTheLine) {
  Scene s = twoBodies(Vector3(0, -0.3, 0), Vector3(0, -9.81, 0));
  const Vector3 axis = Vector3(1, 0, 1).normalized();
  pbd::JointDesc j = joint(JointType::BallOnLine, axis);
  j.position = Vector3(0, 0, 0);
  s.joints = {j};
  s.rigidBodies[1].velocity = 0.5 * axis + 0.3 * Vector3(1, 0, -1).normalized();
  const auto engine = loaded(s, {}, "bullet.dantzig");
  const Vector3 anchorInBody = j.position - s.rigidBodies[1].initialCenterOfMass();
  double worst = 0;
  BodyState b;
  for (int n = 0; n < 200; ++n) {
    engine->step();
    b = readState(*engine).bodies[1];
    const Vector3 anchor = b.position + b.rotation * anchorInBody;
    worst = std::max(worst, double((anchor - anchor.dot(axis) * axis).norm()));
  }
  // Converged pendulums drift by 0.27 h² a_max (BulletPendulum below); a_max ≈ g + v²/L = 10.1
  // m/s² here, so 10 h² a_max = 2.5e-3 m is the parity suite's default bound.
  EXPECT_LE(worst, 2.5e-3);
  // Free along the line: the anchor keeps its 0.5 m/s, 0.5 m in 1 s.
  EXPECT_NEAR((b.position + b.rotation * anchorInBody).dot(axis), 0.5, 1e-3);
}

// --- Pendulum and rebound with converged solves ----------------------------------------------

// The parity suite's pendulum (test_parity.cpp): a 1 kg, 0.1 m cube 1 m below a static pivot,
// released at 20°. Exact period T = 4 K(sin 10°) √(I_p / (m g L)).
Scene pendulum(JointType type) {
  Scene s = emptyScene(0.005, Vector3(0, -9.81, 0));
  const Vector3 pivot(0, 2, 0);
  const double theta0 = 20 * M_PI / 180;
  s.rigidBodies.push_back(pbd::test::boxBody(0, Vector3(0.1, 0.1, 0.1), pivot, 1, false));
  s.rigidBodies.push_back(pbd::test::boxBody(
      1, Vector3(0.1, 0.1, 0.1), pivot + Vector3(std::sin(theta0), -std::cos(theta0), 0), 1000));
  pbd::JointDesc j = joint(type, Vector3::UnitZ());
  j.position = pivot;
  j.axis1 = Vector3::UnitZ();
  j.axis2 = Vector3::UnitX();
  s.joints = {j};
  return s;
}

struct SwingResult {
  double period = 0;
  double jointError = 0;
};

SwingResult swing(const std::vector<State>& samples, const Scene& s) {
  const Vector3 pivot(0, 2, 0);
  const Vector3 anchorInBob = pivot - s.rigidBodies[1].initialCenterOfMass();
  std::vector<double> crossings;
  double previous = 0, previousTime = 0, worst = 0;
  for (const State& st : samples) {
    const Vector3 d = st.bodies[1].position - pivot;
    const double angle = std::atan2(d.x(), -d.y());
    if (st.time > 0 && previous < 0 && angle >= 0)
      crossings.push_back(previousTime + (st.time - previousTime) * -previous / (angle - previous));
    previous = angle;
    previousTime = st.time;
    worst = std::max(
        worst,
        double((st.bodies[1].position + st.bodies[1].rotation * anchorInBob - pivot).norm()));
  }
  return {(crossings.back() - crossings.front()) / double(crossings.size() - 1), worst};
}

double exactPeriod(const Scene& s) {
  const double k = std::sin(10 * M_PI / 180);
  double a = 1, b = std::sqrt(1 - k * k);  // AGM: K(k) = π / (2 AGM(1, √(1 − k²)))
  for (int i = 0; i < 30; ++i)
    std::tie(a, b) = std::make_pair((a + b) / 2, std::sqrt(a * b));
  const auto& bob = s.rigidBodies[1].massProperties;
  const double inertia = double(bob.principalInertia.z() + bob.mass);  // about the pivot, L = 1
  return 4 * (M_PI / (2 * a)) * std::sqrt(inertia / (double(bob.mass) * 9.81));
}

// With the point rows solved to convergence, Bullet's ball and universal pendulums meet the
// parity suite's default bounds (period within ω₀h, joint error within 10 h² a_max): the set-up
// is right, and the larger errors of bullet.si's 10 sweeps are the solver's (parity_profiles.cpp).
TEST(BulletPendulum, ConvergedSolvesMeetTheDefaultParityBounds) {
  const double h = 0.005, omega0 = 3.1, aMax = 9.81 * (1 + 2 * (1 - std::cos(20 * M_PI / 180)));
  for (JointType type : {JointType::Ball, JointType::Universal, JointType::Hinge})
    for (const auto& [method, overrides] : std::vector<std::pair<std::string, Overrides>>{
             {"bullet.dantzig", {}}, {"bullet.si", {{"iterations", "1000"}}}}) {
      const Scene s = pendulum(type);
      const SwingResult r = swing(trajectory(s, 8, method, overrides), s);
      const double expected = exactPeriod(s);
      EXPECT_LE(std::abs(r.period - expected) / expected, omega0 * h)
          << pbd::jointTypeName(type) << " " << method << ": T = " << r.period;
      EXPECT_LE(r.jointError, 10 * h * h * aMax) << pbd::jointTypeName(type) << " " << method;
    }
}

// --- Unsupported features, cases, settings, files --------------------------------------------

TEST(BulletEngineReport, UnsupportedFeaturesAreNamed) {
  Scene s = twoBodies(Vector3(1, 0, 0));
  s.rigidBodies.push_back(pbd::test::sphereBody(2, 0.5, Vector3(3, 0, 0), 1));
  s.rigidBodies.back().collision.type = pbd::CollisionObjectType::HollowSphere;
  s.rigidBodies.back().jsonPath = "RigidBodies[2]";
  pbd::JointDesc distance = pbd::test::makeJointDesc(JointType::Distance, 0, 1);
  pbd::JointDesc particle = pbd::test::makeJointDesc(JointType::RigidBodyParticleBall, 0, -1);
  s.joints = {distance, particle};
  pbd::TriangleModelDesc cloth;
  cloth.jsonPath = "TriangleModels[0]";
  s.triangleModels = {cloth};
  const auto missing = BulletEngine().unsupported(s, testRegistry().resolve("bullet.si"));
  auto names = [&](const std::string& path, const std::string& what) {
    for (const std::string& m : missing)
      if (m.rfind(path + ": ", 0) == 0 && m.find(what) != std::string::npos) return true;
    return false;
  };
  EXPECT_EQ(missing.size(), 4u);
  EXPECT_TRUE(names("DistanceJoints[0]", "no distance constraint"));
  EXPECT_TRUE(names("RigidBodyParticleBallJoints[0]", "Bullet rigid bodies have no particles"));
  EXPECT_TRUE(names("RigidBodies[2]", "hollow sphere"));
  EXPECT_TRUE(names("TriangleModels[0]", "rigid bodies only"));  // once, not per cloth feature
}

std::filesystem::path casesDirectory() {
  return std::filesystem::path(PBDVAL_SOURCE_DIR) / "cases";
}

// Every shipped case runs in Bullet, or is reported unsupported with the names of exactly the
// features Bullet lacks.
TEST(BulletEngineReport, EveryCaseRunsOrNamesWhatIsUnsupported) {
  const std::map<std::string, std::set<std::string>> expectedUnsupported = {
      {"joint_distance.json", {"DistanceJoints[0]"}},
      {"cloth_hanging.json", {"TriangleModels[0]"}},
      {"cloth_on_sphere.json", {"TriangleModels[0]"}},
      {"tet_bar.json", {"TetModels[0]"}},
      {"tet_cantilever.json", {"TetModels[0]"}},
      {"solid_collision.json", {"TetModels[0]", "TetModels[1]"}},
      {"fluid_dam_break.json", {"FluidModels[0]"}},
      {"rod_helix.json", {"LineModels[0]"}},
      {"joint_rigid_body_particle_ball.json",
       {"TriangleModels[0]", "RigidBodyParticleBallJoints[0]"}},
      {"stiff_rod_cantilever.json", {"CosseratJoints[0]", "CosseratJoints[9]"}},
      {"stiff_rod_helix.json", {"CosseratJoints[0]", "CosseratJoints[35]"}},
  };
  int cases = 0;
  for (const auto& entry : std::filesystem::directory_iterator(casesDirectory())) {
    if (entry.path().extension() != ".json") continue;
    ++cases;
    const std::string file = entry.path().filename().string();
    const Scene scene = pbd::loadScene(entry.path().string()).scene;
    BulletEngine engine;
    const RunOutcome outcome =
        runSimulation(engine, scene, testRegistry().resolve("bullet.si"), {1.0, 0}, {});
    const auto expected = expectedUnsupported.find(file);
    if (expected == expectedUnsupported.end()) {
      EXPECT_EQ(outcome.status, RunStatus::Ok) << file << ": " << outcome.reason;
      continue;
    }
    EXPECT_EQ(outcome.status, RunStatus::Unsupported) << file;
    for (const std::string& name : expected->second)
      EXPECT_NE(outcome.reason.find(name + ": "), std::string::npos)
          << file << " should name " << name << ": " << outcome.reason;
  }
  EXPECT_GE(cases, 16);
}

TEST(BulletEngineReport, EffectiveSettingsRecordTheParitySettings) {
  Scene s = sphereOnGround(0.3, 0.5, 0.4, 0.6);
  s.simulation.gravitation = Vector3(0.5, -9.5, 0.25);
  const auto engine = loaded(s, {{"iterations", "25"}, {"erp", "0.4"}});
  const auto settings = engine->effectiveSettings();
  auto value = [&](const std::string& key) {
    const auto it = settings.find(key);
    return it == settings.end() ? std::string("<missing>") : it->second;
  };
  EXPECT_EQ(value("precision"), "double");
  EXPECT_EQ(value("solver"), "si");
  EXPECT_EQ(value("iterations"), "25");
  EXPECT_EQ(value("erp"), "0.4");  // the shortest text that reads back to the double 0.4
  EXPECT_EQ(value("restitutionVelocityThreshold"), "0");
  EXPECT_EQ(value("margin"), "0.001");
  EXPECT_EQ(value("contactProcessingThreshold"), "0");
  EXPECT_EQ(value("splitImpulsePenetrationThreshold"), "0");
  EXPECT_EQ(value("gravity"), "0.5 -9.5 0.25");
  EXPECT_EQ(value("timeStepSize"), "0.001");
  EXPECT_EQ(value("sleeping"), "off (DISABLE_DEACTIVATION)");
  EXPECT_EQ(value("damping"), "0");
  EXPECT_EQ(value("shapes"), "box x1, sphere x1");
  EXPECT_NE(value("gyroscopic").find("IMPLICIT_BODY"), std::string::npos);
  // The world really uses them.
  const btContactSolverInfo& info = engine->world().getSolverInfo();
  EXPECT_EQ(info.m_numIterations, 25);
  EXPECT_EQ(info.m_restitutionVelocityThreshold, 0);
  EXPECT_EQ(engine->world().getGravity(), btVector3(0.5, -9.5, 0.25));
}

TEST(BulletEngineReport, BadParametersAreRejectedByName) {
  BulletEngine engine;
  const Scene s = twoBodies(Vector3(1, 0, 0));
  EXPECT_THROW(engine.load(s, testRegistry().resolve("bullet.si", {{"iterations", "2.5"}})),
               std::invalid_argument);
  try {
    engine.load(s, testRegistry().resolve("bullet.nncg", {{"erp", "abc"}}));
    FAIL() << "erp = abc was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("erp"), std::string::npos) << e.what();
  }
}

// Runs a contact scene and a joint scene in every Bullet method from an empty working
// directory; nothing may appear in it.
TEST(BulletEngineReport, NoFilesAreWritten) {
  const std::filesystem::path previous = std::filesystem::current_path();
  const std::filesystem::path scratch =
      std::filesystem::temp_directory_path() / ("pbdval_bullet_files_" + std::to_string(getpid()));
  std::filesystem::create_directories(scratch);
  std::filesystem::current_path(scratch);
  Scene joints = twoBodies(Vector3(0.5, 0, 0), Vector3(0, -9.81, 0));
  pbd::JointDesc j = joint(JointType::Hinge, Vector3::UnitZ());
  j.position = Vector3::Zero();
  joints.joints = {j};
  for (const char* method : {"bullet.si", "bullet.dantzig", "bullet.nncg"})
    for (const Scene& scene : {sphereOnGround(0.3, 0.5, 0.4, 0.6), joints}) {
      BulletEngine engine;
      const RunOutcome outcome =
          runSimulation(engine, scene, testRegistry().resolve(method), {0.2, 0}, {});
      EXPECT_EQ(outcome.status, RunStatus::Ok) << method << ": " << outcome.reason;
    }
  const bool empty = std::filesystem::is_empty(scratch);
  std::filesystem::current_path(previous);
  std::filesystem::remove_all(scratch);
  EXPECT_TRUE(empty);
}

// --- Shapes ----------------------------------------------------------------------------------

TEST(BulletShapes, ConvexityTestSeparatesHullsFromTriangleMeshes) {
  pbd::TriangleMesh tetrahedron;
  tetrahedron.vertices = {Vector3(0, 0, 0), Vector3(1, 0, 0), Vector3(0, 1, 0), Vector3(0, 0, 1)};
  tetrahedron.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  EXPECT_TRUE(bullet::isConvex(tetrahedron));
  pbd::TriangleMesh dented = tetrahedron;
  dented.vertices[3] = Vector3(0.2, 0.2, -0.5);  // pushed through the opposite face
  EXPECT_FALSE(bullet::isConvex(dented));
}

// A box keeps its outer size with the margin inside: resting on the ground, its centre sits
// at half its height (the box–box detector works on the full extents).
TEST(BulletShapes, BoxRestsAtItsTrueHeight) {
  Scene s = emptyScene(0.002, Vector3(0, -9.81, 0));
  s.rigidBodies.push_back(pbd::test::boxBody(0, Vector3(2, 0.2, 2), Vector3(0, -0.1, 0), 1, false));
  s.rigidBodies.push_back(pbd::test::boxBody(1, Vector3(0.2, 0.3, 0.2), Vector3(0, 0.16, 0), 500));
  const auto engine = loaded(s);
  for (int i = 0; i < 500; ++i)
    engine->step();
  // Resting contacts settle linearSlop (1e-5 m) deep; within a step gravity moves the box by
  // g h² = 3.9e-5 m before the contact stops it.
  EXPECT_NEAR(readState(*engine).bodies[1].position.y(), 0.15 - 1e-5, 3.9e-5);
}

/// A dynamic body of collisionObjectType 5 (SDF) whose mesh is `mesh` scaled by `scale`, at rest
/// `height` above a static ground whose top is y = 0.
Scene meshBodyOnGround(pbd::TriangleMesh mesh, const Vector3& scale, Real height) {
  for (Vector3& v : mesh.vertices)
    v = v.cwiseProduct(scale);
  Scene s = emptyScene(0.002, Vector3(0, -9.81, 0));
  s.rigidBodies.push_back(pbd::test::boxBody(0, Vector3(2, 0.2, 2), Vector3(0, -0.1, 0), 1, false));
  auto body = pbd::test::boxBody(1, scale, Vector3(0, height, 0), 500);
  body.collision.type = pbd::CollisionObjectType::SignedDistanceField;
  body.mesh = std::make_shared<const pbd::TriangleMesh>(std::move(mesh));
  s.rigidBodies.push_back(body);
  return s;
}

// A convex mesh becomes a hull shrunk by the margin, so hull ⊕ margin has the mesh's faces: it
// rests at its true height (as the box above), not a margin (1 mm) higher.
TEST(BulletShapes, ConvexMeshIsAHullWithExactFaces) {
  const pbd::TriangleMesh cube = pbd::loadObj((casesDirectory() / "models" / "cube.obj").string());
  const Scene s = meshBodyOnGround(cube, Vector3(0.2, 0.3, 0.2), Real(0.16));
  const auto engine = loaded(s);
  EXPECT_EQ(engine->effectiveSettings().at("shapes"), "box x1, convex hull x1");
  for (int i = 0; i < 500; ++i)
    engine->step();
  EXPECT_NEAR(readState(*engine).bodies[1].position.y(), 0.15 - 1e-5, 3.9e-5);  // as above
}

// A non-convex mesh becomes a GImpact triangle mesh (dynamic) and collides: a cube with one
// corner pushed in still lands on the ground and comes to rest.
TEST(BulletShapes, NonConvexMeshIsAGImpactTriangleMesh) {
  pbd::TriangleMesh dented = pbd::loadObj((casesDirectory() / "models" / "cube.obj").string());
  dented.vertices[0] *= Real(0.2);  // a corner pulled towards the centre: a concave dent
  ASSERT_FALSE(bullet::isConvex(dented));
  const Scene s = meshBodyOnGround(dented, Vector3(0.2, 0.2, 0.2), Real(0.2));
  const auto engine = loaded(s);
  EXPECT_EQ(engine->effectiveSettings().at("shapes"), "box x1, triangle mesh (GImpact) x1");
  for (int i = 0; i < 1000; ++i)
    engine->step();
  const BodyState b = readState(*engine).bodies[1];
  EXPECT_LT(b.velocity.norm(), 0.05) << "it should have landed";
  EXPECT_GT(b.position.y(), 0.05) << "it fell through the ground";
}

// A hollow box is six walls 2t thick centred on its faces: a sphere dropped inside rests on the
// inner floor, y = −b + t + r.
TEST(BulletShapes, HollowBoxHoldsASphereOnItsInnerFloor) {
  Scene s = emptyScene(0.002, Vector3(0, -9.81, 0));
  auto container = pbd::test::boxBody(0, Vector3(1, 1, 1), Vector3::Zero(), 1, false);
  container.collision.type = pbd::CollisionObjectType::HollowBox;
  container.collision.thicknessSDF = Real(0.05);
  s.rigidBodies = {container, pbd::test::sphereBody(1, 0.1, Vector3(0.1, 0, -0.2), 1000)};
  const auto engine = loaded(s);
  EXPECT_EQ(engine->effectiveSettings().at("shapes"), "hollow box (6 wall boxes) x1, sphere x1");
  for (int i = 0; i < 1000; ++i)
    engine->step();
  EXPECT_NEAR(readState(*engine).bodies[1].position.y(), -0.5 + 0.05 + 0.1 - 1e-5, 3.9e-5);
}

}  // namespace
}  // namespace pbdval::test
