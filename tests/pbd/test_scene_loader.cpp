// The scene loader: every block and key of the seed's format, the seed's defaults, located
// errors for each kind of bad input, warnings, and strict mode.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <initializer_list>
#include <string>
#include <vector>

#include "common/text_assertions.h"
#include "pbd/io/scene_loader.h"

namespace pbd {
namespace {

const Real kPi = Real(EIGEN_PI);
const std::string kDataDir = PBDVAL_TEST_DATA_DIR;
const std::string kSourceDir = PBDVAL_SOURCE_DIR;
// parseScene's source path for inline scenes: relative paths start at tests/data/scenes.
const std::string kInline = kDataDir + "/scenes/inline.json";
const std::string kCube = "../../../cases/models/cube.obj";

std::string normalPath(const std::string& path) {
  return std::filesystem::path(path).lexically_normal().string();
}

LoadedScene parse(const std::string& json, LoadOptions options = {}) {
  return parseScene(json, kInline, options);
}

std::string errorOf(const std::string& json, LoadOptions options = {}) {
  try {
    parse(json, options);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "(no SceneError)";
}

using pbd::test::containsAll;

const SceneDiagnostic* warningAt(const LoadedScene& loaded, const std::string& jsonPath) {
  for (const auto& warning : loaded.warnings)
    if (warning.jsonPath == jsonPath) return &warning;
  return nullptr;
}

std::string allWarnings(const LoadedScene& loaded) {
  std::string text;
  for (const auto& warning : loaded.warnings)
    text += warning.text() + "\n";
  return text;
}

// Two rigid bodies (ids 1 and 2) that need no mesh: unit spheres.
const std::string kTwoBodies =
    R"("RigidBodies": [{"id": 1, "collisionObjectType": 1}, {"id": 2, "collisionObjectType": 1}])";

// ---- the scene with every block and key ------------------------------------------------------

const LoadedScene& everyKeyScene() {
  static const LoadedScene loaded = loadScene(kDataDir + "/scenes/every_key.json");
  return loaded;
}

// Closed forms: box m = ρabc, I = m(b² + c²)/12, ...; sphere I = 2/5 m r²; cylinder (axis y)
// I_y = m r²/2, I_x = I_z = m(3r² + h²)/12.
Vector3 boxInertia(Real mass, const Vector3& e) {
  return mass / 12 *
         Vector3(e.y() * e.y() + e.z() * e.z(), e.x() * e.x() + e.z() * e.z(),
                 e.x() * e.x() + e.y() * e.y());
}

// Mass properties from volume integration of a dyadic box (exact products and sums) or from a
// closed form: only a few roundings separate them from the expected value; 64 ulps relative.
const Real kRelative = 64 * kEpsilon;

void expectVectorNear(const Vector3& actual, const Vector3& expected, Real tolerance) {
  EXPECT_LE((actual - expected).norm(), tolerance)
      << actual.transpose() << " vs " << expected.transpose();
}

TEST(SceneLoaderEveryKey, WarnsOnlyAboutTheSettingsItsMethodsDoNotUse) {
  // The scene gives every key, so some model settings cannot apply: with clothSimulationMethod
  // 4 (XPBD distances) the orthotropic, Poisson and strain-based keys; with
  // solidSimulationMethod 3 (XPBD FEM) the volume stiffness and the strain-based flags
  // (docs/scene-format.md#simulation lists what each method reads). Nothing else warns.
  std::vector<std::string> expected;
  for (const char* key :
       {"cloth_xxStiffness", "cloth_yyStiffness", "cloth_xyStiffness", "cloth_xyPoissonRatio",
        "cloth_yxPoissonRatio", "cloth_normalizeStretch", "cloth_normalizeShear"})
    expected.push_back(std::string("Simulation.") + key +
                       ": ignored: clothSimulationMethod 4 does not use it");
  for (const char* key :
       {"solid_volumeStiffness", "solid_normalizeStretch", "solid_normalizeShear"})
    expected.push_back(std::string("Simulation.") + key +
                       ": ignored: solidSimulationMethod 3 does not use it");
  std::vector<std::string> actual;
  for (const auto& warning : everyKeyScene().warnings)
    actual.push_back(warning.jsonPath + ": " + warning.message);
  std::sort(expected.begin(), expected.end());
  std::sort(actual.begin(), actual.end());
  EXPECT_EQ(actual, expected) << allWarnings(everyKeyScene());
  EXPECT_EQ(everyKeyScene().scene.sourceFile, kDataDir + "/scenes/every_key.json");
}

TEST(SceneLoaderEveryKey, TopLevelAndSimulation) {
  const Scene& scene = everyKeyScene().scene;
  EXPECT_EQ(scene.name, "EveryKey");
  EXPECT_EQ(scene.viewer.cameraPosition, Vector3(1, 2, 3));
  EXPECT_EQ(scene.viewer.cameraLookat, Vector3(4, 5, 6));
  EXPECT_EQ(scene.validationJson, R"({"metrics":["energy"],"tolerance":0.01})");

  const SimulationSettings& s = scene.simulation;
  EXPECT_EQ(s.timeStepSize, Real(0.01));
  EXPECT_EQ(s.gravitation, Vector3(0, -2, 0.5));
  EXPECT_EQ(s.subSteps, 3);
  EXPECT_EQ(s.maxIterations, 2);
  EXPECT_EQ(s.maxIterationsV, 6);
  EXPECT_EQ(s.velocityUpdateMethod, 1);
  EXPECT_EQ(s.contactTolerance, Real(0.02));
  EXPECT_EQ(s.contactStiffnessRigidBody, 2);
  EXPECT_EQ(s.contactStiffnessParticleRigidBody, 50);
  EXPECT_EQ(s.clothSimulationMethod, 4);
  EXPECT_EQ(s.clothBendingMethod, 3);
  EXPECT_EQ(s.cloth_stiffness, Real(0.9));
  EXPECT_EQ(s.cloth_bendingStiffness, Real(0.005));
  EXPECT_EQ(s.cloth_xxStiffness, Real(0.8));
  EXPECT_EQ(s.cloth_yyStiffness, Real(0.7));
  EXPECT_EQ(s.cloth_xyStiffness, Real(0.6));
  EXPECT_EQ(s.cloth_xyPoissonRatio, Real(0.25));
  EXPECT_EQ(s.cloth_yxPoissonRatio, Real(0.2));
  EXPECT_TRUE(s.cloth_normalizeStretch);
  EXPECT_TRUE(s.cloth_normalizeShear);
  EXPECT_EQ(s.solidSimulationMethod, 3);
  EXPECT_EQ(s.solid_stiffness, Real(1e6));
  EXPECT_EQ(s.solid_poissonRatio, Real(0.2));
  EXPECT_EQ(s.solid_volumeStiffness, Real(0.5));
  EXPECT_TRUE(s.solid_normalizeStretch);
  EXPECT_TRUE(s.solid_normalizeShear);
  EXPECT_EQ(s.rod_stretchingStiffness, Real(0.9));
  EXPECT_EQ(s.rod_shearingStiffnessX, Real(0.8));
  EXPECT_EQ(s.rod_shearingStiffnessY, Real(0.7));
  EXPECT_EQ(s.rod_bendingStiffnessX, Real(0.4));
  EXPECT_EQ(s.rod_bendingStiffnessY, Real(0.3));
  EXPECT_EQ(s.rod_twistingStiffness, Real(0.2));

  const ViewerSettings& v = scene.viewer;
  EXPECT_FALSE(v.pause);
  EXPECT_EQ(v.pauseAt, 10);
  EXPECT_EQ(v.numberOfStepsPerRenderUpdate, 4);
  EXPECT_TRUE(v.renderTets);
  EXPECT_TRUE(v.renderTets0);
  EXPECT_TRUE(v.renderContacts);
  EXPECT_TRUE(v.renderAABB);
  EXPECT_TRUE(v.renderSDF);
  EXPECT_EQ(v.renderBVHDepth, 3);  // from the documented alias renderBVH
  EXPECT_EQ(v.renderBVHDepthTets, 2);
  EXPECT_TRUE(v.exportOBJ);
  EXPECT_TRUE(v.exportPLY);
  EXPECT_EQ(v.exportFPS, 30);
}

TEST(SceneLoaderEveryKey, RigidBodyKeys) {
  const Scene& scene = everyKeyScene().scene;
  ASSERT_EQ(scene.rigidBodies.size(), 6u);
  const RigidBodyDesc& b = scene.rigidBodies[0];
  EXPECT_EQ(b.jsonPath, "RigidBodies[0]");
  EXPECT_EQ(b.id, 1);
  EXPECT_TRUE(b.isDynamic);
  EXPECT_EQ(b.density, 500);
  EXPECT_EQ(b.geometryFile, normalPath(kSourceDir + "/cases/models/cube.obj"));
  EXPECT_EQ(b.translation, Vector3(0, 3, 0));
  // rotationAxis [0, 0, 2] is normalised: a rotation by 0.5 rad about z.
  expectVectorNear(b.rotation * Vector3::UnitX(), Vector3(std::cos(0.5), std::sin(0.5), 0),
                   4 * kEpsilon);
  expectVectorNear(b.rotation * Vector3::UnitZ(), Vector3::UnitZ(), 4 * kEpsilon);
  EXPECT_EQ(b.scale, Vector3(2, 1, 0.5));
  EXPECT_EQ(b.velocity, Vector3(1, 0, 0));
  EXPECT_EQ(b.angularVelocity, Vector3(0, 0.5, 0));
  EXPECT_EQ(b.restitution, Real(0.3));
  EXPECT_EQ(b.friction, Real(0.4));
  EXPECT_TRUE(b.flatShading);
  EXPECT_EQ(b.collision.type, CollisionObjectType::Box);
  EXPECT_EQ(b.collision.fileName, "");
  EXPECT_FALSE(b.collision.testMesh);
  EXPECT_EQ(b.collision.scale, Vector3(2, 1, 0.5));
  EXPECT_TRUE(b.collision.invertSDF);
  EXPECT_EQ(b.collision.thicknessSDF, Real(0.05));
  EXPECT_EQ(b.collision.resolutionSDF, Vector3i(20, 30, 40));

  // The mesh is stored scaled, in the scene frame.
  ASSERT_TRUE(b.mesh);
  EXPECT_EQ(b.mesh->vertices.size(), 8u);
  Vector3 maxCorner = Vector3::Constant(-1);
  for (const auto& v : b.mesh->vertices)
    maxCorner = maxCorner.cwiseMax(v);
  EXPECT_EQ(maxCorner, Vector3(1, 0.5, 0.25));

  // Mass properties: the 2 × 1 × 0.5 box of density 500, centred at the scene origin.
  const Real mass = 500 * 2 * 1 * 0.5;
  EXPECT_NEAR(b.massProperties.mass, mass, kRelative * mass);
  expectVectorNear(b.massProperties.principalInertia, boxInertia(mass, Vector3(2, 1, 0.5)),
                   kRelative * mass);
  expectVectorNear(b.massProperties.centerOfMass, Vector3::Zero(), kRelative);
  EXPECT_TRUE(b.massProperties.principalRotation.isApprox(Quaternion::Identity()));
  expectVectorNear(b.initialCenterOfMass(), Vector3(0, 3, 0), kRelative);

  // The static ground: its collision file is resolved against the scene's folder.
  const RigidBodyDesc& ground = scene.rigidBodies[5];
  EXPECT_EQ(ground.id, 0);
  EXPECT_FALSE(ground.isDynamic);
  EXPECT_EQ(ground.collision.fileName, normalPath(kDataDir + "/meshes/placeholder.csdf"));
}

TEST(SceneLoaderEveryKey, PrimitivesWithoutGeometryUseClosedForms) {
  const Scene& scene = everyKeyScene().scene;
  const RigidBodyDesc& sphere = scene.rigidBodies[1];  // r = 0.5, ρ = 1000
  EXPECT_TRUE(sphere.geometryFile.empty());
  EXPECT_FALSE(sphere.mesh);
  const Real sphereMass = 1000 * 4 * kPi * std::pow(Real(0.5), Real(3)) / 3;
  EXPECT_NEAR(sphere.massProperties.mass, sphereMass, kRelative * sphereMass);
  expectVectorNear(sphere.massProperties.principalInertia,
                   Vector3::Constant(Real(0.4) * sphereMass * Real(0.25)), kRelative * sphereMass);
  EXPECT_EQ(sphere.massProperties.centerOfMass, Vector3::Zero());
  expectVectorNear(sphere.initialCenterOfMass(), Vector3(3, 1, 0), 0);

  const RigidBodyDesc& cylinder = scene.rigidBodies[2];  // r = 0.3, h = 2, ρ = 1 (default)
  const Real r = Real(0.3), h = 2;
  const Real cylinderMass = kPi * r * r * h;
  EXPECT_NEAR(cylinder.massProperties.mass, cylinderMass, kRelative * cylinderMass);
  const Real transverse = cylinderMass * (3 * r * r + h * h) / 12;
  expectVectorNear(cylinder.massProperties.principalInertia,
                   Vector3(transverse, cylinderMass * r * r / 2, transverse),
                   kRelative * cylinderMass);
  EXPECT_TRUE(cylinder.massProperties.principalRotation.isApprox(Quaternion::Identity()));
}

TEST(SceneLoaderEveryKey, MassAndInertiaOverrides) {
  const Scene& scene = everyKeyScene().scene;
  // `mass` alone: the 1 × 2 × 3 box of density 2 (12 kg) scaled to 6 kg, inertia scaled alike.
  const RigidBodyDesc& scaled = scene.rigidBodies[3];
  EXPECT_EQ(scaled.massProperties.mass, 6);
  expectVectorNear(scaled.massProperties.principalInertia, boxInertia(6, Vector3(1, 2, 3)),
                   kRelative * 6);
  // `mass` and `inertia`: taken as given, about the scene origin, in the scene axes.
  const RigidBodyDesc& given = scene.rigidBodies[4];
  EXPECT_EQ(given.massProperties.mass, 2);
  EXPECT_EQ(given.massProperties.principalInertia, Vector3(1, 2, 2.5));
  EXPECT_EQ(given.massProperties.centerOfMass, Vector3::Zero());
  EXPECT_TRUE(given.massProperties.principalRotation.isApprox(Quaternion::Identity()));
  EXPECT_FALSE(given.mesh);
}

TEST(SceneLoaderEveryKey, TriangleAndTetModelsAndTheirParticles) {
  const Scene& scene = everyKeyScene().scene;
  ASSERT_EQ(scene.triangleModels.size(), 1u);
  ASSERT_EQ(scene.tetModels.size(), 1u);
  // 3 × 3 cloth, then one tetrahedron, then the rods (3 + 4 points: test_line_models.cpp)
  ASSERT_EQ(scene.particles.size(), 9u + 4u + 7u);

  const TriangleModelDesc& cloth = scene.triangleModels[0];
  EXPECT_EQ(cloth.id, 7);
  EXPECT_EQ(cloth.jsonPath, "TriangleModels[0]");
  EXPECT_EQ(cloth.geometryFile, normalPath(kDataDir + "/meshes/plane_3x3.obj"));
  EXPECT_EQ(cloth.translation, Vector3(0, 5, 0));
  EXPECT_EQ(cloth.scale, Vector3(2, 1, 2));
  EXPECT_EQ(cloth.staticParticles, (std::vector<int>{0, 2}));
  EXPECT_EQ(cloth.restitution, Real(0.15));
  EXPECT_EQ(cloth.friction, Real(0.25));
  EXPECT_EQ(cloth.firstParticle, 0);
  EXPECT_EQ(cloth.mesh.triangles.size(), 8u);
  // Vertex (x, 0, z) → scale (2x, 0, 2z) → +90° about x: (2x, −2z, 0) → + (0, 5, 0).
  // cos(π/2) rounds to 6e-17 in double, so components are exact to a few ulps of 5.
  for (int j = 0; j < 9; ++j) {
    const Real x = Real(0.5) * (j % 3), z = Real(0.5) * (j / 3);
    const Vector3 expected(2 * x, 5 - 2 * z, 0);
    expectVectorNear(cloth.mesh.vertices[static_cast<std::size_t>(j)], expected, 16 * kEpsilon);
    expectVectorNear(scene.particles[static_cast<std::size_t>(j)].position, expected,
                     16 * kEpsilon);
    EXPECT_EQ(scene.particles[static_cast<std::size_t>(j)].mass, (j == 0 || j == 2) ? 0 : 1);
  }

  const TetModelDesc& tet = scene.tetModels[0];
  EXPECT_EQ(tet.id, 8);
  EXPECT_EQ(tet.nodeFile, normalPath(kDataDir + "/meshes/tet.node"));
  EXPECT_EQ(tet.eleFile, normalPath(kDataDir + "/meshes/tet.ele"));
  EXPECT_EQ(tet.visFile, normalPath(kDataDir + "/meshes/tet_surface.obj"));
  EXPECT_EQ(tet.staticParticles, (std::vector<int>{3}));
  EXPECT_EQ(tet.restitution, Real(0.05));
  EXPECT_EQ(tet.friction, Real(0.35));
  // A tet model's shape keys other than these two are ignored with a warning (warningCases).
  EXPECT_EQ(tet.collision.type, CollisionObjectType::SignedDistanceField);
  EXPECT_TRUE(tet.collision.testMesh);
  EXPECT_EQ(tet.firstParticle, 9);
  ASSERT_EQ(tet.mesh.tetrahedra.size(), 1u);
  EXPECT_EQ(tet.mesh.tetrahedra[0], (std::array<int, 4>{0, 1, 2, 3}));
  // Unit tetrahedron → scale 2 → 180° about y: (x, y, z) ↦ (−x, y, −z) → + (0, 0, 5).
  // sin(π) rounds to 1.2e-16 in double: a few ulps of 5.
  const Vector3 expected[4] = {{0, 0, 5}, {-2, 0, 5}, {0, 2, 5}, {0, 0, 3}};
  ASSERT_TRUE(tet.visMesh);
  for (std::size_t k = 0; k < 4; ++k) {
    expectVectorNear(tet.mesh.vertices[k], expected[k], 16 * kEpsilon);
    expectVectorNear(tet.visMesh->vertices[k], expected[k], 16 * kEpsilon);
    expectVectorNear(scene.particles[9 + k].position, expected[k], 16 * kEpsilon);
    EXPECT_EQ(scene.particles[9 + k].mass, k == 3 ? 0 : 1);
  }
}

TEST(SceneLoaderEveryKey, JointsInBlockOrderWithResolvedBodies) {
  const Scene& scene = everyKeyScene().scene;
  const std::vector<JointType> expectedOrder = {
      JointType::Ball,
      JointType::BallOnLine,
      JointType::Hinge,
      JointType::Hinge,
      JointType::Universal,
      JointType::Slider,
      JointType::RigidBodyParticleBall,
      JointType::RigidBodySpring,
      JointType::Distance,
      JointType::Damper,
      JointType::TargetAngleMotorHinge,
      JointType::TargetAngleMotorHinge,
      JointType::TargetVelocityMotorHinge,
      JointType::TargetVelocityMotorHinge,
      JointType::TargetPositionMotorSlider,
      JointType::TargetPositionMotorSlider,
      JointType::TargetVelocityMotorSlider,
      JointType::TargetVelocityMotorSlider,
  };
  ASSERT_EQ(scene.joints.size(), expectedOrder.size());
  for (std::size_t i = 0; i < expectedOrder.size(); ++i)
    EXPECT_EQ(scene.joints[i].type, expectedOrder[i]) << i;

  // Body ids 1, 2, 3, 4, 5, 0 are rigid bodies 0 … 5.
  const JointDesc& ball = scene.joints[0];
  EXPECT_EQ(ball.jsonPath, "BallJoints[0]");
  EXPECT_EQ(ball.bodyId1, 1);
  EXPECT_EQ(ball.bodyId2, 2);
  EXPECT_EQ(ball.body1, 0);
  EXPECT_EQ(ball.body2, 1);
  EXPECT_EQ(ball.position, Vector3(0, 1, 0));

  EXPECT_EQ(scene.joints[1].axis, Vector3(1, 0, 0));  // [2, 0, 0] normalised

  const JointDesc& hinge = scene.joints[3];  // the second HingeJoints entry
  EXPECT_EQ(hinge.jsonPath, "HingeJoints[1]");
  EXPECT_EQ(hinge.body1, 1);
  EXPECT_EQ(hinge.body2, 2);
  EXPECT_EQ(scene.joints[2].position, Vector3(1, 2, 3));
  EXPECT_EQ(scene.joints[2].axis, Vector3(0, 0, 1));

  const JointDesc& universal = scene.joints[4];
  EXPECT_EQ(universal.axis1, Vector3(1, 0, 0));
  EXPECT_EQ(universal.axis2, Vector3(0, 0, 1));

  EXPECT_EQ(scene.joints[5].body2, 3);  // slider to id 4

  const JointDesc& particle = scene.joints[6];
  EXPECT_EQ(particle.bodyId1, 2);
  EXPECT_EQ(particle.body1, 1);
  EXPECT_EQ(particle.body2, -1);
  EXPECT_EQ(particle.particle, 10);
  EXPECT_EQ(particle.position, scene.particles[10].position);

  const JointDesc& spring = scene.joints[7];
  EXPECT_EQ(spring.position1, Vector3(1, 0, 0));
  EXPECT_EQ(spring.position2, Vector3(2, 0, 0));
  EXPECT_EQ(spring.stiffness, 10000);

  EXPECT_EQ(scene.joints[8].position2, Vector3(0, 3, 4));

  EXPECT_EQ(scene.joints[9].axis, Vector3(0, 1, 0));
  EXPECT_EQ(scene.joints[9].stiffness, 500000);
}

TEST(SceneLoaderEveryKey, MotorTargets) {
  const Scene& scene = everyKeyScene().scene;
  const MotorTarget& angle = scene.joints[10].target;
  EXPECT_EQ(angle.times, (std::vector<Real>{0, 2, 8, 12, 18, 20}));
  EXPECT_EQ(angle.values,
            (std::vector<Real>{0, Real(0.707), Real(0.707), Real(-0.707), Real(-0.707), 0}));
  EXPECT_TRUE(angle.repeat);
  // Linear interpolation halfway between (0, 0) and (2, 0.707); the period is 20.
  EXPECT_NEAR(angle.valueAt(1), 0.3535, 8 * kEpsilon);
  EXPECT_NEAR(angle.valueAt(21), 0.3535, 64 * kEpsilon);  // fmod(21, 20) rounds a little
  EXPECT_EQ(scene.joints[11].target.constant, Real(0.5));
  EXPECT_FALSE(scene.joints[11].target.hasSequence());

  EXPECT_EQ(scene.joints[12].target.constant, 10);
  EXPECT_FALSE(scene.joints[12].target.repeat);
  EXPECT_EQ(scene.joints[13].target.times, (std::vector<Real>{0, 2, 3}));
  EXPECT_EQ(scene.joints[13].target.values, (std::vector<Real>{0, Real(0.5), 2}));
  EXPECT_TRUE(scene.joints[13].target.repeat);

  EXPECT_EQ(scene.joints[14].target.values, (std::vector<Real>{0, Real(0.5), 2}));
  EXPECT_EQ(scene.joints[15].target.constant, Real(-0.5));

  EXPECT_EQ(scene.joints[16].axis, Vector3(0, 0, -1));
  EXPECT_EQ(scene.joints[16].target.constant, Real(0.25));
  EXPECT_EQ(scene.joints[17].target.times, (std::vector<Real>{1, 2}));
  EXPECT_EQ(scene.joints[17].target.values, (std::vector<Real>{0, 1}));
}

// ---- defaults --------------------------------------------------------------------------------

TEST(SceneLoaderDefaults, AbsentKeysTakeTheSeedsCodeDefaults) {
  const LoadedScene loaded = parse(R"({
    "RigidBodies": [{"geometryFile": ")" +
                                   kCube + R"("}],
    "TriangleModels": [{"geometryFile": "../meshes/plane_3x3.obj"}],
    "TetModels": [{"nodeFile": "../meshes/tet.node", "eleFile": "../meshes/tet.ele"}]
  })");
  EXPECT_TRUE(loaded.warnings.empty()) << allWarnings(loaded);
  const Scene& scene = loaded.scene;
  EXPECT_EQ(scene.name, "");
  EXPECT_EQ(scene.validationJson, "");

  // The seed's code defaults (research notes §4.1; velocityUpdateMethod is 0 in the code).
  const SimulationSettings& s = scene.simulation;
  EXPECT_EQ(s.timeStepSize, Real(0.005));
  EXPECT_EQ(s.gravitation, Vector3(0, Real(-9.81), 0));
  EXPECT_EQ(s.subSteps, 5);
  EXPECT_EQ(s.maxIterations, 1);
  EXPECT_EQ(s.maxIterationsV, 5);
  EXPECT_EQ(s.velocityUpdateMethod, 0);
  EXPECT_EQ(s.contactTolerance, Real(0.01));
  EXPECT_EQ(s.contactStiffnessRigidBody, 1);
  EXPECT_EQ(s.contactStiffnessParticleRigidBody, 100);
  EXPECT_EQ(s.clothSimulationMethod, 2);
  EXPECT_EQ(s.clothBendingMethod, 2);
  // Unset: the seed's forced value for the method (1; 10⁵ N/m for XPBD distance, method 4).
  EXPECT_FALSE(s.cloth_stiffness.has_value());
  EXPECT_EQ(clothStiffnessFor(s), 1);
  EXPECT_FALSE(s.cloth_bendingStiffness.has_value());
  EXPECT_EQ(clothBendingStiffnessFor(s), Real(0.01));
  EXPECT_EQ(s.cloth_xxStiffness, 1);
  EXPECT_EQ(s.cloth_yyStiffness, 1);
  EXPECT_EQ(s.cloth_xyStiffness, 1);
  EXPECT_EQ(s.cloth_xyPoissonRatio, Real(0.3));
  EXPECT_EQ(s.cloth_yxPoissonRatio, Real(0.3));
  EXPECT_FALSE(s.cloth_normalizeStretch);
  EXPECT_FALSE(s.cloth_normalizeShear);
  EXPECT_EQ(s.solidSimulationMethod, 2);
  EXPECT_FALSE(s.solid_stiffness.has_value());
  EXPECT_EQ(solidStiffnessFor(s), 1);
  EXPECT_EQ(s.solid_poissonRatio, Real(0.3));
  EXPECT_FALSE(s.solid_volumeStiffness.has_value());
  EXPECT_EQ(solidVolumeStiffnessFor(s), 1);
  {
    SimulationSettings xpbd = s;
    xpbd.clothSimulationMethod = 4;
    xpbd.solidSimulationMethod = 6;
    EXPECT_EQ(clothStiffnessFor(xpbd), Real(1e5));
    EXPECT_EQ(solidStiffnessFor(xpbd), Real(1e5));
    EXPECT_EQ(solidVolumeStiffnessFor(xpbd), Real(1e5));
    xpbd.solidSimulationMethod = 3;
    EXPECT_EQ(solidStiffnessFor(xpbd), Real(1e6));
    xpbd.clothBendingMethod = 3;
    EXPECT_EQ(clothBendingStiffnessFor(xpbd), Real(100));
    xpbd.cloth_stiffness = Real(7);  // a scene's value wins, as in the seed
    EXPECT_EQ(clothStiffnessFor(xpbd), 7);
  }
  EXPECT_FALSE(s.solid_normalizeStretch);
  EXPECT_FALSE(s.solid_normalizeShear);
  EXPECT_EQ(s.rod_stretchingStiffness, 1);
  EXPECT_EQ(s.rod_shearingStiffnessX, 1);
  EXPECT_EQ(s.rod_shearingStiffnessY, 1);
  EXPECT_EQ(s.rod_bendingStiffnessX, Real(0.5));
  EXPECT_EQ(s.rod_bendingStiffnessY, Real(0.5));
  EXPECT_EQ(s.rod_twistingStiffness, Real(0.5));

  const ViewerSettings& v = scene.viewer;
  EXPECT_TRUE(v.pause);
  EXPECT_EQ(v.pauseAt, -1);
  EXPECT_FALSE(v.renderTets || v.renderTets0 || v.renderContacts || v.renderAABB || v.renderSDF);
  EXPECT_EQ(v.renderBVHDepth, -1);
  EXPECT_EQ(v.renderBVHDepthTets, -1);
  EXPECT_FALSE(v.exportOBJ || v.exportPLY);
  EXPECT_EQ(v.exportFPS, 25);
  EXPECT_EQ(v.cameraPosition, Vector3(5, 10, 30));
  EXPECT_EQ(v.cameraLookat, Vector3(5, 0, 0));

  const RigidBodyDesc& b = scene.rigidBodies.at(0);
  EXPECT_EQ(b.id, 0);
  EXPECT_TRUE(b.isDynamic);
  EXPECT_EQ(b.density, 1);
  EXPECT_EQ(b.translation, Vector3::Zero());
  EXPECT_TRUE(b.rotation.isApprox(Quaternion::Identity()));
  EXPECT_EQ(b.scale, Vector3::Ones());
  EXPECT_EQ(b.velocity, Vector3::Zero());
  EXPECT_EQ(b.angularVelocity, Vector3::Zero());
  EXPECT_EQ(b.restitution, Real(0.6));
  EXPECT_EQ(b.friction, Real(0.2));
  EXPECT_FALSE(b.flatShading);
  EXPECT_EQ(b.collision.type, CollisionObjectType::None);
  EXPECT_EQ(b.collision.fileName, "");
  EXPECT_TRUE(b.collision.testMesh);
  EXPECT_EQ(b.collision.scale, Vector3::Ones());
  EXPECT_FALSE(b.collision.invertSDF);
  EXPECT_EQ(b.collision.thicknessSDF, Real(0.1));
  EXPECT_EQ(b.collision.resolutionSDF, Vector3i(10, 10, 10));
  EXPECT_NEAR(b.massProperties.mass, 1, kRelative);  // unit cube, density 1

  const TriangleModelDesc& cloth = scene.triangleModels.at(0);
  EXPECT_EQ(cloth.id, 0);
  EXPECT_EQ(cloth.restitution, Real(0.1));
  EXPECT_EQ(cloth.friction, Real(0.2));
  EXPECT_TRUE(cloth.staticParticles.empty());
  const TetModelDesc& tet = scene.tetModels.at(0);
  EXPECT_EQ(tet.restitution, Real(0.1));
  EXPECT_EQ(tet.friction, Real(0.2));
  EXPECT_EQ(tet.visFile, "");
  EXPECT_FALSE(tet.visMesh);
  EXPECT_EQ(tet.collision.type, CollisionObjectType::None);
  for (const ParticleDesc& p : scene.particles)
    EXPECT_EQ(p.mass, 1);
  EXPECT_EQ(scene.particles.size(), 13u);
}

TEST(SceneLoaderDefaults, EmptySceneIsValid) {
  const LoadedScene loaded = parse("{}");
  EXPECT_TRUE(loaded.warnings.empty());
  EXPECT_TRUE(loaded.scene.rigidBodies.empty());
  EXPECT_TRUE(loaded.scene.joints.empty());
}

TEST(SceneLoaderDefaults, MotorWithoutTargetHoldsZero) {
  const LoadedScene loaded = parse("{" + kTwoBodies + R"(,
    "TargetVelocityMotorHingeJoints": [{"bodyID1": 1, "bodyID2": 2, "position": [0, 0, 0],
                                        "axis": [1, 0, 0]}]})");
  const MotorTarget& target = loaded.scene.joints.at(0).target;
  EXPECT_EQ(target.constant, 0);
  EXPECT_FALSE(target.hasSequence());
  EXPECT_FALSE(target.repeat);
}

// ---- other accepted forms --------------------------------------------------------------------

TEST(SceneLoaderForms, BodiesWithTheSameFileAndScaleShareOneMesh) {
  const LoadedScene loaded = parse(R"({"RigidBodies": [
    {"id": 1, "geometryFile": ")" + kCube +
                                   R"(", "scale": [1, 2, 1]},
    {"id": 2, "geometryFile": ")" + kCube +
                                   R"(", "scale": [1, 2, 1]},
    {"id": 3, "geometryFile": ")" + kCube +
                                   R"(", "scale": [1, 3, 1]}]})");
  const auto& bodies = loaded.scene.rigidBodies;
  EXPECT_EQ(bodies[0].mesh, bodies[1].mesh);
  EXPECT_NE(bodies[0].mesh, bodies[2].mesh);
}

