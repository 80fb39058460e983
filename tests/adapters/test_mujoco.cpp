// MuJoCo adapter: how the Scene maps onto MuJoCo (frames, mass properties, shapes, materials,
// the kinematic tree) and how MuJoCo's failures surface. The generic physics checks are in
// test_parity.cpp; expected values here come from the Scene itself or from closed forms.
#include <gtest/gtest.h>
#include <mujoco/mujoco.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <functional>

#include "adapters/mujoco/contact_softness.h"
#include "adapters/mujoco/kinematic_tree.h"
#include "adapters/mujoco/mujoco_engine.h"
#include "adapters/mujoco/mujoco_errors.h"
#include "common/scene_fixtures.h"
#include "engines/selftest_engine.h"
#include "pbd/io/scene_loader.h"
#include "validation/run/case_spec.h"
#include "validation/run/simulation.h"

namespace pbdval::test {
namespace {

using pbd::AngleAxis;
using pbd::JointType;
using pbd::Scene;

constexpr double kG = 9.81;
constexpr double kRoundOff = 1e-12;  // a few hundred ε on O(1) values after a few operations

Scene emptyScene(double stepSize = 0.005, const Vector3& gravity = Vector3(0, -kG, 0)) {
  Scene s;
  s.simulation.timeStepSize = Real(stepSize);
  s.simulation.gravitation = gravity;
  return s;
}

Method method(const std::string& name = "mujoco.euler",
              const std::map<std::string, std::string>& overrides = {}) {
  return testRegistry().resolve(name, overrides);
}

/// Loads `scene` and steps it `steps` times; returns the state after each step (t = 0 first).
std::vector<State> simulate(MujocoEngine& engine, const Scene& scene, int steps,
                            const Method& m = method()) {
  engine.load(scene, m);
  std::vector<State> states(1);
  engine.read(states[0]);
  for (int i = 0; i < steps; ++i) {
    engine.step();
    states.emplace_back();
    engine.read(states.back());
  }
  return states;
}

/// Joint tests: no collision shapes (the seed lets jointed bodies collide, and these overlap).
void withoutCollisions(Scene& s) {
  for (pbd::RigidBodyDesc& b : s.rigidBodies)
    b.collision.type = pbd::CollisionObjectType::None;
}

double angleBetween(const Quaternion& a, const Quaternion& b) {
  return a.angularDistance(b);
}

/// A body with a principal frame that differs from its scene frame in both position and axes.
pbd::RigidBodyDesc asymmetricBody(int id, const Vector3& translation, const Quaternion& rotation) {
  pbd::RigidBodyDesc b =
      pbd::test::boxBody(id, Vector3(0.1, 0.2, 0.3), translation, 500, true, rotation);
  b.massProperties.mass = 3;
  b.massProperties.principalInertia = Vector3(1, 2, 2.5);
  b.massProperties.centerOfMass = Vector3(0.1, -0.05, 0.02);
  b.massProperties.principalRotation =
      Quaternion(AngleAxis(0.4, Vector3(0.3, -1, 0.5).normalized()));
  return b;
}

// --- Methods -----------------------------------------------------------------------------------

TEST(MujocoMethods, ThreeIntegratorsWithSolverAndContactParameters) {
  EXPECT_EQ(testRegistry().defaultMethod("mujoco"), "mujoco.euler");
  for (const char* name : {"mujoco.euler", "mujoco.rk4", "mujoco.implicit"}) {
    const Method m = method(name);
    EXPECT_EQ(m.values.at("solver").text(), "Newton") << name;
    EXPECT_EQ(m.values.at("iterations").text(), "100") << name;
    EXPECT_EQ(m.values.at("cone").text(), "elliptic") << name;
    EXPECT_EQ(m.values.at("contactTimeconst").text(), "4h") << name;
  }
  EXPECT_THROW(testRegistry().resolve("mujoco.euler", {{"substeps", "2"}}), std::invalid_argument);
}

TEST(MujocoMethods, SettingsResolveStepMultiplesAndRejectBadValues) {
  Scene s = emptyScene(0.002);
  const auto settings = mujoco::mujocoSettingsFor(s, method("mujoco.rk4", {{"solver", "PGS"}}));
  EXPECT_EQ(settings.integrator, "RK4");
  EXPECT_EQ(settings.solver, "PGS");
  EXPECT_DOUBLE_EQ(settings.contactTimeConstant, 4 * 0.002);
  EXPECT_DOUBLE_EQ(settings.equalitySolref[0], 2 * 0.002);
  // Below 2h MuJoCo's refsafe would silently change the time constant: rejected instead.
  EXPECT_THROW(mujoco::mujocoSettingsFor(s, method("mujoco.euler", {{"contactTimeconst", "1h"}})),
               std::invalid_argument);
  EXPECT_THROW(mujoco::mujocoSettingsFor(s, method("mujoco.euler", {{"cone", "round"}})),
               std::invalid_argument);
  EXPECT_THROW(mujoco::mujocoSettingsFor(s, method("mujoco.euler", {{"solimpMidpoint", "1"}})),
               std::invalid_argument);
  // The same rule for a time constant given in seconds, checked once the step is known:
  // 0.003 s is 1.5 steps of 2 ms.
  EXPECT_THROW(
      mujoco::mujocoSettingsFor(s, method("mujoco.euler", {{"contactTimeconst", "0.003"}})),
      std::invalid_argument);
  EXPECT_DOUBLE_EQ(
      mujoco::mujocoSettingsFor(s, method("mujoco.euler", {{"contactTimeconst", "0.004"}}))
          .contactTimeConstant,
      0.004);
}

// --- Bodies and frames -----------------------------------------------------------------------

TEST(MujocoModel, MassAndInertiaAreTheScenesNotTheGeoms) {
  Scene s = emptyScene();
  s.rigidBodies.push_back(asymmetricBody(4, Vector3(0, 1, 0), Quaternion::Identity()));
  MujocoEngine engine;
  engine.load(s, method());
  const mjModel* m = engine.model();
  const int id = engine.bodyId(0);
  EXPECT_EQ(m->body_mass[id], 3);  // the box's geometry would give 500 · 0.006 = 3 kg too,
  EXPECT_EQ(m->body_inertia[3 * id + 0], 1);  // but never these moments
  EXPECT_EQ(m->body_inertia[3 * id + 1], 2);
  EXPECT_EQ(m->body_inertia[3 * id + 2], 2.5);
  for (int k = 0; k < 3; ++k)
    EXPECT_EQ(m->body_ipos[3 * id + k], 0);
  EXPECT_EQ(m->body_iquat[4 * id], 1);
}

TEST(MujocoModel, ReadBackUndoesThePrincipalFrame) {
  Scene s = emptyScene(0.005, Vector3::Zero());
  const Quaternion rotation(AngleAxis(0.7, Vector3(1, 2, 3).normalized()));
  pbd::RigidBodyDesc b = asymmetricBody(4, Vector3(0.3, 1, -0.2), rotation);
  const Quaternion principal = b.initialPrincipalRotation();
  const Vector3 spinAxis = principal * Vector3::UnitY();  // a principal axis: ω stays constant
  b.velocity = Vector3(0.5, -1, 2);
  b.angularVelocity = 3 * spinAxis;
  s.rigidBodies.push_back(b);
  MujocoEngine engine;
  const std::vector<State> states = simulate(engine, s, 200);
  const BodyState& first = states.front().bodies[0];
  EXPECT_EQ(first.id, 4);
  EXPECT_LE((first.position - b.initialCenterOfMass()).norm(), kRoundOff);
  EXPECT_LE(angleBetween(first.rotation, rotation), kRoundOff);
  EXPECT_LE((first.velocity - b.velocity).norm(), kRoundOff);
  EXPECT_LE((first.angularVelocity - b.angularVelocity).norm(), kRoundOff);
  // Torque-free spin about a principal axis: ω constant (in the world), the scene frame turned
  // about it by ω t; the centre of mass moves uniformly.
  const State& last = states.back();
  const double t = last.time;
  EXPECT_NEAR(t, 1.0, 1e-12);
  EXPECT_LE((last.bodies[0].angularVelocity - b.angularVelocity).norm(), 1e-9);
  EXPECT_LE((last.bodies[0].position - (b.initialCenterOfMass() + t * b.velocity)).norm(), 1e-9);
  const Quaternion expected = Quaternion(AngleAxis(3 * t, spinAxis)) * rotation;
  EXPECT_LE(angleBetween(last.bodies[0].rotation, expected), 1e-9);
}

TEST(MujocoModel, StaticBodiesReadBackTheirScenePose) {
  Scene s = emptyScene();
  const Quaternion rotation(AngleAxis(0.3, Vector3(0, 0, 1)));
  s.rigidBodies.push_back(asymmetricBody(2, Vector3(1, 2, 3), rotation));
  s.rigidBodies.back().isDynamic = false;
  MujocoEngine engine;
  const std::vector<State> states = simulate(engine, s, 10);
  for (const State& st : {states.front(), states.back()}) {
    EXPECT_LE((st.bodies[0].position - s.rigidBodies[0].initialCenterOfMass()).norm(), kRoundOff);
    EXPECT_LE(angleBetween(st.bodies[0].rotation, rotation), kRoundOff);
    EXPECT_EQ(st.bodies[0].velocity.norm(), 0);
  }
}

TEST(MujocoModel, CylinderAxisIsTheScenesY) {
  Scene s = emptyScene();
  pbd::RigidBodyDesc c = pbd::test::boxBody(0, Vector3(0.2, 0.6, 0.2), Vector3(0, 1, 0), 100, true,
                                            Quaternion(AngleAxis(0.3, Vector3::UnitZ())));
  c.collision.type = pbd::CollisionObjectType::Cylinder;
  c.collision.scale = Vector3(0.1, 0.6, 1);
  c.massProperties = pbd::toPrincipal(pbd::cylinderMoments(0.1, 0.6, 100));
  s.rigidBodies.push_back(c);
  MujocoEngine engine;
  engine.load(s, method());
  const mjModel* m = engine.model();
  ASSERT_EQ(m->ngeom, 1);
  EXPECT_EQ(m->geom_type[0], mjGEOM_CYLINDER);
  EXPECT_DOUBLE_EQ(m->geom_size[0], 0.1);         // radius
  EXPECT_DOUBLE_EQ(m->geom_size[1], 0.3);         // half height
  const mjtNum* xmat = engine.data()->geom_xmat;  // row-major; column 2 is the geom's z axis
  const Vector3 mujocoAxis(xmat[2], xmat[5], xmat[8]);
  EXPECT_LE((mujocoAxis - c.rotation * Vector3::UnitY()).norm(), kRoundOff);
}

/// A closed box mesh over [lo, hi] (counter-clockwise seen from outside).
pbd::TriangleMesh boxMesh(const Vector3& lo, const Vector3& hi) {
  pbd::TriangleMesh mesh;
  for (int i = 0; i < 8; ++i)
    mesh.vertices.emplace_back(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(),
                               i & 4 ? hi.z() : lo.z());
  mesh.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                    {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return mesh;
}

// MuJoCo re-centres a mesh on its own centroid and principal axes and moves the geom frame to
// compensate; the hull must still sit where the Scene puts the body's mesh.
TEST(MujocoModel, AMeshHullSitsWhereTheSceneMeshIs) {
  Scene s = emptyScene();
  pbd::RigidBodyDesc b =
      pbd::test::boxBody(0, Vector3(1, 1, 1), Vector3(0.5, 1, -0.3), 1000, true,
                         Quaternion(AngleAxis(0.9, Vector3(1, -2, 0.5).normalized())));
  auto mesh =
      std::make_shared<pbd::TriangleMesh>(boxMesh(Vector3(0, 0.1, -0.1), Vector3(0.2, 0.4, 0.1)));
  b.mesh = mesh;
  b.collision.type = pbd::CollisionObjectType::SignedDistanceField;
  b.collision.scale = Vector3::Ones();
  b.massProperties = pbd::toPrincipal(pbd::integrateSolid(*mesh, 1000));
  s.rigidBodies.push_back(b);
  MujocoEngine engine;
  engine.load(s, method());
  const mjModel* m = engine.model();
  const mjData* d = engine.data();
  ASSERT_EQ(m->nmesh, 1);
  ASSERT_EQ(m->mesh_vertnum[0], 8);
  for (int v = 0; v < 8; ++v) {
    const float* local = m->mesh_vert + 3 * (m->mesh_vertadr[0] + v);
    Vector3 world(d->geom_xpos[0], d->geom_xpos[1], d->geom_xpos[2]);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        world[r] += d->geom_xmat[3 * r + c] * double(local[c]);
    double nearest = 1e9;
    for (const Vector3& sceneVertex : mesh->vertices)
      nearest =
          std::min(nearest, double((b.translation + b.rotation * sceneVertex - world).norm()));
    EXPECT_LE(nearest, 1e-6) << "vertex " << v;  // MuJoCo stores mesh vertices as float
  }
  bool recorded = false;
  for (const std::string& w : engine.warnings())
    recorded = recorded || w.find("convex hull") != std::string::npos;
  EXPECT_TRUE(recorded) << "the hull approximation is recorded";
}

// --- Springs -------------------------------------------------------------------------------------

// A 1 kg box on a spring of k = 100 N/m (a tendon with stiffness, or the damper joint's slide
// stiffness), no gravity, started through its rest position at 0.1 m/s: semi-implicit Euler
// oscillates with ω_h = (2/h) asin(ωh/2), ω = √(k/m), i.e. the period 2π/ω_h.
TEST(MujocoSprings, SpringAndDamperJointOscillateAtTheirDiscreteFrequency) {
  for (JointType type : {JointType::RigidBodySpring, JointType::Damper}) {
    Scene s = emptyScene(0.005, Vector3::Zero());
    s.rigidBodies.push_back(
        pbd::test::boxBody(0, Vector3(0.1, 0.1, 0.1), Vector3(0, 2, 0), 1, false));
    s.rigidBodies.push_back(pbd::test::boxBody(1, Vector3(0.1, 0.1, 0.1), Vector3(0, 1, 0), 1000));
    s.rigidBodies[1].velocity = Vector3(0, 0.1, 0);
    withoutCollisions(s);
    pbd::JointDesc j = pbd::test::makeJointDesc(type, 0, 1);
    j.position1 = Vector3(0, 2, 0);
    j.position2 = Vector3(0, 1, 0);
    j.axis = Vector3::UnitY();
    j.stiffness = 100;
    s.joints.push_back(j);
    MujocoEngine engine;
    const std::vector<State> states = simulate(engine, s, 800);
    std::vector<double> crossings;
    for (std::size_t k = 1; k < states.size(); ++k) {
      const double y0 = states[k - 1].bodies[1].position.y() - 1,
                   y1 = states[k].bodies[1].position.y() - 1;
      if (y0 < 0 && y1 >= 0)
        crossings.push_back(states[k - 1].time +
                            (states[k].time - states[k - 1].time) * -y0 / (y1 - y0));
    }
    ASSERT_GE(crossings.size(), 4u) << pbd::jointTypeName(type);
    const double h = 0.005, omega = 10;
    const double expected = 2 * M_PI / (2 / h * std::asin(omega * h / 2));
    const double measured = (crossings.back() - crossings.front()) / double(crossings.size() - 1);
    // Crossing times interpolated linearly on a sine: error ≲ (ωh)²/8 · h per crossing.
    EXPECT_NEAR(measured, expected, omega * omega * h * h / 8 * h) << pbd::jointTypeName(type);
  }
}

// --- Contacts ----------------------------------------------------------------------------------

TEST(MujocoContacts, EveryPairCarriesTheScenesMaterial) {
  Scene s = emptyScene();
  auto ground = pbd::test::boxBody(0, Vector3(4, 1, 4), Vector3(0, -0.5, 0), 1, false);
  ground.friction = Real(0.3);
  ground.restitution = Real(0.5);
  auto wall = pbd::test::boxBody(1, Vector3(1, 1, 1), Vector3(3, 0.5, 0), 1, false);
  auto a = pbd::test::sphereBody(2, 0.1, Vector3(0, 1, 0), 1000);
  a.friction = Real(0.2);
  a.restitution = Real(0.4);
  auto b = pbd::test::sphereBody(3, 0.1, Vector3(1, 1, 0), 1000);
  b.friction = 0;
  b.restitution = Real(0.9);
  s.rigidBodies = {ground, wall, a, b};
  pbd::ContactPairDesc pair;  // ground–b: friction overridden, restitution by the rule
  pair.body1 = 3;
  pair.body2 = 0;
  pair.hasFriction = true;
  pair.friction = Real(0.7);
  s.contactPairs.push_back(pair);
  MujocoEngine engine;
  engine.load(s, method());
  const mjModel* m = engine.model();
  for (int g = 0; g < m->ngeom; ++g)
    EXPECT_EQ(m->geom_contype[g] | m->geom_conaffinity[g], 0);
  ASSERT_EQ(m->npair, 5);  // every pair but wall–ground (both static)
  const double tau = 4 * 0.005;
  for (int p = 0; p < m->npair; ++p) {
    const int bodyA = m->geom_bodyid[m->pair_geom1[p]], bodyB = m->geom_bodyid[m->pair_geom2[p]];
    int sceneA = -1, sceneB = -1;
    for (std::size_t i = 0; i < 4; ++i) {
      if (engine.bodyId(i) == bodyA) sceneA = int(i);
      if (engine.bodyId(i) == bodyB) sceneB = int(i);
    }
    const pbd::ContactMaterial expected = s.pairMaterial(sceneA, sceneB);
    EXPECT_DOUBLE_EQ(m->pair_friction[5 * p], expected.friction);
    EXPECT_DOUBLE_EQ(m->pair_friction[5 * p + 1], expected.friction);
    EXPECT_EQ(m->pair_friction[5 * p + 2], 0);  // no torsional or rolling friction
    EXPECT_EQ(m->pair_dim[p], expected.friction > 0 ? 3 : 1);
    EXPECT_EQ(m->pair_margin[p], 0);
    EXPECT_EQ(m->pair_gap[p], 0);
    const double zeta = mujoco::dampingRatioForRestitution(expected.restitution, tau / (2 * 0.005));
    EXPECT_DOUBLE_EQ(m->pair_solref[2 * p], -1 / (tau * tau));
    EXPECT_DOUBLE_EQ(m->pair_solref[2 * p + 1], -2 * zeta / tau);
  }
  // The seed's rule for ground–a: μ = 0.3 + 0.2, e = 0.5 · 0.4; the override for ground–b.
  EXPECT_NEAR(s.pairMaterial(0, 2).friction, 0.5, 1e-7);
  EXPECT_NEAR(s.pairMaterial(0, 3).friction, 0.7, 1e-7);
}

// e(ζ) against a direct integration of x'' = −2ζω x' − ω² x from x = 0, x' = 1 until the
// force 2ζω x' + ω² x vanishes (RK4 with 10⁵ steps per 1/ω: error ≪ 1e-6).
double integratedRestitution(double zeta) {
  const double dt = 1e-5;
  double x = 0, v = 1;
  auto acc = [zeta](double px, double pv) { return -2 * zeta * pv - px; };
  for (int i = 0; i < 10000000; ++i) {
    const double k1x = v, k1v = acc(x, v);
    const double k2x = v + dt / 2 * k1v, k2v = acc(x + dt / 2 * k1x, v + dt / 2 * k1v);
    const double k3x = v + dt / 2 * k2v, k3v = acc(x + dt / 2 * k2x, v + dt / 2 * k2v);
    const double k4x = v + dt * k3v, k4v = acc(x + dt * k3x, v + dt * k3v);
    const double nx = x + dt / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
    const double nv = v + dt / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
    if (2 * zeta * nv + nx <= 0) {  // force zero: interpolate the exit velocity
      const double f0 = 2 * zeta * v + x, f1 = 2 * zeta * nv + nx;
      return -(v + (nv - v) * f0 / (f0 - f1));
    }
    x = nx;
    v = nv;
  }
  return 0;
}

TEST(MujocoContacts, RestitutionOfASpringDashpotMatchesItsIntegration) {
  EXPECT_EQ(mujoco::restitutionOfDampingRatio(0), 1);
  EXPECT_DOUBLE_EQ(mujoco::restitutionOfDampingRatio(1), std::exp(-2.0));
  EXPECT_NEAR(mujoco::restitutionOfDampingRatio(1 - 1e-7), std::exp(-2.0), 1e-6);
  EXPECT_NEAR(mujoco::restitutionOfDampingRatio(1 + 1e-7), std::exp(-2.0), 1e-6);
  for (double zeta : {0.05, 0.3, 0.6, 1 / std::sqrt(2.0), 0.9, 1.5, 2.0})
    EXPECT_NEAR(mujoco::restitutionOfDampingRatio(zeta), integratedRestitution(zeta), 1e-6)
        << "zeta " << zeta;
  for (double e : {0.1, 0.36, 0.8, 0.99})
    EXPECT_NEAR(mujoco::restitutionOfDampingRatio(mujoco::dampingRatioForRestitution(e, 10)), e,
                1e-12);
  // Below e(ζ_max) the ratio is clamped to ζ_max.
  EXPECT_EQ(mujoco::dampingRatioForRestitution(0, 2), 2);
  EXPECT_EQ(mujoco::dampingRatioForRestitution(1, 2), 0);
}

// At rest MuJoCo's constraint acceleration a = d·a_ref + (1 − d)·a₀ vanishes, with a₀ = −g and,
// in the direct format with d = dmax, d·a_ref = stiffness · r = r/τ² (r the penetration):
// r = (1 − d) g τ².
TEST(MujocoContacts, RestingPenetrationIsTheSoftContactClosedForm) {
  Scene s = emptyScene(0.002);
  s.rigidBodies.push_back(pbd::test::boxBody(0, Vector3(2, 1, 2), Vector3(0, -0.5, 0), 1, false));
  s.rigidBodies.push_back(pbd::test::sphereBody(1, 0.1, Vector3(0, 0.1, 0), 1000));
  s.rigidBodies[1].restitution = 0;
  MujocoEngine engine;
  const std::vector<State> states = simulate(engine, s, 1000);
  const double tau = 4 * 0.002, d = 0.99;
  const double penetration = 0.1 - double(states.back().bodies[1].position.y());
  EXPECT_NEAR(penetration, (1 - d) * kG * tau * tau, 1e-3 * (1 - d) * kG * tau * tau);
}

// --- Kinematic tree ----------------------------------------------------------------------------

Scene chainScene(int links, JointType type) {
  Scene s = emptyScene();
  s.rigidBodies.push_back(
      pbd::test::boxBody(0, Vector3(0.1, 0.1, 0.1), Vector3(0, 2, 0), 1, false));
  pbd::test::appendChain(s, links, type);
  return s;
}

TEST(MujocoTree, AChainHangsFromTheStaticBody) {
  const Scene s = chainScene(5, JointType::Ball);
  const mujoco::KinematicTree tree = mujoco::planKinematicTree(s);
  EXPECT_TRUE(tree.unsupported.empty());
  for (int i = 1; i <= 5; ++i) {
    EXPECT_EQ(tree.parent[std::size_t(i)], i - 1);
    EXPECT_FALSE(tree.freeRoot[std::size_t(i)]);
  }
  MujocoEngine engine;
  engine.load(s, method());
  EXPECT_EQ(engine.model()->nv, 15);  // five ball joints, no free joint
  EXPECT_EQ(engine.model()->neq, 0);
  for (int i = 1; i <= 5; ++i)
    EXPECT_EQ(engine.model()->body_parentid[engine.bodyId(std::size_t(i))],
              engine.bodyId(std::size_t(i - 1)));
}

// A four-bar linkage: ground – crank – coupler – rocker – ground, all hinges about z. The last
// hinge cannot be a tree joint; it becomes two `connect`s, and the loop holds to the soft
// constraint's static error, (1 − d) a τ² with a ≲ 2g: 1e-5 m at τ = 2h = 0.01 s.
TEST(MujocoTree, ALoopIsClosedByEqualityConstraints) {
  Scene s = emptyScene();
  s.rigidBodies.push_back(
      pbd::test::boxBody(0, Vector3(0.1, 0.1, 0.1), Vector3(0, 2, 0), 1, false));
  const Vector3 p0(0, 2, 0), p1(0, 1.5, 0), p2(0.6, 1.5, 0), p3(0.6, 2, 0);
  s.rigidBodies.push_back(pbd::test::boxBody(1, Vector3(0.05, 0.5, 0.05), (p0 + p1) / 2, 500));
  s.rigidBodies.push_back(pbd::test::boxBody(2, Vector3(0.6, 0.05, 0.05), (p1 + p2) / 2, 500));
  s.rigidBodies.push_back(pbd::test::boxBody(3, Vector3(0.05, 0.5, 0.05), (p2 + p3) / 2, 500));
  // A parallelogram swinging at ω = 2 rad/s: crank and rocker turn, the coupler translates.
  s.rigidBodies[1].velocity = s.rigidBodies[3].velocity = Vector3(0.5, 0, 0);
  s.rigidBodies[1].angularVelocity = s.rigidBodies[3].angularVelocity = Vector3(0, 0, 2);
  s.rigidBodies[2].velocity = Vector3(1, 0, 0);
  const std::pair<int, int> bodies[] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}};
  const Vector3 points[] = {p0, p1, p2, p3};
  for (int k = 0; k < 4; ++k) {
    pbd::JointDesc j =
        pbd::test::makeJointDesc(JointType::Hinge, bodies[k].first, bodies[k].second);
    j.position = points[k];
    j.axis = Vector3::UnitZ();
    s.joints.push_back(j);
  }
  withoutCollisions(s);
  const mujoco::KinematicTree tree = mujoco::planKinematicTree(s);
  int closures = 0;
  for (mujoco::JointRole role : tree.roles)
    closures += role == mujoco::JointRole::LoopClosure;
  EXPECT_EQ(closures, 1);
  MujocoEngine engine;
  const std::vector<State> states = simulate(engine, s, 400);
  EXPECT_EQ(engine.model()->nv, 3);
  EXPECT_EQ(engine.model()->neq, 2);
  // The rocker's pivot p3, fixed in body 3, stays at p3.
  const Vector3 local =
      s.rigidBodies[3].rotation.conjugate() * (p3 - s.rigidBodies[3].initialCenterOfMass());
  double worst = 0, swing = 0;
  for (const State& st : states) {
    worst = std::max(worst,
                     double((st.bodies[3].position + st.bodies[3].rotation * local - p3).norm()));
    swing = std::max(swing, double((st.bodies[2].position - states[0].bodies[2].position).norm()));
  }
  EXPECT_LE(worst, 1e-4);
  EXPECT_GT(swing, 0.1) << "the linkage should swing";
}

TEST(MujocoTree, ASliderClosingALoopIsUnsupportedByName) {
  Scene s = chainScene(2, JointType::Slider);
  pbd::JointDesc closing = pbd::test::makeJointDesc(JointType::Slider, 2, 0);
  closing.jsonPath = "SliderJoints[2]";
  closing.axis = Vector3::UnitX();
  s.joints.push_back(closing);
  MujocoEngine engine;
  const std::vector<std::string> missing = engine.unsupported(s, method());
  ASSERT_EQ(missing.size(), 1u);
  EXPECT_NE(missing[0].find("SliderJoints[2]: any other joint that closes a kinematic loop"),
            std::string::npos)
      << missing[0];
  EXPECT_NE(missing[0].find("a slider joint"), std::string::npos) << missing[0];
}

TEST(MujocoTree, UnsupportedFeaturesAreNamed) {
  Scene s = chainScene(1, JointType::Ball);
  pbd::JointDesc particle = pbd::test::makeJointDesc(JointType::RigidBodyParticleBall, 1, -1);
  particle.body2 = -1;
  s.joints.push_back(particle);
  s.rigidBodies[1].collision.type = pbd::CollisionObjectType::Torus;
  s.triangleModels.emplace_back();
  s.triangleModels.back().jsonPath = "TriangleModels[0]";
  MujocoEngine engine;
  const std::vector<std::string> missing = engine.unsupported(s, method());
  auto mentions = [&](const std::string& text) {
    for (const std::string& m : missing)
      if (m.find(text) != std::string::npos) return true;
    return false;
  };
  EXPECT_TRUE(
      mentions("RigidBodyParticleBallJoints[0]: rigid body–particle ball joint "
               "(RigidBodyParticleBallJoints): MuJoCo has no particles in this adapter"));
  EXPECT_TRUE(mentions("RigidBodies[1]: torus without a geometryFile"));
  EXPECT_TRUE(mentions("MuJoCo has no torus"));
  EXPECT_TRUE(mentions("TriangleModels[0]: cloth"));
  EXPECT_TRUE(mentions("MuJoCo has no particles in this adapter (flexes"));
  EXPECT_THROW(engine.load(s, method()), EngineError);
}

// --- Joints in reduced coordinates ---------------------------------------------------------------

/// A 1 m pendulum bob hanging off a static box, joined by `type` at the pivot, released at 30°.
Scene pendulum(JointType type, bool staticFirst) {
  Scene s = emptyScene();
  const Vector3 pivot(0, 2, 0);
  const Vector3 bob = pivot + Vector3(std::sin(0.5), -std::cos(0.5), 0);
  s.rigidBodies.push_back(pbd::test::boxBody(0, Vector3(0.1, 0.1, 0.1), pivot, 1, false));
  s.rigidBodies.push_back(pbd::test::boxBody(1, Vector3(0.1, 0.2, 0.3), bob, 1000));
  s.rigidBodies[1].angularVelocity = Vector3(0.3, 0, 0);  // tumbles where the joint allows
  pbd::JointDesc j = pbd::test::makeJointDesc(type, staticFirst ? 0 : 1, staticFirst ? 1 : 0);
  j.position = type == JointType::BallOnLine ? bob : pivot;
  j.axis = Vector3(1, 1, 0).normalized();
  j.axis1 = Vector3::UnitZ();
  j.axis2 = Vector3::UnitX();
  s.joints.push_back(j);
  withoutCollisions(s);
  return s;
}

TEST(MujocoJoints, UniversalHoldsItsPointAndPerpendicularAxesExactly) {
  for (bool staticFirst : {true, false}) {
    const Scene s = pendulum(JointType::Universal, staticFirst);
    MujocoEngine engine;
    const std::vector<State> states = simulate(engine, s, 200);
    const pbd::RigidBodyDesc& bob = s.rigidBodies[1];
    const Vector3 pivot(0, 2, 0),
        local = bob.rotation.conjugate() * (pivot - bob.initialCenterOfMass());
    // axis1 belongs to the joint's first body, axis2 to its second.
    const std::size_t first = staticFirst ? 0 : 1, second = staticFirst ? 1 : 0;
    for (const State& st : states) {
      const BodyState& b = st.bodies[1];
      EXPECT_LE((b.position + b.rotation * local - pivot).norm(), kRoundOff);
      const Vector3 a1 = st.bodies[first].rotation * Vector3::UnitZ();
      const Vector3 a2 = st.bodies[second].rotation * Vector3::UnitX();
      EXPECT_LE(std::abs(a1.dot(a2)), kRoundOff) << "static first: " << staticFirst;
    }
    EXPECT_GT((states.back().bodies[1].position - states.front().bodies[1].position).norm(), 0.05);
  }
}

TEST(MujocoJoints, BallOnLineKeepsTheAnchorOnTheLineFromEitherSide) {
  for (bool staticFirst : {true, false}) {
    const Scene s = pendulum(JointType::BallOnLine, staticFirst);
    MujocoEngine engine;
    const std::vector<State> states = simulate(engine, s, 200);
    const pbd::JointDesc& j = s.joints[0];
    const std::size_t lineBody = std::size_t(j.body1), pointBody = std::size_t(j.body2);
    const auto& lb = s.rigidBodies[lineBody];
    const auto& pb = s.rigidBodies[pointBody];
    const Vector3 pointLocal = pb.rotation.conjugate() * (j.position - pb.initialCenterOfMass());
    const Vector3 originLocal = lb.rotation.conjugate() * (j.position - lb.initialCenterOfMass());
    const Vector3 axisLocal = lb.rotation.conjugate() * j.axis;
    double travel = 0;
    for (const State& st : states) {
      const BodyState &l = st.bodies[lineBody], &p = st.bodies[pointBody];
      const Vector3 point = p.position + p.rotation * pointLocal;
      const Vector3 origin = l.position + l.rotation * originLocal, axis = l.rotation * axisLocal;
      const Vector3 offset = point - origin;
      EXPECT_LE((offset - offset.dot(axis) * axis).norm(), kRoundOff)
          << "static first: " << staticFirst;
      travel = std::max(travel, std::abs(double(offset.dot(axis))));
    }
    EXPECT_GT(travel, 0.01) << "the anchor should slide along the line";
  }
}

// --- Motors --------------------------------------------------------------------------------------

/// A hinge motor between a static box and a link, about z through the pivot, no gravity.
Scene motorScene(JointType type, double target, bool staticFirst) {
  Scene s = emptyScene(0.005, Vector3::Zero());
  s.rigidBodies.push_back(
      pbd::test::boxBody(0, Vector3(0.1, 0.1, 0.1), Vector3(0, 2, 0), 1, false));
  s.rigidBodies.push_back(pbd::test::boxBody(1, Vector3(0.1, 0.6, 0.1), Vector3(0, 1.7, 0), 1000));
  pbd::JointDesc j = pbd::test::makeJointDesc(type, staticFirst ? 0 : 1, staticFirst ? 1 : 0);
  j.position = Vector3(0, 2, 0);
  j.axis = Vector3::UnitZ();
  j.target.constant = Real(target);
  s.joints.push_back(j);
  withoutCollisions(s);
  return s;
}

// A critically damped servo with time constant τ = 4h = 0.02 s leaves an error
// e^{−t/τ}(1 + t/τ) of the step: 3e-17 relative after 2 s (100 τ); round-off dominates.
TEST(MujocoMotors, AngleMotorReachesItsTargetWithTheScenesSign) {
  for (bool staticFirst : {true, false}) {
    const Scene s = motorScene(JointType::TargetAngleMotorHinge, 0.5, staticFirst);
    MujocoEngine engine;
    const std::vector<State> states = simulate(engine, s, 400);
    const std::size_t first = staticFirst ? 0 : 1, second = staticFirst ? 1 : 0;
    const Quaternion relative =
        states.back().bodies[first].rotation.conjugate() * states.back().bodies[second].rotation;
    const AngleAxis turn(relative);
    EXPECT_NEAR(turn.angle() * turn.axis().z(), 0.5, 1e-9) << "static first: " << staticFirst;
  }
}

// A velocity servo approaches its set point as e^{−t/τ}: 2e-22 relative after 2 s.
TEST(MujocoMotors, VelocityMotorsReachTheirTargetWithTheScenesSign) {
  for (JointType type :
       {JointType::TargetVelocityMotorHinge, JointType::TargetVelocityMotorSlider}) {
    for (bool staticFirst : {true, false}) {
      Scene s = motorScene(type, 0.3, staticFirst);
      s.joints[0].axis =
          type == JointType::TargetVelocityMotorSlider ? Vector3::UnitX() : Vector3::UnitZ();
      MujocoEngine engine;
      const std::vector<State> states = simulate(engine, s, 400);
      const std::size_t first = staticFirst ? 0 : 1, second = staticFirst ? 1 : 0;
      const BodyState &a = states.back().bodies[first], &b = states.back().bodies[second];
      const double rate = type == JointType::TargetVelocityMotorSlider
                              ? (b.velocity - a.velocity).x()
                              : (b.angularVelocity - a.angularVelocity).z();
      EXPECT_NEAR(rate, 0.3, 1e-9) << pbd::jointTypeName(type) << ", static first: " << staticFirst;
    }
  }
}

// --- Initial velocities --------------------------------------------------------------------------

TEST(MujocoModel, VelocitiesTheJointsForbidAreProjectedAndRecorded) {
  Scene s = pendulum(JointType::Hinge, true);
  s.joints[0].axis = Vector3::UnitZ();
  s.rigidBodies[1].angularVelocity = Vector3::Zero();
  const Vector3 rod = (s.rigidBodies[1].initialCenterOfMass() - Vector3(0, 2, 0)).normalized();
  s.rigidBodies[1].velocity = rod + Vector3(0, 0, 1);  // along the rod and along the axis
  MujocoEngine engine;
  const std::vector<State> states = simulate(engine, s, 0);
  EXPECT_LE(std::abs(states[0].bodies[1].velocity.dot(rod)), kRoundOff);
  EXPECT_LE(std::abs(states[0].bodies[1].velocity.z()), kRoundOff);
  bool recorded = false;
  for (const std::string& w : engine.warnings())
    recorded =
        recorded || w.find("RigidBodies[1]: initial velocity disagrees") != std::string::npos;
  EXPECT_TRUE(recorded);
}

// --- Errors --------------------------------------------------------------------------------------

TEST(MujocoErrors, AnMjuErrorBecomesAnEngineError) {
  std::vector<std::string> warnings;
  try {
    mujoco::guarded("a test call", warnings, [] { mju_error("something broke"); });
    FAIL() << "no EngineError";
  } catch (const EngineError& e) {
    EXPECT_STREQ(e.what(), "MuJoCo error in a test call: something broke");
  }
  mujoco::guarded("a test call", warnings, [] { mju_warning("careful"); });
  EXPECT_EQ(warnings, std::vector<std::string>{"careful"});
}

TEST(MujocoErrors, AnErrorInsideAStepStopsTheRun) {
  const Scene s = chainScene(3, JointType::Ball);
  MujocoEngine engine;
  engine.load(s, method());
  engine.data()->nstack = 10;  // MuJoCo's stack allocator now fails: mju_error("Stack overflow")
  try {
    engine.step();
    FAIL() << "no EngineError";
  } catch (const EngineError& e) {
    EXPECT_NE(std::string(e.what()).find("Stack overflow"), std::string::npos) << e.what();
  }
  EXPECT_THROW(engine.step(), EngineError);  // the data is not trusted again
  const RunOutcome outcome = runSimulation(engine, s, method(), {0.1, 0}, {});
  EXPECT_EQ(outcome.status, RunStatus::Ok) << "a fresh load recovers: " << outcome.reason;
}

TEST(MujocoErrors, BadNumbersStopTheRunAndNoLogFileIsWritten) {
  const std::filesystem::path original = std::filesystem::current_path();
  const std::filesystem::path scratch =
      std::filesystem::temp_directory_path() / ("pbdval_mujoco_log_" + std::to_string(::getpid()));
  std::filesystem::create_directories(scratch);
  std::filesystem::current_path(scratch);
  Scene s = chainScene(1, JointType::Ball);
  s.rigidBodies[1].velocity = Vector3(0, 1e12, 0);  // a joint speed beyond mjMAXVAL = 1e10
  MujocoEngine engine;
  const RunOutcome outcome = runSimulation(engine, s, method(), {0.1, 0}, {});
  std::vector<std::string> warnings;
  mujoco::guarded("a test call", warnings, [] { mju_warning("a warning"); });
  EXPECT_THROW(mujoco::guarded("a test call", warnings, [] { mju_error("an error"); }),
               EngineError);
  const bool logWritten = std::filesystem::exists(scratch / "MUJOCO_LOG.TXT");
  std::filesystem::current_path(original);
  std::filesystem::remove_all(scratch);
  // MuJoCo's bad-state reset is an instability: the run is reported diverged, with the time
  // of the step that failed (MuJoCo's own clock restarts at 0 on a reset).
  EXPECT_EQ(outcome.status, RunStatus::Diverged);
  EXPECT_NE(outcome.reason.find("MuJoCo reset the state"), std::string::npos) << outcome.reason;
  EXPECT_NE(outcome.reason.find("t = 0.005 s"), std::string::npos) << outcome.reason;
  EXPECT_FALSE(logWritten);
}

// --- The shipped cases ---------------------------------------------------------------------------

TEST(MujocoCases, EveryCaseRunsOrNamesWhatIsMissing) {
  const std::filesystem::path cases = std::filesystem::path(PBDVAL_SOURCE_DIR) / "cases";
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(cases)) {
    if (entry.path().extension() != ".json") continue;
    ++count;
    const Scene s = pbd::loadScene(entry.path().string()).scene;
    MujocoEngine engine;
    const RunOutcome outcome = runSimulation(engine, s, method(), {0.5, 0}, {});
    const std::string name = entry.path().filename().string();
    if (outcome.status == RunStatus::Unsupported) {
      EXPECT_NE(outcome.reason.find("]: "), std::string::npos)
          << name << ": unsupported features must be named by their JSON path: " << outcome.reason;
    } else {
      EXPECT_EQ(outcome.status, RunStatus::Ok) << name << ": " << outcome.reason;
    }
  }
  EXPECT_GE(count, 15);
}

}  // namespace
}  // namespace pbdval::test
