// The ODE adapter's own mapping: what reaches ODE (mass, inertia, frames, shapes, materials,
// joints and motors), what is refused by name, and how ODE's process-wide state is handled.
// Expected values come from the Scene, closed forms, or the same run repeated.
#include <gtest/gtest.h>
#include <ode/ode.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <regex>

#include "adapters/ode/ode_engine.h"
#include "common/scene_fixtures.h"
#include "engines/selftest_engine.h"
#include "pbd/io/scene_loader.h"
#include "pbd/math/quaternion.h"
#include "validation/run/simulation.h"

namespace pbdval::test {
namespace {

namespace fs = std::filesystem;
using pbd::JointType;
using pbd::Scene;

Method method(const std::string& name = "ode.quickstep",
              const std::map<std::string, std::string>& overrides = {}) {
  return testRegistry().resolve(name, overrides);
}

Scene sceneWith(double stepSize, const Vector3& gravity) {
  Scene s;
  s.simulation.timeStepSize = Real(stepSize);
  s.simulation.gravitation = gravity;
  return s;
}

Quaternion rotation(double angle, const Vector3& axis) {
  return Quaternion(pbd::AngleAxis(Real(angle), axis.normalized()));
}

/// Angle of `q` about the unit `axis`, assuming q is a rotation about it.
double angleAbout(const Quaternion& q, const Vector3& axis) {
  return 2 * std::atan2(double(q.vec().dot(axis)), double(q.w()));
}

std::vector<State> runSteps(OdeEngine& engine, int steps) {
  std::vector<State> states(1);
  engine.read(states[0]);
  for (int n = 0; n < steps; ++n) {
    engine.step();
    states.emplace_back();
    engine.read(states.back());
  }
  return states;
}

// --- Methods ----------------------------------------------------------------------------------

TEST(OdeMethods, QuickStepIsTheDefaultAndBothCarryODEsDefaults) {
  EXPECT_EQ(testRegistry().defaultMethod("ode"), "ode.quickstep");
  const Method quick = method("ode.quickstep");
  EXPECT_EQ(quick.values.at("iterations").text(), "20");  // dWORLDQUICKSTEP_ITERATION_COUNT_DEFAULT
  EXPECT_EQ(quick.values.at("sor").text(), "1.3");        // ODE manual: w = 1.3
  EXPECT_EQ(quick.values.at("erp").text(), "0.2");        // dWorldCreate
  EXPECT_EQ(quick.values.at("cfm").text(), "1e-10");      // dWorldCreate, double precision
  const Method step = method("ode.step");
  EXPECT_EQ(step.values.count("iterations"), 0u);
  EXPECT_EQ(odeSettingsFor(step).solver, OdeSettings::Solver::Step);
}

TEST(OdeMethods, OutOfRangeParametersAreRejectedByName) {
  try {
    odeSettingsFor(method("ode.quickstep", {{"erp", "1.5"}}));
    FAIL() << "erp 1.5 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("erp"), std::string::npos) << e.what();
  }
  EXPECT_THROW(odeSettingsFor(method("ode.quickstep", {{"iterations", "2.5"}})),
               std::invalid_argument);
  EXPECT_THROW(odeSettingsFor(method("ode.step", {{"maxContacts", "0"}})), std::invalid_argument);
}

// --- Bodies -----------------------------------------------------------------------------------

TEST(OdeBodies, MassAndInertiaAreTheScenesGivenExplicitly) {
  Scene s = sceneWith(0.01, Vector3::Zero());
  auto box = pbd::test::boxBody(1, Vector3(0.1, 0.2, 0.3), Vector3::Zero(), 1000);
  // Values no shape-based ODE mass function would produce for this box.
  box.massProperties.mass = Real(3.5);
  box.massProperties.principalInertia = Vector3(0.1, 0.2, 0.25);
  s.rigidBodies = {box};
  OdeEngine engine;
  engine.load(s, method());
  dMass m;
  dBodyGetMass(engine.body(0), &m);
  EXPECT_EQ(m.mass, 3.5);
  EXPECT_EQ(m.I[0], 0.1);  // dMatrix3 rows have 4 entries
  EXPECT_EQ(m.I[5], 0.2);
  EXPECT_EQ(m.I[10], 0.25);
  for (int offDiagonal : {1, 2, 4, 6, 8, 9})
    EXPECT_EQ(m.I[offDiagonal], 0);
  for (int k = 0; k < 3; ++k)
    EXPECT_EQ(m.c[k], 0) << "ODE's body frame is the centre of mass";
}

// A body whose centre of mass is off its scene origin and whose principal axes are turned,
// posed with another asymmetric rotation: ODE's body sits at the centre of mass in principal
// axes, its box geom at the scene frame, and read() gives the scene frame back.
Scene offsetBodyScene() {
  Scene s = sceneWith(0.005, Vector3::Zero());
  auto body = pbd::test::boxBody(7, Vector3(0.4, 0.2, 0.1), Vector3(1, 2, 3), 500);
  body.massProperties.centerOfMass = Vector3(0.1, -0.2, 0.05);
  body.massProperties.principalRotation = rotation(0.7, Vector3(1, 2, 3));
  body.massProperties.principalInertia = Vector3(0.3, 0.5, 0.7);
  body.rotation = rotation(-1.1, Vector3(-2, 1, 0.5));
  s.rigidBodies = {body};
  return s;
}

TEST(OdeBodies, PrincipalAndSceneFramesRoundTripAtRest) {
  const Scene s = offsetBodyScene();
  const pbd::RigidBodyDesc& desc = s.rigidBodies[0];
  OdeEngine engine;
  engine.load(s, method());
  State state;
  engine.read(state);
  const BodyState& b = state.bodies[0];
  EXPECT_EQ(b.id, 7);
  EXPECT_EQ(b.position, desc.initialCenterOfMass());  // handed to ODE and read back unchanged
  EXPECT_LE(pbd::rotationAngleBetween(b.rotation, desc.rotation), 1e-14);
  // ODE's own frame is the principal frame at the centre of mass.
  const Quaternion odeRotation = ode::quaternionFromOde(dBodyGetQuaternion(engine.body(0)));
  EXPECT_LE(pbd::rotationAngleBetween(odeRotation, desc.initialPrincipalRotation()), 1e-14);
  // The geom (a box centred at the scene origin, in scene axes) is back at the scene frame.
  EXPECT_LE((ode::fromOde(dGeomGetPosition(engine.geom(0))) - desc.translation).norm(), 1e-14);
  dQuaternion geomRotation;
  dGeomGetQuaternion(engine.geom(0), geomRotation);
  EXPECT_LE(pbd::rotationAngleBetween(ode::quaternionFromOde(geomRotation), desc.rotation), 1e-14);
}

TEST(OdeBodies, SpinAboutAPrincipalAxisIsReadBackInTheSceneFrame) {
  Scene s = offsetBodyScene();
  pbd::RigidBodyDesc& desc = s.rigidBodies[0];
  const Vector3 axis = desc.initialPrincipalRotation() * Vector3::UnitY();  // a principal axis
  const double omega = 3;
  desc.angularVelocity = omega * axis;
  desc.velocity = Vector3(0.5, -1, 2);
  OdeEngine engine;
  engine.load(s, method());
  const int steps = 200;
  const std::vector<State> states = runSteps(engine, steps);
  const double h = s.simulation.timeStepSize;
  // ODE's infinitesimal update q ← normalize(q + ½ h [0, ω] ⊗ q) turns by 2 atan(h ω/2) per step.
  const double turned = steps * 2 * std::atan(h * omega / 2);
  const Quaternion expected = rotation(turned, axis) * desc.rotation;
  const BodyState& last = states.back().bodies[0];
  EXPECT_LE(pbd::rotationAngleBetween(last.rotation, expected), 1e-11);
  EXPECT_LE((last.angularVelocity - omega * axis).norm(), 1e-12);
  EXPECT_LE((last.position - (desc.initialCenterOfMass() + steps * h * desc.velocity)).norm(),
            1e-12);
}

TEST(OdeBodies, StaticBodiesAreGeomsWithoutBodiesReadAtTheirPose) {
  Scene s = offsetBodyScene();
  s.rigidBodies[0].isDynamic = false;
  OdeEngine engine;
  engine.load(s, method());
  EXPECT_EQ(engine.body(0), nullptr);
  ASSERT_NE(engine.geom(0), nullptr);
  EXPECT_EQ(dGeomGetBody(engine.geom(0)), nullptr);
  engine.step();
  State state;
  engine.read(state);
  EXPECT_EQ(state.bodies[0].position, s.rigidBodies[0].initialCenterOfMass());
  EXPECT_EQ(state.bodies[0].rotation.coeffs(), s.rigidBodies[0].rotation.coeffs());
  EXPECT_EQ(state.bodies[0].velocity, Vector3::Zero());
}

// --- Shapes -----------------------------------------------------------------------------------

pbd::RigidBodyDesc cylinderBody(int id, const Vector3& position) {
  pbd::RigidBodyDesc b;
  b.id = id;
  b.jsonPath = "RigidBodies[" + std::to_string(id) + "]";
  b.translation = position;
  b.collision.type = pbd::CollisionObjectType::Cylinder;
  b.collision.scale = Vector3(0.1, 0.6, 0);  // r, h (axis y)
  b.density = 1000;
  b.massProperties = pbd::toPrincipal(pbd::cylinderMoments(Real(0.1), Real(0.6), Real(1000)));
  return b;
}

TEST(OdeShapes, CylinderAxisIsTheScenesY) {
  Scene s = sceneWith(0.002, Vector3(0, -9.81, 0));
  s.rigidBodies.push_back(pbd::test::boxBody(0, Vector3(4, 1, 4), Vector3(0, -0.5, 0), 1, false));
  s.rigidBodies.push_back(cylinderBody(1, Vector3(0, 0.301, 0)));
  OdeEngine engine;
  engine.load(s, method("ode.step"));
  EXPECT_EQ(dGeomGetClass(engine.geom(1)), dCylinderClass);
  const dReal* r = dGeomGetRotation(engine.geom(1));  // ODE's z axis is column 2
  EXPECT_LE((Vector3(r[2], r[6], r[10]) - Vector3::UnitY()).norm(), 1e-15);
  // Standing on its end, it comes to rest at half its height (0.3 m), not at its radius.
  const std::vector<State> states = runSteps(engine, 500);
  // ODE's resting penetration with CFM 1e-10 and ERP 0.2: ≪ 1 mm.
  EXPECT_NEAR(states.back().bodies[1].position.y(), 0.3, 1e-3);
}

TEST(OdeShapes, PrimitivesAreNativeAndTorusCollidesItsMeshAsATrimesh) {
  Scene s = sceneWith(0.01, Vector3::Zero());
  s.rigidBodies.push_back(pbd::test::sphereBody(0, Real(0.5), Vector3::Zero()));
  s.rigidBodies.push_back(pbd::test::boxBody(1, Vector3(1, 1, 1), Vector3(3, 0, 0)));
  auto torus = pbd::test::boxBody(2, Vector3(1, 1, 1), Vector3(6, 0, 0));
  torus.collision.type = pbd::CollisionObjectType::Torus;
  auto mesh = std::make_shared<pbd::TriangleMesh>();
  mesh->vertices = {Vector3(0, 0, 0), Vector3(1, 0, 0), Vector3(0, 1, 0), Vector3(0, 0, 1)};
  mesh->triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  torus.mesh = mesh;
  s.rigidBodies.push_back(torus);
  auto none = pbd::test::boxBody(3, Vector3(1, 1, 1), Vector3(9, 0, 0));
  none.collision.type = pbd::CollisionObjectType::None;
  s.rigidBodies.push_back(none);
  OdeEngine engine;
  ASSERT_TRUE(engine.unsupported(s, method()).empty());
  engine.load(s, method());
  EXPECT_EQ(dGeomGetClass(engine.geom(0)), dSphereClass);
  EXPECT_EQ(dGeomGetClass(engine.geom(1)), dBoxClass);
  EXPECT_EQ(dGeomGetClass(engine.geom(2)), dTriMeshClass);
  EXPECT_EQ(engine.geom(3), nullptr);
  EXPECT_EQ(dGeomSphereGetRadius(engine.geom(0)), 0.5);
}

TEST(OdeShapes, FrictionPyramidFollowsWorldXProjectedOnTheContactPlane) {
  for (const Vector3& n : {Vector3(0, 1, 0), Vector3(0.3, 0.9, -0.2).normalized(), Vector3(1, 0, 0),
                           Vector3(-0.95, 0.1, 0.2).normalized()}) {
    const Vector3 d = ode::frictionDirection(n);
    EXPECT_NEAR(d.norm(), 1, 1e-15);
    EXPECT_NEAR(d.dot(n), 0, 1e-15);
    // x projected, unless the normal is within 30° of x (then z projected).
    const Vector3 reference =
        std::abs(n.x()) > std::cos(M_PI / 6) ? Vector3::UnitZ() : Vector3::UnitX();
    EXPECT_GT(d.dot(reference), 0.49) << n.transpose();
  }
  EXPECT_LE((ode::frictionDirection(Vector3::UnitY()) - Vector3::UnitX()).norm(), 1e-15);
}

// --- Contacts ---------------------------------------------------------------------------------

TEST(OdeContacts, EachPairGetsScenePairMaterialInItsContacts) {
  Scene s = sceneWith(0.001, Vector3(0, -9.81, 0));
  auto ground = pbd::test::boxBody(0, Vector3(4, 1, 4), Vector3(0, -0.5, 0), 1, false);
  ground.friction = Real(0.3);
  ground.restitution = Real(0.5);
  auto a = pbd::test::sphereBody(1, Real(0.1), Vector3(-1, 0.099, 0), 1000);
  a.friction = Real(0.1);
  a.restitution = Real(0.6);
  auto b = pbd::test::sphereBody(2, Real(0.1), Vector3(1, 0.099, 0), 1000);
  b.friction = Real(0.4);
  b.restitution = Real(0.9);
  s.rigidBodies = {ground, a, b};
  pbd::ContactPairDesc pair;
  pair.body1 = 2;
  pair.body2 = 0;
  pair.hasFriction = pair.hasRestitution = true;
  pair.friction = Real(0.05);
  pair.restitution = 0;
  s.contactPairs.push_back(pair);
  OdeEngine engine;
  engine.load(s, method());
  engine.step();
  int seen[3] = {0, 0, 0};
  for (const ode::ContactRecord& c : engine.lastContacts()) {
    const int sphere = c.body1 == 0 ? c.body2 : c.body1;
    const pbd::ContactMaterial expected = s.pairMaterial(0, sphere);
    EXPECT_EQ(c.friction, expected.friction) << "sphere " << sphere;
    EXPECT_EQ(c.restitution, expected.restitution) << "sphere " << sphere;
    ++seen[sphere];
  }
  EXPECT_EQ(seen[1], 1);
  EXPECT_EQ(seen[2], 1);
  // The seed's rule (μ_a + μ_b, e_a e_b) for sphere 1, the explicit pair for sphere 2.
  EXPECT_EQ(s.pairMaterial(0, 1).friction, Real(0.3) + Real(0.1));
  EXPECT_EQ(s.pairMaterial(0, 2).friction, Real(0.05));
}

TEST(OdeUnsupported, FeaturesWithoutAnODECounterpartAreNamed) {
  Scene s = sceneWith(0.01, Vector3::Zero());
  auto hollow = pbd::test::sphereBody(0, Real(0.5), Vector3::Zero());
  hollow.collision.type = pbd::CollisionObjectType::HollowSphere;
  auto sdf = pbd::test::boxBody(1, Vector3(1, 1, 1), Vector3(3, 0, 0));
  sdf.collision.type = pbd::CollisionObjectType::SignedDistanceField;  // and no mesh
  s.rigidBodies = {hollow, sdf};
  s.particles.push_back({});
  pbd::JointDesc particleJoint = pbd::test::makeJointDesc(JointType::RigidBodyParticleBall, 1, -1);
  particleJoint.particle = 0;
  s.joints.push_back(particleJoint);
  OdeEngine engine;
  const std::vector<std::string> missing = engine.unsupported(s, method());
  ASSERT_EQ(missing.size(), 3u);
  // Each names the JSON path, the feature, and the reason of ODE's feature table.
  EXPECT_EQ(missing[0],
            "RigidBodies[0]: hollow sphere (collisionObjectType 6): ODE has no hollow shape (a "
            "wall of thickness thicknessSDF)");
  EXPECT_EQ(
      missing[1].rfind("RigidBodies[1]: signed distance field without a geometryFile mesh", 0), 0u)
      << missing[1];
  EXPECT_EQ(missing[2],
            "RigidBodyParticleBallJoints[0]: rigid body–particle ball joint "
            "(RigidBodyParticleBallJoints): ODE has no particles");
  const RunOutcome outcome = runSimulation(engine, s, method(), {0.1, 0}, {});
  EXPECT_EQ(outcome.status, RunStatus::Unsupported);
  EXPECT_NE(outcome.reason.find("RigidBodyParticleBallJoints[0]"), std::string::npos);
  EXPECT_THROW(engine.load(s, method()), EngineError);
}

TEST(OdeUnsupported, EveryCaseRunsOrNamesWhatItCannotRepresent) {
  const fs::path cases = fs::path(PBDVAL_SOURCE_DIR) / "cases";
  const std::regex jsonPath(R"(^[A-Za-z]+\[\d+\][.:])");
  int count = 0;
  for (const fs::directory_entry& entry : fs::directory_iterator(cases)) {
    if (entry.path().extension() != ".json") continue;
    ++count;
    const Scene s = pbd::loadScene(entry.path().string()).scene;
    for (const char* name : {"ode.quickstep", "ode.step"}) {
      OdeEngine engine;
      const std::vector<std::string> missing = engine.unsupported(s, method(name));
      const RunOutcome outcome = runSimulation(engine, s, method(name), {1.0, 0}, {});
      if (missing.empty()) {
        EXPECT_EQ(outcome.status, RunStatus::Ok)
            << entry.path() << " " << name << ": " << outcome.reason;
      } else {
        EXPECT_EQ(outcome.status, RunStatus::Unsupported) << entry.path();
        for (const std::string& m : missing)
          EXPECT_TRUE(std::regex_search(m, jsonPath)) << entry.path() << ": " << m;
      }
    }
  }
  EXPECT_GE(count, 10) << cases;
}

// --- Joints -----------------------------------------------------------------------------------

/// Two boxes 1 m apart along x, joined by `type` at the first one's centre; `staticFirst`
/// and `staticSecond` choose which end is static.
Scene jointScene(JointType type, bool staticFirst, bool staticSecond) {
  Scene s = sceneWith(0.005, Vector3::Zero());
  s.rigidBodies.push_back(
      pbd::test::boxBody(0, Vector3(0.2, 0.2, 0.2), Vector3::Zero(), 1000, !staticFirst));
  s.rigidBodies.push_back(
      pbd::test::boxBody(1, Vector3(0.2, 0.2, 0.2), Vector3(1, 0, 0), 1000, !staticSecond));
  pbd::JointDesc j = pbd::test::makeJointDesc(type, 0, 1);
  j.position = Vector3::Zero();
  j.axis = Vector3::UnitZ();
  j.position1 = Vector3::Zero();
  j.position2 = Vector3(1, 0, 0);
  s.joints.push_back(j);
  return s;
}

// The seed's motors act on body 1 relative to body 0; with either end static the relative
// motion must have the set point's sign.
TEST(OdeJoints, VelocityMotorSetPointIsBodyOneRelativeToBodyZero) {
  for (const bool staticFirst : {true, false}) {
    Scene s = jointScene(JointType::TargetVelocityMotorHinge, staticFirst, !staticFirst);
    s.joints[0].target.constant = 2;
    OdeEngine engine;
    engine.load(s, method("ode.step"));
    const State last = runSteps(engine, 10).back();
    const double relative =
        (last.bodies[1].angularVelocity - last.bodies[0].angularVelocity).dot(Vector3::UnitZ());
    // A hard velocity row solved by the direct LCP: exact to round-off.
    EXPECT_NEAR(relative, 2, 1e-9) << (staticFirst ? "body 0 static" : "body 1 static");
  }
}

TEST(OdeJoints, TargetAngleMotorReachesItsSetPointEveryStep) {
  for (const bool staticFirst : {true, false}) {
    Scene s = jointScene(JointType::TargetAngleMotorHinge, staticFirst, !staticFirst);
    s.joints[0].target.times = {0, 1};
    s.joints[0].target.values = {0, 1.2};
    OdeEngine engine;
    engine.load(s, method("ode.step"));
    const std::vector<State> states = runSteps(engine, 100);
    for (std::size_t n = 1; n < states.size(); n += 33) {
      const Quaternion relative =
          states[n].bodies[0].rotation.conjugate() * states[n].bodies[1].rotation;
      // Servo: each step asks for the set point's angle change; ODE's rotation update turns by
      // 2 atan(h ω/2) instead of h ω, so the angle lags by (h ω)³/12 (1.8e-8 rad at
      // ω = 1.2 rad/s, h = 5 ms), corrected by the next step: the lag never accumulates. The
      // motor row's CFM (1e-10) yields h·CFM·τ ≈ 1e-9 rad more in the first step, where the
      // torque τ = I ω/h ≈ 2e3 N m starts the motion.
      const double lag = std::pow(s.simulation.timeStepSize * 1.2, 3) / 12;
      EXPECT_NEAR(angleAbout(relative, Vector3::UnitZ()), 1.2 * states[n].time, lag + 2e-9)
          << "t = " << states[n].time << (staticFirst ? ", body 0 static" : ", body 1 static");
    }
  }
}

TEST(OdeJoints, TargetPositionMotorReachesItsSetPointEveryStep) {
  for (const bool staticFirst : {true, false}) {
    Scene s = jointScene(JointType::TargetPositionMotorSlider, staticFirst, !staticFirst);
    s.joints[0].axis = Vector3::UnitX();
    s.joints[0].target.constant = Real(0.25);
    OdeEngine engine;
    engine.load(s, method("ode.step"));
    const State last = runSteps(engine, 3).back();
    const double offset = (last.bodies[1].position - last.bodies[0].position).x();
    EXPECT_NEAR(offset, 1.25, 1e-9) << (staticFirst ? "body 0 static" : "body 1 static");
  }
}

// A spring row with ERP = 1, CFM = 1/(h k) is implicit Euler on m x″ = −k x:
//   x_{n+1} = (x_n + h v_n)/(1 + h² k/m),  v_{n+1} = (x_{n+1} − x_n)/h.
// Body 1 starts at the rest offset, moving along the spring.
double worstDeviationFromImplicitEuler(JointType type, const std::string& methodName) {
  Scene s = jointScene(type, true, false);
  s.joints[0].axis = Vector3::UnitX();
  s.joints[0].stiffness = 500;
  s.rigidBodies[1].velocity = Vector3(0.3, 0, 0);
  OdeEngine engine;
  engine.load(s, method(methodName));
  const std::vector<State> states = runSteps(engine, 400);  // 2 s, about 1.6 periods
  const double h = s.simulation.timeStepSize;
  const double w2 = 500 / double(s.rigidBodies[1].massProperties.mass);
  double x = 0, v = 0.3, worst = 0;
  for (std::size_t n = 1; n < states.size(); ++n) {
    const double next = (x + h * v) / (1 + h * h * w2);
    v = (next - x) / h;
    x = next;
    worst = std::max(worst, std::abs(double(states[n].bodies[1].position.x()) - 1 - x));
  }
  return worst;
}

TEST(OdeJoints, SpringAndDamperRowsAreImplicitEulerSprings) {
  // The direct solver: round-off over 400 steps of an amplitude of 2 cm.
  EXPECT_LE(worstDeviationFromImplicitEuler(JointType::RigidBodySpring, "ode.step"), 1e-12);
  EXPECT_LE(worstDeviationFromImplicitEuler(JointType::Damper, "ode.step"), 1e-12);
}

// A rod hanging 20° off the vertical from a point that slides on a rail along x (no collision
// shapes: the rod's end overlaps the rail's body).
Scene ballOnLineScene() {
  Scene s = sceneWith(0.005, Vector3(0, -9.81, 0));
  s.rigidBodies.push_back(
      pbd::test::boxBody(0, Vector3(0.2, 0.2, 0.2), Vector3(0, 2, 0), 1000, false));
  const double tilt = 20 * M_PI / 180;
  const Quaternion q = rotation(tilt, Vector3::UnitZ());
  s.rigidBodies.push_back(pbd::test::boxBody(
      1, Vector3(0.1, 0.6, 0.1), Vector3(0, 2, 0) + q * Vector3(0, -0.3, 0), 1000, true, q));
  s.rigidBodies[1].velocity = Vector3(0.2, 0, 0.3);
  for (pbd::RigidBodyDesc& b : s.rigidBodies)
    b.collision.type = pbd::CollisionObjectType::None;
  pbd::JointDesc j = pbd::test::makeJointDesc(JointType::BallOnLine, 0, 1);
  j.position = Vector3(0, 2, 0);
  j.axis = Vector3::UnitX();
  s.joints.push_back(j);
  return s;
}

TEST(OdeJoints, BallOnLineIsARailCarriageInTheDirectSolverOnly) {
  const Scene s = ballOnLineScene();
  OdeEngine engine;
  const std::vector<std::string> quick = engine.unsupported(s, method("ode.quickstep"));
  ASSERT_EQ(quick.size(), 1u);
  EXPECT_EQ(quick[0].rfind("BallOnLineJoints[0]: ball-on-line joint (BallOnLineJoints): ODE has no "
                           "ball-on-line joint",
                           0),
            0u)
      << quick[0];
  ASSERT_TRUE(engine.unsupported(s, method("ode.step")).empty());

  engine.load(s, method("ode.step"));
  EXPECT_EQ(engine.auxiliaryBodyCount(), 1u);
  const std::vector<State> states = runSteps(engine, 600);
  const double h = s.simulation.timeStepSize, ratio = 1e-3;  // carriageMassRatio's default
  const Vector3 anchorInBody = s.rigidBodies[1].rotation.conjugate() *
                               (Vector3(0, 2, 0) - s.rigidBodies[1].initialCenterOfMass());
  auto anchorVelocity = [&](const BodyState& b) {
    return Vector3(b.velocity + b.angularVelocity.cross(b.rotation * anchorInBody));
  };
  const BodyState& first = states.front().bodies[1];
  double lineError = 0, largestAcceleration = 0, momentumError = 0;
  for (std::size_t n = 0; n < states.size(); ++n) {
    const BodyState& b = states[n].bodies[1];
    ASSERT_EQ(states[n].bodies.size(), 2u) << "the carriage is not a scene body";
    const Vector3 anchor = b.position + b.rotation * anchorInBody;
    lineError = std::max(lineError, double(Vector3(0, anchor.y() - 2, anchor.z()).norm()));
    if (n > 0)
      largestAcceleration = std::max(
          largestAcceleration,
          double((anchorVelocity(b) - anchorVelocity(states[n - 1].bodies[1])).norm()) / h);
    // Nothing pushes along the rail: the x momentum of the rod and the carriage (which moves
    // with the anchor) is conserved.
    momentumError = std::max(
        momentumError, std::abs(double(b.velocity.x() - first.velocity.x()) +
                                ratio * double(anchorVelocity(b).x() - anchorVelocity(first).x())));
  }
  // The parity suite's joint bound: ten times the drift of one step of motion, h² a.
  EXPECT_LE(lineError, 10 * h * h * largestAcceleration);
  // Velocity-level rows with ERP feedback let the carriage differ from the anchor by up to
  // ERP × error / h ≈ 0.2 × 1e-3 m / 5 ms = 0.04 m/s; its share of the momentum: ratio × 0.1.
  EXPECT_LE(momentumError, ratio * 0.1);
  std::printf("  ode.step ball-on-line: line error %.2e m, x-momentum error %.2e m/s\n", lineError,
              momentumError);
}

// --- Process-wide state -----------------------------------------------------------------------

Scene chainScene() {
  Scene s = sceneWith(0.005, Vector3(0, -9.81, 0));
  s.rigidBodies.push_back(
      pbd::test::boxBody(0, Vector3(0.2, 0.2, 0.2), Vector3(0, 2, 0), 1, false));
  pbd::test::appendChain(s, 3, JointType::Ball);
  return s;
}

bool sameStates(const State& a, const State& b) {
  for (std::size_t i = 0; i < a.bodies.size(); ++i)
    if (a.bodies[i].position != b.bodies[i].position ||
        a.bodies[i].rotation.coeffs() != b.bodies[i].rotation.coeffs() ||
        a.bodies[i].velocity != b.bodies[i].velocity)
      return false;
  return true;
}

TEST(OdeProcess, TwoEnginesLiveSideBySideWithoutInterfering) {
  const int before = ode::OdeLibrary::references();
  const Scene chain = chainScene();
  std::vector<State> alone;
  {
    OdeEngine engine;
    engine.load(chain, method());
    alone = runSteps(engine, 100);
  }
  EXPECT_EQ(ode::OdeLibrary::references(), before);
  auto first = std::make_unique<OdeEngine>();
  auto second = std::make_unique<OdeEngine>();
  EXPECT_EQ(ode::OdeLibrary::references(), before + 2);
  first->load(chain, method());
  second->load(offsetBodyScene(), method("ode.step"));
  State state;
  for (int n = 1; n <= 100; ++n) {
    first->step();
    if (n <= 50) second->step();
    if (n == 50) second.reset();  // destroying one engine leaves the other running
    first->read(state);
    ASSERT_TRUE(sameStates(state, alone[std::size_t(n)])) << "step " << n;
  }
  first.reset();
  EXPECT_EQ(ode::OdeLibrary::references(), before);
}

TEST(OdeProcess, AnODEErrorBecomesAnEngineErrorNotAnExit) {
  OdeEngine engine;  // holds the library, so the handlers are installed
  ode::OdeContext context;
  try {
    ode::OdeCall call(context);
    dError(7, "synthetic error %d", 42);  // ODE would call exit(1) after its handler
    FAIL() << "dError returned";
  } catch (const EngineError& e) {
    EXPECT_EQ(std::string(e.what()), "ODE error 7: synthetic error 42");
  }
  try {
    ode::OdeCall call(context);
    dDebug(3, "synthetic assertion");  // ODE would call abort()
    FAIL() << "dDebug returned";
  } catch (const EngineError& e) {
    EXPECT_EQ(std::string(e.what()), "ODE internal error 3: synthetic assertion");
  }
  {
    ode::OdeCall call(context);
    dMessage(5, "a warning");
  }
  EXPECT_EQ(context.messages.total, 1u);
  ASSERT_EQ(context.messages.kept.size(), 1u);
  EXPECT_EQ(context.messages.kept[0], "ODE message 5: a warning");
}

TEST(OdeProcess, InvalidMassRejectedByODEIsARunStatus) {
  Scene s = chainScene();
  s.rigidBodies[2].massProperties.principalInertia = Vector3(1, 1, -1);  // not positive definite
  OdeEngine engine;
  const RunOutcome outcome = runSimulation(engine, s, method(), {0.1, 0}, {});
  EXPECT_EQ(outcome.status, RunStatus::Error);
  EXPECT_NE(outcome.reason.find("ODE"), std::string::npos) << outcome.reason;
  std::printf("  invalid inertia: %s\n", outcome.reason.c_str());
  EXPECT_THROW(engine.step(), EngineError);
  // The process and ODE are fine: the next engine runs.
  OdeEngine next;
  EXPECT_EQ(runSimulation(next, chainScene(), method(), {0.1, 0}, {}).status, RunStatus::Ok);
}

// Issue 25: states the scene loader refuses (|ω| = 1e300, |x| = 1e308), handed to the engine
// directly, in both solvers and with contacts (a box on a static box): whatever ODE makes of
// them, and whatever error its handlers throw inside a step (collision callbacks included),
// the run ends with a status; the engine is then destroyed without ending the process, and
// the next engine runs. Before the fix this aborted the test binary (std::terminate).
TEST(OdeProcess, ExtremeStatesEndAsAStatusAndTheEngineIsDestroyedSafely) {
  auto tetrahedron = std::make_shared<pbd::TriangleMesh>();
  tetrahedron->vertices = {Vector3(0, 0, 0), Vector3(0.2, 0, 0), Vector3(0, 0.2, 0),
                           Vector3(0, 0, 0.2)};
  tetrahedron->triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  for (const std::string solver : {"ode.quickstep", "ode.step"}) {
    for (const pbd::CollisionObjectType shape :
         {pbd::CollisionObjectType::Box, pbd::CollisionObjectType::Sphere,
          pbd::CollisionObjectType::Torus /* its mesh, as an ODE trimesh */}) {
      for (int variant = 0; variant < 4; ++variant) {
        Scene s = sceneWith(0.005, Vector3(0, -9.81, 0));
        s.rigidBodies.push_back(
            pbd::test::boxBody(0, Vector3(2, 0.2, 2), Vector3(0, -0.1, 0), 1000, false));
        pbd::RigidBodyDesc body =
            shape == pbd::CollisionObjectType::Sphere
                ? pbd::test::sphereBody(1, Real(0.1), Vector3(0, 0.1, 0), 1000)
                : pbd::test::boxBody(1, Vector3(0.2, 0.2, 0.2), Vector3(0, 0.1, 0), 1000);
        if (shape == pbd::CollisionObjectType::Torus) {
          body.collision.type = shape;
          body.mesh = tetrahedron;
        }
        if (variant == 0) body.angularVelocity = Vector3(1e300, 0, 0);
        if (variant == 1) body.translation = Vector3(1e308, 0, 0);
        if (variant == 2) body.velocity = Vector3(0, -1e300, 0);
        if (variant == 3) body.angularVelocity = Vector3(1e300, -1e300, 1e300);
        s.rigidBodies.push_back(body);
        auto engine = std::make_unique<OdeEngine>();
        const RunOutcome outcome = runSimulation(*engine, s, method(solver), {0.05, 0}, {});
        EXPECT_NE(outcome.status, RunStatus::Ok)
            << solver << " shape " << int(shape) << " variant " << variant;
        EXPECT_FALSE(outcome.reason.empty());
        engine.reset();  // must not call std::terminate (nor dCloseODE, the last reference)
      }
    }
    OdeEngine next;
    EXPECT_EQ(runSimulation(next, chainScene(), method(solver), {0.1, 0}, {}).status,
              RunStatus::Ok);
  }
}

// An ODE error raised in the engine and the engine kept after it (as a Python object is, to the
// interpreter's exit): destroying it leaves ODE usable and does not end the process.
TEST(OdeProcess, AnEngineThatFailedIsDestroyedWithoutEndingTheProcess) {
  Scene s = chainScene();
  s.rigidBodies[2].massProperties.principalInertia = Vector3(1, 1, -1);  // ODE refuses it
  for (int round = 0; round < 3; ++round) {
    auto engine = std::make_unique<OdeEngine>();
    EXPECT_EQ(runSimulation(*engine, s, method(), {0.1, 0}, {}).status, RunStatus::Error);
    EXPECT_THROW(engine->step(), EngineError);
    engine.reset();
  }
  OdeEngine next;
  EXPECT_EQ(runSimulation(next, chainScene(), method(), {0.1, 0}, {}).status, RunStatus::Ok);
}

TEST(OdeProcess, NothingIsWrittenToTheWorkingDirectory) {
  const fs::path previous = fs::current_path();
  const fs::path scratch = fs::temp_directory_path() / ("pbdval_ode_" + std::to_string(getpid()));
  fs::create_directories(scratch);
  fs::current_path(scratch);
  {
    OdeEngine engine;
    runSimulation(engine, chainScene(), method(), {0.5, 0}, {});
    Scene bad = chainScene();
    bad.rigidBodies[1].massProperties.mass = -1;
    OdeEngine failing;
    runSimulation(failing, bad, method("ode.step"), {0.1, 0}, {});
  }
  fs::current_path(previous);
  EXPECT_TRUE(fs::is_empty(scratch));
  fs::remove_all(scratch);
}

}  // namespace
}  // namespace pbdval::test