TEST(SceneLoaderForms, CommentKeysAreAllowedEverywhere) {
  // The seed's shipped scenes annotate objects with "comment".
  const LoadedScene loaded = parse(R"({"comment": "top", "Simulation": {"comment": 1},
    "RigidBodies": [{"collisionObjectType": 1, "comment": "1: Sphere, 2: Box"}]})");
  EXPECT_TRUE(loaded.warnings.empty()) << allWarnings(loaded);
}

TEST(SceneLoaderForms, IntegralFloatsAreIntegersAndZeroAngleNeedsNoAxis) {
  const LoadedScene loaded = parse(R"({"Simulation": {"subSteps": 2.0},
    "RigidBodies": [{"collisionObjectType": 1, "rotationAxis": [0, 0, 0], "rotationAngle": 0}]})");
  EXPECT_TRUE(loaded.warnings.empty()) << allWarnings(loaded);
  EXPECT_EQ(loaded.scene.simulation.subSteps, 2);
  EXPECT_TRUE(loaded.scene.rigidBodies[0].rotation.isApprox(Quaternion::Identity()));
}

TEST(SceneLoaderForms, StaticBodyWithAnOpenMeshHasNoMass) {
  const LoadedScene loaded = parse(R"({"RigidBodies": [
    {"isDynamic": false, "geometryFile": "../meshes/open_box.obj", "translation": [1, 2, 3]}]})");
  const MassProperties& props = loaded.scene.rigidBodies[0].massProperties;
  EXPECT_EQ(props.mass, 0);
  EXPECT_EQ(props.centerOfMass, Vector3::Zero());
  EXPECT_TRUE(props.principalRotation.isApprox(Quaternion::Identity()));
  EXPECT_EQ(loaded.scene.rigidBodies[0].initialCenterOfMass(), Vector3(1, 2, 3));
}

TEST(SceneLoaderForms, DynamicBodyWithAnOpenMeshIsAcceptedWithMassAndInertia) {
  const LoadedScene loaded = parse(R"({"RigidBodies": [
    {"geometryFile": "../meshes/open_box.obj", "mass": 3, "inertia": [1, 1, 1]}]})");
  EXPECT_EQ(loaded.scene.rigidBodies[0].massProperties.mass, 3);
}

TEST(SceneLoaderForms, UniversalAxesWithinTheToleranceArePerpendicular) {
  // |cos| = 1e-7 < 1e-6.
  const LoadedScene loaded = parse("{" + kTwoBodies + R"(, "UniversalJoints": [{"bodyID1": 1,
    "bodyID2": 2, "position": [0, 0, 0], "axis1": [1, 0, 0], "axis2": [1e-7, 1, 0]}]})");
  EXPECT_EQ(loaded.scene.joints.size(), 1u);
}

// ---- errors ----------------------------------------------------------------------------------

TEST(SceneLoaderErrors, SyntaxErrorGivesLineAndColumn) {
  EXPECT_TRUE(containsAll(errorOf("{\n  \"Name\": \"x\",\n  \"Simulation\": {,}\n}"),
                          {"inline.json: ", "invalid JSON at line 3, column 18"}));
  EXPECT_TRUE(containsAll(errorOf("{\"Name\": \"x\""), {"invalid JSON at line 1"}));
  EXPECT_TRUE(
      containsAll(errorOf("[1, 2]"), {"expected a JSON object at the top level, got [1,2]"}));
}

TEST(SceneLoaderErrors, WrongTypesNameThePathTheExpectationAndTheValue) {
  EXPECT_TRUE(
      containsAll(errorOf(R"({"Simulation": {"timeStepSize": "fast"}})"),
                  {"inline.json: Simulation.timeStepSize: expected a number in [1e-07, 10], got "
                   "\"fast\""}));
  EXPECT_TRUE(containsAll(
      errorOf(R"({"RigidBodies": [{"collisionObjectType": 1, "collisionObjectScale": "abc"}]})"),
      {"RigidBodies[0].collisionObjectScale: expected an array of 3 finite numbers, got "
       "\"abc\""}));
  EXPECT_TRUE(containsAll(errorOf(R"({"Simulation": {"pause": 2}})"),
                          {"Simulation.pause: expected a boolean (true/false or 0/1), got 2"}));
  EXPECT_TRUE(containsAll(errorOf(R"({"RigidBodies": {"id": 1}})"),
                          {"RigidBodies: expected an array of rigid-body objects, got {"}));
  EXPECT_TRUE(
      containsAll(errorOf(R"({"BallJoints": [3]})"), {"BallJoints[0]: expected an object, got 3"}));
  EXPECT_TRUE(containsAll(errorOf(R"({"Name": 5})"), {"Name: expected a string, got 5"}));
  // Long values are shortened in messages.
  std::string longArray = "[0";
  for (int i = 1; i < 100; ++i)
    longArray += "," + std::to_string(i);
  const std::string message = errorOf(R"({"Name": )" + longArray + "]}");
  EXPECT_TRUE(containsAll(message, {"Name: expected a string, got [0,1,2", "..."}));
  EXPECT_LT(message.size(), 200u);
}

TEST(SceneLoaderErrors, MissingRequiredKeys) {
  EXPECT_TRUE(containsAll(errorOf(R"({"TriangleModels": [{"id": 1}]})"),
                          {"TriangleModels[0]: missing required key \"geometryFile\""}));
  EXPECT_TRUE(containsAll(errorOf(R"({"TetModels": [{"nodeFile": "../meshes/tet.node"}]})"),
                          {"TetModels[0]: missing required key \"eleFile\""}));
  EXPECT_TRUE(containsAll(errorOf(R"({"RigidBodies": [{"id": 1}]})"),
                          {"RigidBodies[0]: missing required key \"geometryFile\"",
                           "collisionObjectType is 1, 2 or 3", "\"mass\" and \"inertia\""}));
  EXPECT_TRUE(containsAll(errorOf(R"({"RigidBodies": [{"id": 1, "mass": 1}]})"),
                          {"RigidBodies[0]: missing required key \"geometryFile\""}));
  EXPECT_TRUE(containsAll(
      errorOf("{" + kTwoBodies +
              R"(, "HingeJoints": [{"bodyID1": 1, "bodyID2": 2, "position": [0, 0, 0]}]})"),
      {"HingeJoints[0]: missing required key \"axis\""}));
  EXPECT_TRUE(containsAll(errorOf("{" + kTwoBodies + R"(, "BallJoints": [{"bodyID1": 1}]})"),
                          {"BallJoints[0]: missing required key \"bodyID2\""}));
  EXPECT_TRUE(containsAll(
      errorOf("{" + kTwoBodies +
              R"(, "RigidBodySprings": [{"bodyID1": 1, "bodyID2": 2, "position1": [0, 0, 0],
                 "position2": [1, 0, 0]}]})"),
      {"RigidBodySprings[0]: missing required key \"stiffness\""}));
}

TEST(SceneLoaderErrors, NonFiniteNumbers) {
  EXPECT_TRUE(containsAll(errorOf(R"({"Simulation": {"gravitation": [0, 1e999, 0]}})"),
                          {"inline.json: Simulation.gravitation[1]: expected a finite number, "
                           "got 1e999"}));
  EXPECT_TRUE(
      containsAll(errorOf(R"({"RigidBodies": [{"collisionObjectType": 1, "density": -1e999}]})"),
                  {"RigidBodies[0].density: expected a finite number, got -1e999"}));
  // Anywhere in the file, even in a block the library does not interpret.
  EXPECT_TRUE(containsAll(errorOf(R"({"Validation": {"a": [1, 2e400]}})"),
                          {"Validation.a[1]: expected a finite number"}));
}

TEST(SceneLoaderErrors, NonIntegralIntegers) {
  EXPECT_TRUE(containsAll(errorOf(R"({"Simulation": {"subSteps": 2.5}})"),
                          {"Simulation.subSteps: expected an integer in [1, 10000], got 2.5"}));
  EXPECT_TRUE(containsAll(errorOf(R"({"RigidBodies": [{"collisionObjectType": 1, "id": 0.5}]})"),
                          {"RigidBodies[0].id: expected an integer, got 0.5"}));
  EXPECT_TRUE(containsAll(errorOf(R"({"Simulation": {"maxIterations": 1e10}})"),
                          {"Simulation.maxIterations: expected an integer in [1, 10000]"}));
}

TEST(SceneLoaderErrors, OutOfRangeValues) {
  const std::pair<std::string, std::string> cases[] = {
      {R"({"Simulation": {"timeStepSize": 0}})",
       "Simulation.timeStepSize: expected a number in [1e-07, 10], got 0"},
      {R"({"Simulation": {"subSteps": 0}})",
       "Simulation.subSteps: expected an integer in [1, 10000]"},
      // The bounds keep every run finite: 10^9 substeps per step would hang a run.
      {R"({"Simulation": {"subSteps": 1000000000}})",
       "Simulation.subSteps: expected an integer in [1, 10000], got 1000000000"},
      {R"({"Simulation": {"timeStepSize": 1e-20}})",
       "Simulation.timeStepSize: expected a number in [1e-07, 10], got 1e-20"},
      {R"({"Simulation": {"maxIterationsV": -1}})",
       "Simulation.maxIterationsV: expected an integer in [0, 10000]"},
      {R"({"Simulation": {"velocityUpdateMethod": 2}})",
       "Simulation.velocityUpdateMethod: expected an integer in [0, 1], got 2"},
      {R"({"Simulation": {"contactTolerance": -0.1}})",
       "Simulation.contactTolerance: expected a number >= 0"},
      {R"({"Simulation": {"cloth_stiffness": -1}})",
       "Simulation.cloth_stiffness: expected a number >= 0"},
      {R"({"Simulation": {"clothSimulationMethod": 5}})",
       "Simulation.clothSimulationMethod: expected an integer in [0, 4], got 5"},
      {R"({"Simulation": {"clothBendingMethod": 4}})",
       "Simulation.clothBendingMethod: expected an integer in [0, 3]"},
      {R"({"Simulation": {"solidSimulationMethod": 7}})",
       "Simulation.solidSimulationMethod: expected an integer in [0, 6]"},
      {R"({"Simulation": {"solid_poissonRatio": 0.5}})",
       "Simulation.solid_poissonRatio: expected a number in [0, 0.49], got 0.5"},
      {R"({"Simulation": {"cloth_xyPoissonRatio": 2, "cloth_yxPoissonRatio": 0.5}})",
       "Simulation.cloth_yxPoissonRatio: expected Poisson ratios with"},
      {R"({"RigidBodies": [{"collisionObjectType": 8}]})",
       "RigidBodies[0].collisionObjectType: expected an integer in [0, 7], got 8"},
      {R"({"RigidBodies": [{"collisionObjectType": 1, "resolutionSDF": [10, 0, 10]}]})",
       "RigidBodies[0].resolutionSDF[1]: expected an integer in [1, 512], got 0"},
      {R"({"RigidBodies": [{"collisionObjectType": 1, "density": 0}]})",
       "RigidBodies[0].density: expected a number > 0 for a dynamic body, got 0"},
      {R"({"RigidBodies": [{"collisionObjectType": 1, "restitution": 1.5}]})",
       "RigidBodies[0].restitution: expected a number in [0, 1], got 1.5"},
      {R"({"RigidBodies": [{"collisionObjectType": 1, "collisionObjectScale": [0, 1, 1]}]})",
       "RigidBodies[0].collisionObjectScale: expected positive values for [radius, -, -]"},
      {R"({"RigidBodies": [{"collisionObjectType": 1, "scale": [1, -1, 1]}]})",
       "RigidBodies[0].scale: expected an array of 3 finite numbers > 0"},
      {R"({"RigidBodies": [{"collisionObjectType": 1, "mass": -1}]})",
       "RigidBodies[0].mass: expected a number in [1e-12, 1e+12], got -1"},
      {R"({"RigidBodies": [{"collisionObjectType": 1, "inertia": [1, 1, 3]}]})",
       "RigidBodies[0].inertia: expected principal moments [Ixx, Iyy, Izz] > 0 with Ia + Ib >= "
       "Ic"},
      {R"({"RigidBodies": [{"collisionObjectType": 1, "rotationAxis": [0, 0, 0],
           "rotationAngle": 1}]})",
       "RigidBodies[0].rotationAxis: expected a non-zero axis for a non-zero angle, got [0,0,0]"},
      {R"({"TriangleModels": [{"geometryFile": "../meshes/plane_3x3.obj",
           "staticParticles": [0, 9]}]})",
       "TriangleModels[0].staticParticles[1]: expected a vertex index in [0, 8] (the model has "
       "9 vertices), got 9"},
      {"{" + kTwoBodies + R"(, "DamperJoints": [{"bodyID1": 1, "bodyID2": 2, "axis": [0, 1, 0],
           "stiffness": 0}]})",
       "DamperJoints[0].stiffness: expected a number > 0, got 0"},
  };
  for (const auto& [json, expected] : cases)
    EXPECT_TRUE(containsAll(errorOf(json), {"inline.json: ", expected}));
}

TEST(SceneLoaderErrors, MissingMeshFileNamesTheKeyAndTheResolvedPath) {
  EXPECT_TRUE(containsAll(errorOf(R"({"RigidBodies": [{"geometryFile": "missing.obj"}]})"),
                          {"inline.json: RigidBodies[0].geometryFile: expected an existing file",
                           normalPath(kDataDir + "/scenes/missing.obj"), "got \"missing.obj\""}));
  EXPECT_TRUE(containsAll(
      errorOf(R"({"TetModels": [{"nodeFile": "../meshes/tet.node", "eleFile": "nope.ele"}]})"),
      {"TetModels[0].eleFile: expected an existing file"}));
  EXPECT_TRUE(containsAll(errorOf(R"({"RigidBodies": [{"geometryFile": ""}]})"),
                          {"RigidBodies[0].geometryFile: expected a file path, got \"\""}));
  // A PLY file that exists but is malformed: the key, the file and the header line.
  EXPECT_TRUE(
      containsAll(errorOf(R"({"RigidBodies": [{"geometryFile": "../meshes/malformed.ply"}]})"),
                  {"RigidBodies[0].geometryFile: cannot load the mesh: ", "malformed.ply",
                   "header line 1: a PLY file starts with the line 'ply'"}));
  // A mesh that exists but is malformed: the key, the mesh file and its line.
  EXPECT_TRUE(containsAll(errorOf(R"({"RigidBodies": [{"geometryFile": "../meshes/tet.ele"}]})"),
                          {"RigidBodies[0].geometryFile: cannot load the mesh: ",
                           normalPath(kDataDir + "/meshes/tet.ele"), "line 1"}));
}

TEST(SceneLoaderErrors, JointBodyReferences) {
  EXPECT_TRUE(containsAll(
      errorOf("{" + kTwoBodies +
              R"(, "BallJoints": [{"bodyID1": 1, "bodyID2": 7, "position": [0, 0, 0]}]})"),
      {"inline.json: BallJoints[0].bodyID2: expected the id of a rigid body", "got 7"}));
  EXPECT_TRUE(containsAll(
      errorOf("{" + kTwoBodies +
              R"(, "BallJoints": [{"bodyID1": 2, "bodyID2": 2, "position": [0, 0, 0]}]})"),
      {"BallJoints[0]: bodyID1 and bodyID2 both refer to RigidBodies[1] (id 2)"}));
  EXPECT_TRUE(containsAll(
      errorOf(R"({"RigidBodies": [{"collisionObjectType": 1}, {"collisionObjectType": 1},
                 {"id": 3, "collisionObjectType": 1}],
                 "BallJoints": [{"bodyID1": 3, "bodyID2": 0, "position": [0, 0, 0]}]})"),
      {"BallJoints[0].bodyID2: id 0 is ambiguous: RigidBodies[0], RigidBodies[1] share it"}));
  EXPECT_TRUE(containsAll(
      errorOf(R"({"RigidBodies": [{"id": 2, "collisionObjectType": 1}],
                 "TriangleModels": [{"geometryFile": "../meshes/plane_3x3.obj"}],
                 "RigidBodyParticleBallJoints": [{"rbID": 2, "particleID": 9}]})"),
      {"RigidBodyParticleBallJoints[0].particleID: expected a particle index in [0, 8]", "got 9"}));
  EXPECT_TRUE(containsAll(errorOf(R"({"RigidBodies": [{"id": 2, "collisionObjectType": 1}],
                 "RigidBodyParticleBallJoints": [{"rbID": 2, "particleID": 0}]})"),
                          {"particleID: expected a particle index (the scene has no particles)"}));
}

TEST(SceneLoaderErrors, JointGeometry) {
  EXPECT_TRUE(
      containsAll(errorOf("{" + kTwoBodies + R"(, "HingeJoints": [{"bodyID1": 1, "bodyID2": 2,
                 "position": [0, 0, 0], "axis": [0, 0, 0]}]})"),
                  {"inline.json: HingeJoints[0].axis: expected a non-zero axis, got [0,0,0]"}));
  EXPECT_TRUE(containsAll(
      errorOf("{" + kTwoBodies + R"(, "UniversalJoints": [{"bodyID1": 1, "bodyID2": 2,
                 "position": [0, 0, 0], "axis1": [1, 0, 0], "axis2": [1, 1, 0]}]})"),
      {"UniversalJoints[0].axis2: expected an axis perpendicular to axis1", "got [1,1,0]"}));
  EXPECT_TRUE(
      containsAll(errorOf("{" + kTwoBodies + R"(, "DistanceJoints": [{"bodyID1": 1, "bodyID2": 2,
                 "position1": [1, 2, 3], "position2": [1, 2, 3]}]})"),
                  {"DistanceJoints[0].position2: expected a point different from position1"}));
  EXPECT_TRUE(
      containsAll(errorOf("{" + kTwoBodies + R"(, "RigidBodySprings": [{"bodyID1": 1, "bodyID2": 2,
                 "position1": [0, 0, 0], "position2": [0, 0, 0], "stiffness": 1}]})"),
                  {"RigidBodySprings[0].position2: expected a point different from position1"}));
}

TEST(SceneLoaderErrors, MotorSequences) {
  const std::string motor = "{" + kTwoBodies +
                            R"(, "TargetAngleMotorHingeJoints": [{"bodyID1": 1, "bodyID2": 2,
                 "position": [0, 0, 0], "axis": [1, 0, 0], "targetSequence": )";
  EXPECT_TRUE(containsAll(errorOf(motor + "[0, 1, 2]}]}"),
                          {"inline.json: TargetAngleMotorHingeJoints[0].targetSequence: expected "
                           "a flat array [t0, v0, t1, v1, ...] of even length >= 2",
                           "got [0,1,2]"}));
  EXPECT_TRUE(containsAll(errorOf(motor + "[]}]}"), {"of even length >= 2"}));
  EXPECT_TRUE(containsAll(errorOf(motor + "[0, 0, 2, 1, 2, 3]}]}"),
                          {"TargetAngleMotorHingeJoints[0].targetSequence[4]: expected a time > 2 "
                           "(sequence times must increase strictly), got 2"}));
  EXPECT_TRUE(containsAll(errorOf(motor + "[0, \"a\"]}]}"),
                          {"targetSequence[1]: expected a number, got \"a\""}));
}

TEST(SceneLoaderErrors, DynamicBodiesNeedAClosedOutwardMesh) {
  EXPECT_TRUE(
      containsAll(errorOf(R"({"RigidBodies": [{"geometryFile": "../meshes/open_box.obj"}]})"),
                  {"inline.json: RigidBodies[0].geometryFile: the mesh", "open_box.obj",
                   "encloses no positive volume (open surface)", "give \"mass\" and \"inertia\""}));
  EXPECT_TRUE(containsAll(
      errorOf(R"({"RigidBodies": [{"geometryFile": "../meshes/inside_out_cube.obj"}]})"),
      {"RigidBodies[0].geometryFile: the mesh", "(inside-out: volume -1)"}));
}

TEST(SceneLoaderErrors, MissingSceneFile) {
  const std::string path = kDataDir + "/scenes/no_such_scene.json";
  try {
    loadScene(path);
    ADD_FAILURE() << "no SceneError";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.diagnostic().file, path);
    EXPECT_TRUE(containsAll(e.what(), {path, "cannot open the scene file"}));
  }
}

TEST(SceneLoaderErrors, DiagnosticCarriesFilePathAndMessageSeparately) {
  try {
    parse(R"({"Simulation": {"subSteps": 0}})");
    ADD_FAILURE() << "no SceneError";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.diagnostic().file, kInline);
    EXPECT_EQ(e.diagnostic().jsonPath, "Simulation.subSteps");
    EXPECT_EQ(e.diagnostic().message, "expected an integer in [1, 10000], got 0");
    EXPECT_EQ(e.diagnostic().text(), std::string(e.what()));
  }
}

// ---- warnings and strict mode ----------------------------------------------------------------

struct WarningCase {
  std::string json;
  std::string path;     // JSON path of the warning
  std::string message;  // a substring of its message
};

std::vector<WarningCase> warningCases() {
  const std::string motor = "{" + kTwoBodies + R"(, "TargetAngleMotorHingeJoints": [{"bodyID1":
      1, "bodyID2": 2, "position": [0, 0, 0], "axis": [1, 0, 0], )";
  return {
      {R"({"RigidBodies": [{"collisionObjectType": 1, "densty": 2}]})", "RigidBodies[0].densty",
       "unknown key (ignored); did you mean \"density\"?"},
      {R"({"Simulation": {"TimeStepsize": 0.1}})", "Simulation.TimeStepsize",
       "did you mean \"timeStepSize\"?"},
      {"{" + kTwoBodies + R"(, "HingeJoints": [{"bodyID1": 1, "bodyID2": 2, "position": [0, 0, 0],
          "axis": [1, 0, 0], "axes": [1, 0, 0]}]})",
       "HingeJoints[0].axes", "did you mean \"axis\"?"},
      {R"({"Foo": 1})", "Foo", "unknown key (ignored)"},
      {R"({"TetModels": [{"nodeFile": "../meshes/tet.node", "eleFile": "../meshes/tet.ele",
          "collisionObjectType": 1, "collisionObjectScale": [2, 2, 2]}]})",
       "TetModels[0].collisionObjectScale", "ignored for a tet model"},
      {R"({"TetModels": [{"nodeFile": "../meshes/tet.node", "eleFile": "../meshes/tet.ele",
          "resolutionSDF": [4, 4, 4]}]})",
       "TetModels[0].resolutionSDF", "only collisionObjectType and testMesh take effect"},
      {R"({"Simulation": {"maxIter": 4}})", "Simulation.maxIter",
       "stale name that PositionBasedDynamics silently ignores; did you mean \"maxIterations\"?"},
      {R"({"Simulation": {"maxIterVel": 4}})", "Simulation.maxIterVel",
       "did you mean \"maxIterationsV\"?"},
      {R"({"Simulation": {"tetModelSimulationMethod": 1}})", "Simulation.tetModelSimulationMethod",
       "did you mean \"solidSimulationMethod\"?"},
      {R"({"Simulation": {"triangleModelSimulationMethod": 1}})",
       "Simulation.triangleModelSimulationMethod", "did you mean \"clothSimulationMethod\"?"},
      {R"({"Simulation": {"triangleModelBendingMethod": 1}})",
       "Simulation.triangleModelBendingMethod", "did you mean \"clothBendingMethod\"?"},
      {R"({"Simulation": {"gravity": [0, -2, 0]}})", "Simulation.gravity",
       "as PositionBasedDynamics ignores \"gravity\": the gravitation stays the default [0, -9.81, "
       "0]"},
      {R"({"Simulation": {"gravity": [0, -2, 0], "gravitation": [0, -1, 0]}})",
       "Simulation.gravity", "ignored: \"gravitation\" is also given"},
      {R"({"Simulation": {"renderBVH": 2, "renderBVHDepth": 3}})", "Simulation.renderBVH",
       "ignored: \"renderBVHDepth\" is also given"},
      {R"({"RigidBodies": [{"collisionObjectType": 1}, {"collisionObjectType": 1}]})",
       "RigidBodies[1].id",
       "id 0 is shared by RigidBodies[0], RigidBodies[1]; CSV rows and joints can't tell"},
      {R"({"RigidBodies": [{"collisionObjectType": 1, "rotationAngle": 1}]})",
       "RigidBodies[0].rotationAngle", "no rotation is applied: \"rotationAxis\" is missing"},
      {R"({"TriangleModels": [{"geometryFile": "../meshes/plane_3x3.obj",
          "rotationAxis": [1, 0, 0]}]})",
       "TriangleModels[0].rotationAxis", "no rotation is applied: \"rotationAngle\" is missing"},
      {R"({"RigidBodies": [{"collisionObjectType": 2, "scale": [2, 2, 2]}]})",
       "RigidBodies[0].scale", "takes its size from \"collisionObjectScale\""},
      {motor + R"("target": 0.5, "targetSequence": [0, 1, 2, 3]}]})",
       "TargetAngleMotorHingeJoints[0].targetSequence", "ignored: \"target\" is also given"},
      {motor + R"("target": 4}]})", "TargetAngleMotorHingeJoints[0].target",
       "target angle 4 clamped to 3.14159"},
      {motor + R"("targetSequence": [0, 1, 2, -4]}]})",
       "TargetAngleMotorHingeJoints[0].targetSequence[3]", "target angle -4 clamped to -3.14159"},
      {R"({"RigidBodies": [{"id": 2, "collisionObjectType": 1}],
          "TriangleModels": [{"geometryFile": "../meshes/plane_3x3.obj"}],
          "RigidBodyParticleBallJoints": [{"rbID": 2, "particleID": 8, "position": [0, 0, 0]}]})",
       "RigidBodyParticleBallJoints[0].position", "ignored: the joint sits at particle 8"},
      {R"({"Name": "a", "Name": "b"})", "Name", "duplicate key; the last value is used"},
      // Cloth and solid settings nothing reads: no model of the family, or a method that does
      // not use the key (pbd/src/constraints/*), or bending on a cloth of method 0.
      {R"({"Simulation": {"cloth_stiffness": 0.5}})", "Simulation.cloth_stiffness",
       "ignored: the scene has no TriangleModels"},
      {R"({"Simulation": {"solidSimulationMethod": 3}})", "Simulation.solidSimulationMethod",
       "ignored: the scene has no TetModels"},
      {R"({"Simulation": {"clothSimulationMethod": 0, "clothBendingMethod": 2},
          "TriangleModels": [{"geometryFile": "../meshes/plane_3x3.obj"}]})",
       "Simulation.clothBendingMethod", "ignored: clothSimulationMethod 0 simulates no cloth"},
      {R"({"Simulation": {"clothSimulationMethod": 1, "cloth_xxStiffness": 2},
          "TriangleModels": [{"geometryFile": "../meshes/plane_3x3.obj"}]})",
       "Simulation.cloth_xxStiffness", "ignored: clothSimulationMethod 1 does not use it"},
      {R"({"Simulation": {"clothBendingMethod": 0, "cloth_bendingStiffness": 2},
          "TriangleModels": [{"geometryFile": "../meshes/plane_3x3.obj"}]})",
       "Simulation.cloth_bendingStiffness", "ignored: clothBendingMethod 0 has no bending"},
      {R"({"Simulation": {"solidSimulationMethod": 5, "solid_poissonRatio": 0.2},
          "TetModels": [{"nodeFile": "../meshes/tet.node", "eleFile": "../meshes/tet.ele"}]})",
       "Simulation.solid_poissonRatio", "ignored: solidSimulationMethod 5 does not use it"},
  };
}

TEST(SceneLoaderWarnings, EachCaseWarnsAtItsPath) {
  for (const WarningCase& c : warningCases()) {
    const LoadedScene loaded = parse(c.json);
    const SceneDiagnostic* warning = warningAt(loaded, c.path);
    ASSERT_NE(warning, nullptr) << c.path << " not warned for " << c.json << "\n"
                                << allWarnings(loaded);
    EXPECT_EQ(warning->file, kInline);
    EXPECT_TRUE(containsAll(warning->message, {c.message}));
  }
}

TEST(SceneLoaderWarnings, WarnedValuesAreHandledAsDocumented) {
  // Unknown and stale keys change nothing.
  EXPECT_EQ(parse(R"({"Simulation": {"maxIter": 4}})").scene.simulation.maxIterations, 1);
  // `gravity` is ignored, as the seed ignores it (its CarScene.json gives [0, -2, 0] and falls
  // at -9.81): alone it leaves the default, with `gravitation` that one holds.
  EXPECT_EQ(parse(R"({"Simulation": {"gravity": [0, -2, 0]}})").scene.simulation.gravitation,
            Vector3(0, Real(-9.81), 0));
  EXPECT_EQ(parse(R"({"Simulation": {"gravity": [0, -2, 0], "gravitation": [0, -1, 0]}})")
                .scene.simulation.gravitation,
            Vector3(0, -1, 0));
  // A single rotation key: no rotation.
  EXPECT_TRUE(parse(R"({"RigidBodies": [{"collisionObjectType": 1, "rotationAngle": 1}]})")
                  .scene.rigidBodies[0]
                  .rotation.isApprox(Quaternion::Identity()));
  // target + targetSequence: the constant target, no sequence; angles clamped to ±π.
  const std::string motor = "{" + kTwoBodies + R"(, "TargetAngleMotorHingeJoints": [{"bodyID1":
      1, "bodyID2": 2, "position": [0, 0, 0], "axis": [1, 0, 0], )";
  const MotorTarget both =
      parse(motor + R"("target": 0.5, "targetSequence": [0, 1, 2, 3]}]})").scene.joints[0].target;
  EXPECT_EQ(both.constant, Real(0.5));
  EXPECT_FALSE(both.hasSequence());
  EXPECT_EQ(parse(motor + R"("target": 4}]})").scene.joints[0].target.constant, kPi);
  EXPECT_EQ(parse(motor + R"("targetSequence": [0, 1, 2, -4]}]})").scene.joints[0].target.values,
            (std::vector<Real>{1, -kPi}));
  // The particle joint sits at its particle whatever `position` says.
  const LoadedScene particle = parse(R"({"RigidBodies": [{"id": 2, "collisionObjectType": 1}],
      "TriangleModels": [{"geometryFile": "../meshes/plane_3x3.obj"}],
      "RigidBodyParticleBallJoints": [{"rbID": 2, "particleID": 8, "position": [0, 0, 0]}]})");
  EXPECT_EQ(particle.scene.joints[0].position, Vector3(1, 0, 1));
  // Duplicate JSON keys: the last one wins, as in the seed.
  EXPECT_EQ(parse(R"({"Name": "a", "Name": "b"})").scene.name, "b");
}

TEST(SceneLoaderWarnings, StrictModeTurnsEachWarningIntoAnError) {
  LoadOptions strict;
  strict.strict = true;
  for (const WarningCase& c : warningCases()) {
    try {
      parse(c.json, strict);
      ADD_FAILURE() << "strict mode did not reject " << c.json;
    } catch (const SceneError& e) {
      EXPECT_EQ(e.diagnostic().jsonPath, c.path);
      EXPECT_TRUE(containsAll(e.what(), {"inline.json: ", c.message}));
    }
  }
  // A clean scene is accepted in strict mode.
  EXPECT_NO_THROW(loadScene(std::string(PBDVAL_SOURCE_DIR) + "/cases/cloth_hanging.json", strict));
}

}  // namespace
}  // namespace pbd

// --- Contact materials (extension) ----------------------------------------------------------
namespace pbd {
namespace {

const char* kTwoPrimitives = R"({
  "Simulation": {"contactCombineRule": "%RULE%"},
  "RigidBodies": [
    {"id": 1, "collisionObjectType": 1, "collisionObjectScale": [0.5, 0.5, 0.5], "friction": 0.3, "restitution": 0.5},
    {"id": 2, "collisionObjectType": 2, "collisionObjectScale": [1, 1, 1], "friction": 0.1, "restitution": 0.8},
    {"id": 3, "collisionObjectType": 2, "collisionObjectScale": [1, 1, 1], "friction": 0.6, "restitution": 0.2}
  ],
  "ContactPairs": [ {"bodyID1": 3, "bodyID2": 1, "friction": 0.9} ]
})";

Scene sceneWithRule(const std::string& rule) {
  std::string text = kTwoPrimitives;
  text.replace(text.find("%RULE%"), 6, rule);
  return parseScene(text, "/tmp/rules.json").scene;
}

TEST(ContactMaterial, RulesCombineAsNamed) {
  // Bodies 0 (μ 0.3, e 0.5) and 1 (μ 0.1, e 0.8).
  struct Expected {
    const char* rule;
    Real friction, restitution;
  };
  for (const Expected& x :
       {Expected{"seed", 0.4, 0.4}, Expected{"product", 0.03, 0.4}, Expected{"average", 0.2, 0.65},
        Expected{"min", 0.1, 0.5}, Expected{"max", 0.3, 0.8}}) {
    const ContactMaterial m = sceneWithRule(x.rule).pairMaterial(0, 1);
    EXPECT_NEAR(m.friction, x.friction, 1e-6) << x.rule;  // float-exact decimal inputs
    EXPECT_NEAR(m.restitution, x.restitution, 1e-6) << x.rule;
    const ContactMaterial swapped = sceneWithRule(x.rule).pairMaterial(1, 0);
    EXPECT_EQ(m.friction, swapped.friction) << x.rule;  // symmetric
  }
}

TEST(ContactMaterial, ExplicitPairOverridesOnlyItsValues) {
  const Scene s = sceneWithRule("seed");
  const ContactMaterial m = s.pairMaterial(0, 2);  // ContactPairs gives friction 0.9 only
  EXPECT_NEAR(m.friction, 0.9, 1e-6);
  EXPECT_NEAR(m.restitution, 0.5 * 0.2, 1e-6);  // restitution by the seed rule
}

TEST(ContactMaterial, BadRuleAndPairsAreLocatedErrors) {
  auto message = [](const std::string& text) {
    try {
      parseScene(text, "/tmp/bad.json");
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  std::string text = kTwoPrimitives;
  text.replace(text.find("%RULE%"), 6, "sum");
  EXPECT_NE(message(text).find("Simulation.contactCombineRule: expected one of"), std::string::npos)
      << message(text);
  std::string pairs = kTwoPrimitives;
  pairs.replace(pairs.find("%RULE%"), 6, "seed");
  const std::string missingValue =
      std::string(pairs).replace(pairs.find(", \"friction\": 0.9"), 17, "");
  EXPECT_NE(message(missingValue).find("ContactPairs[0]: a contact pair needs"), std::string::npos)
      << message(missingValue);
  const std::string unknownBody =
      std::string(pairs).replace(pairs.find("\"bodyID1\": 3"), 12, "\"bodyID1\": 9");
  EXPECT_NE(message(unknownBody).find("ContactPairs[0].bodyID1"), std::string::npos)
      << message(unknownBody);
}

// A NUL byte anywhere in the scene text is an error naming the file and the byte offset
// (issue 25): before, the bytes after a NUL that followed the closing brace were accepted.
TEST(SceneLoader, NulByteIsAnErrorNamingTheFileAndOffset) {
  const std::string valid = R"({"Name": "nul"})";
  for (const std::size_t offset : {valid.size(), std::size_t(3)}) {
    std::string text = valid;
    text.insert(offset, 1, '\0');
    const std::string error = errorOf(text);
    EXPECT_TRUE(containsAll(error, {kInline, "NUL byte", "byte offset " + std::to_string(offset)}))
        << error;
  }
}

// Physical ranges checked at load (issue 25, docs/scene-format.md#ranges): each error names the
// file, the JSON path and the range. Every value here was accepted before (an angular velocity
// of 1e300 ran "ok" with a zero quaternion).
TEST(SceneLoaderRanges, OutOfRangeValuesAreErrorsNamingThePathAndTheRange) {
  struct Case {
    const char* json;
    std::vector<std::string> expected;
  };
  const std::string body = R"({"RigidBodies": [{"collisionObjectType": 2, )";
  const std::vector<Case> cases = {
      {R"("angularVelocity": [0, 1e300, 0]}]})",
       {"RigidBodies[0].angularVelocity", "[-1000000, 1000000]"}},
      {R"("velocity": [2e6, 0, 0]}]})", {"RigidBodies[0].velocity", "[-1000000, 1000000]"}},
      {R"("translation": [0, -1e7, 0]}]})", {"RigidBodies[0].translation", "[-1000000, 1000000]"}},
      {R"("mass": 1e-300, "inertia": [1, 1, 1]}]})", {"RigidBodies[0].mass", "[1e-12, 1e+12]"}},
      {R"("mass": 1e300, "inertia": [1, 1, 1]}]})", {"RigidBodies[0].mass", "[1e-12, 1e+12]"}},
      // A 1 m box of density 1e13 kg/m³: the computed mass is out of range.
      {R"("density": 1e13}]})", {"RigidBodies[0].density", "1e+13 kg", "[1e-12, 1e+12] kg"}},
      {R"("resolutionSDF": [10, 100000, 10]}]})", {"RigidBodies[0].resolutionSDF", "[1, 512]"}},
  };
  // (gravitation 1e308 made ODE fail an assertion inside the first step: the simulate fuzz target)
  EXPECT_TRUE(containsAll(errorOf(R"({"Simulation": {"gravitation": [0, 1e308, 0]}})"),
                          {"inline.json", "Simulation.gravitation", "[-1000000, 1000000]"}));
  EXPECT_NO_THROW(parse(R"({"Simulation": {"gravitation": [1e6, -1e6, 0]}})"));
  for (const Case& c : cases) {
    const std::string error = errorOf(body + c.json);
    for (const std::string& part : c.expected)
      EXPECT_NE(error.find(part), std::string::npos)
          << c.json << ": '" << part << "' not in " << error;
    EXPECT_NE(error.find("inline.json"), std::string::npos) << error;
  }
  // The bounds themselves are accepted.
  EXPECT_NO_THROW(parse(body + R"("velocity": [1e6, -1e6, 0], "angularVelocity": [0, 0, 1e6],
      "translation": [1e6, 0, -1e6], "mass": 1e-12, "inertia": [1, 1, 1]}]})"));
}

// A degenerate element relative to the model's size is an error naming the model, the element
// index and the bound (issue 25: a flat tet's centre of mass drifted 4 mm in 0.5 s).
TEST(SceneLoaderRanges, DegenerateElementsAreErrorsNamingTheModelAndElement) {
  EXPECT_TRUE(containsAll(errorOf(R"({"TetModels": [{"nodeFile": "../meshes/flat_tet.node",
                                 "eleFile": "../meshes/flat_tet.ele"}]})"),
                          {"inline.json", "TetModels[0].eleFile", "tet 1 ", "1e-12 L^3"}));
  EXPECT_TRUE(containsAll(
      errorOf(R"({"TriangleModels": [{"geometryFile": "../meshes/degenerate_triangle.obj"}]})"),
      {"inline.json", "TriangleModels[0].geometryFile", "triangle 1 ", "1e-12 L^2"}));
  // The regular meshes load.
  EXPECT_NO_THROW(parse(R"({"TetModels": [{"nodeFile": "../meshes/tet.node",
                                          "eleFile": "../meshes/tet.ele"}],
                           "TriangleModels": [{"geometryFile": "../meshes/plane_3x3.obj"}]})"));
}

}  // namespace
}  // namespace pbd
