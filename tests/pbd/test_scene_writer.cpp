// The scene writer against the loader (pbd/io/scene_writer.h): a Scene written back loads to the
// same Scene, field by field, for every scene file of the repository and for a few hundred
// random scenes (a property test with fixed seeds). Exact equality everywhere but the joints'
// unit axes, which the loader normalises again: a unit vector divided by its own computed norm
// moves by at most a few ulp (the norm of a unit vector is 1 within 2 ulp; one division adds
// half an ulp), so they are compared to 8 ε.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "pbd/io/scene_loader.h"
#include "pbd/io/scene_writer.h"

namespace pbd {
namespace {

namespace fs = std::filesystem;

constexpr Real kUnitAxisTolerance = 8 * kEpsilon;  // see the file's header

#define EXPECT_VEC_EQ(a, b, what) \
  EXPECT_TRUE((a) == (b)) << (what) << ": " << (a).transpose() << " vs " << (b).transpose()

void expectSameQuaternion(const Quaternion& a, const Quaternion& b, const std::string& what) {
  EXPECT_TRUE(a.coeffs() == b.coeffs())
      << what << ": " << a.coeffs().transpose() << " vs " << b.coeffs().transpose();
}

void expectSameMesh(const TriangleMesh* a, const TriangleMesh* b, const std::string& what) {
  ASSERT_EQ(a == nullptr, b == nullptr) << what;
  if (!a) return;
  ASSERT_EQ(a->vertices.size(), b->vertices.size()) << what;
  ASSERT_EQ(a->triangles.size(), b->triangles.size()) << what;
  for (std::size_t i = 0; i < a->vertices.size(); ++i)
    EXPECT_VEC_EQ(a->vertices[i], b->vertices[i], what);
  for (std::size_t i = 0; i < a->triangles.size(); ++i)
    EXPECT_TRUE(a->triangles[i] == b->triangles[i]) << what;
}

void expectSameCollision(const CollisionObjectDesc& a, const CollisionObjectDesc& b,
                         const std::string& what) {
  EXPECT_EQ(a.type, b.type) << what;
  EXPECT_EQ(a.fileName, b.fileName) << what;
  expectSameMesh(a.mesh.get(), b.mesh.get(), what + ".collision mesh");
  EXPECT_EQ(a.testMesh, b.testMesh) << what;
  EXPECT_VEC_EQ(a.scale, b.scale, what + ".collisionObjectScale");
  EXPECT_EQ(a.invertSDF, b.invertSDF) << what;
  EXPECT_EQ(a.thicknessSDF, b.thicknessSDF) << what;
  EXPECT_TRUE(a.resolutionSDF == b.resolutionSDF) << what;
}

void expectSameUnitAxis(const Vector3& a, const Vector3& b, const std::string& what) {
  EXPECT_LE((a - b).cwiseAbs().maxCoeff(), kUnitAxisTolerance) << what;
}

/// Every field of scene.h but sourceFile.
void expectSameScene(const Scene& a, const Scene& b) {
  EXPECT_EQ(a.name, b.name);
  const SimulationSettings &s = a.simulation, &t = b.simulation;
  EXPECT_EQ(s.timeStepSize, t.timeStepSize);
  EXPECT_VEC_EQ(s.gravitation, t.gravitation, "gravitation");
  EXPECT_EQ(s.subSteps, t.subSteps);
  EXPECT_EQ(s.maxIterations, t.maxIterations);
  EXPECT_EQ(s.maxIterationsV, t.maxIterationsV);
  EXPECT_EQ(s.velocityUpdateMethod, t.velocityUpdateMethod);
  EXPECT_EQ(s.contactTolerance, t.contactTolerance);
  EXPECT_EQ(s.contactStiffnessRigidBody, t.contactStiffnessRigidBody);
  EXPECT_EQ(s.contactStiffnessParticleRigidBody, t.contactStiffnessParticleRigidBody);
  EXPECT_EQ(s.contactCombineRule, t.contactCombineRule);
  EXPECT_EQ(s.contactModel, t.contactModel);
  EXPECT_EQ(s.distanceGrid, t.distanceGrid);
  EXPECT_EQ(s.clothSimulationMethod, t.clothSimulationMethod);
  EXPECT_EQ(s.clothBendingMethod, t.clothBendingMethod);
  for (auto member :
       {&SimulationSettings::cloth_stiffness, &SimulationSettings::solid_stiffness,
        &SimulationSettings::solid_volumeStiffness, &SimulationSettings::cloth_bendingStiffness})
    EXPECT_EQ(s.*member, t.*member);  // optional: unset stays unset
  for (auto member :
       {&SimulationSettings::cloth_xxStiffness, &SimulationSettings::cloth_yyStiffness,
        &SimulationSettings::cloth_xyStiffness, &SimulationSettings::cloth_xyPoissonRatio,
        &SimulationSettings::cloth_yxPoissonRatio, &SimulationSettings::solid_poissonRatio,
        &SimulationSettings::rod_stretchingStiffness, &SimulationSettings::rod_shearingStiffnessX,
        &SimulationSettings::rod_shearingStiffnessY, &SimulationSettings::rod_bendingStiffnessX,
        &SimulationSettings::rod_bendingStiffnessY, &SimulationSettings::rod_twistingStiffness})
    EXPECT_EQ(s.*member, t.*member);
  for (auto member :
       {&SimulationSettings::cloth_normalizeStretch, &SimulationSettings::cloth_normalizeShear,
        &SimulationSettings::solid_normalizeStretch, &SimulationSettings::solid_normalizeShear})
    EXPECT_EQ(s.*member, t.*member);
  EXPECT_EQ(s.solidSimulationMethod, t.solidSimulationMethod);

  const ViewerSettings &v = a.viewer, &w = b.viewer;
  EXPECT_EQ(v.pause, w.pause);
  EXPECT_EQ(v.pauseAt, w.pauseAt);
  EXPECT_EQ(v.numberOfStepsPerRenderUpdate, w.numberOfStepsPerRenderUpdate);
  for (auto member :
       {&ViewerSettings::renderTets, &ViewerSettings::renderTets0, &ViewerSettings::renderContacts,
        &ViewerSettings::renderAABB, &ViewerSettings::renderSDF, &ViewerSettings::exportOBJ,
        &ViewerSettings::exportPLY})
    EXPECT_EQ(v.*member, w.*member);
  EXPECT_EQ(v.renderBVHDepth, w.renderBVHDepth);
  EXPECT_EQ(v.renderBVHDepthTets, w.renderBVHDepthTets);
  EXPECT_EQ(v.exportFPS, w.exportFPS);
  EXPECT_VEC_EQ(v.cameraPosition, w.cameraPosition, "cameraPosition");
  EXPECT_VEC_EQ(v.cameraLookat, w.cameraLookat, "cameraLookat");

  ASSERT_EQ(a.rigidBodies.size(), b.rigidBodies.size());
  for (std::size_t i = 0; i < a.rigidBodies.size(); ++i) {
    const RigidBodyDesc &x = a.rigidBodies[i], &y = b.rigidBodies[i];
    const std::string what = x.jsonPath;
    EXPECT_EQ(x.id, y.id) << what;
    EXPECT_EQ(x.jsonPath, y.jsonPath);
    EXPECT_EQ(x.isDynamic, y.isDynamic) << what;
    EXPECT_EQ(x.density, y.density) << what;
    EXPECT_EQ(x.geometryFile, y.geometryFile) << what;
    expectSameMesh(x.mesh.get(), y.mesh.get(), what + " mesh");
    EXPECT_VEC_EQ(x.translation, y.translation, what + ".translation");
    expectSameQuaternion(x.rotation, y.rotation, what + " rotation");
    EXPECT_VEC_EQ(x.scale, y.scale, what + ".scale");
    EXPECT_VEC_EQ(x.velocity, y.velocity, what + ".velocity");
    EXPECT_VEC_EQ(x.angularVelocity, y.angularVelocity, what + ".angularVelocity");
    EXPECT_EQ(x.restitution, y.restitution) << what;
    EXPECT_EQ(x.friction, y.friction) << what;
    EXPECT_EQ(x.flatShading, y.flatShading) << what;
    expectSameCollision(x.collision, y.collision, what);
    EXPECT_EQ(x.massProperties.mass, y.massProperties.mass) << what;
    EXPECT_VEC_EQ(x.massProperties.centerOfMass, y.massProperties.centerOfMass,
                  what + " centre of mass");
    EXPECT_VEC_EQ(x.massProperties.principalInertia, y.massProperties.principalInertia,
                  what + " inertia");
    expectSameQuaternion(x.massProperties.principalRotation, y.massProperties.principalRotation,
                         what + " principal frame");
    EXPECT_EQ(x.givenMass, y.givenMass) << what;
    EXPECT_EQ(x.givenInertia.has_value(), y.givenInertia.has_value()) << what;
  }

  ASSERT_EQ(a.joints.size(), b.joints.size());
  for (std::size_t i = 0; i < a.joints.size(); ++i) {
    const JointDesc &x = a.joints[i], &y = b.joints[i];
    const std::string what = x.jsonPath;
    EXPECT_EQ(x.type, y.type) << what;
    EXPECT_EQ(x.jsonPath, y.jsonPath);
    EXPECT_EQ(x.bodyId1, y.bodyId1) << what;
    EXPECT_EQ(x.bodyId2, y.bodyId2) << what;
    EXPECT_EQ(x.body1, y.body1) << what;
    EXPECT_EQ(x.body2, y.body2) << what;
    EXPECT_EQ(x.particle, y.particle) << what;
    EXPECT_VEC_EQ(x.position, y.position, what + ".position");
    EXPECT_VEC_EQ(x.position1, y.position1, what + ".position1");
    EXPECT_VEC_EQ(x.position2, y.position2, what + ".position2");
    expectSameUnitAxis(x.axis, y.axis, what + ".axis");
    expectSameUnitAxis(x.axis1, y.axis1, what + ".axis1");
    expectSameUnitAxis(x.axis2, y.axis2, what + ".axis2");
    EXPECT_EQ(x.stiffness, y.stiffness) << what;
    EXPECT_EQ(x.target.constant, y.target.constant) << what;
    EXPECT_EQ(x.target.times, y.target.times) << what;
    EXPECT_EQ(x.target.values, y.target.values) << what;
    EXPECT_EQ(x.target.repeat, y.target.repeat) << what;
  }

  ASSERT_EQ(a.triangleModels.size(), b.triangleModels.size());
  for (std::size_t i = 0; i < a.triangleModels.size(); ++i) {
    const TriangleModelDesc &x = a.triangleModels[i], &y = b.triangleModels[i];
    EXPECT_EQ(x.id, y.id);
    EXPECT_EQ(x.geometryFile, y.geometryFile);
    expectSameMesh(&x.mesh, &y.mesh, x.jsonPath);
    EXPECT_VEC_EQ(x.translation, y.translation, x.jsonPath);
    expectSameQuaternion(x.rotation, y.rotation, x.jsonPath);
    EXPECT_VEC_EQ(x.scale, y.scale, x.jsonPath);
    EXPECT_EQ(x.staticParticles, y.staticParticles);
    EXPECT_EQ(x.restitution, y.restitution);
    EXPECT_EQ(x.friction, y.friction);
    EXPECT_EQ(x.density, y.density);
    EXPECT_EQ(x.firstParticle, y.firstParticle);
  }
  ASSERT_EQ(a.tetModels.size(), b.tetModels.size());
  for (std::size_t i = 0; i < a.tetModels.size(); ++i) {
    const TetModelDesc &x = a.tetModels[i], &y = b.tetModels[i];
    EXPECT_EQ(x.id, y.id);
    EXPECT_EQ(x.nodeFile, y.nodeFile);
    EXPECT_EQ(x.eleFile, y.eleFile);
    EXPECT_EQ(x.visFile, y.visFile);
    ASSERT_EQ(x.mesh.vertices.size(), y.mesh.vertices.size());
    for (std::size_t k = 0; k < x.mesh.vertices.size(); ++k)
      EXPECT_VEC_EQ(x.mesh.vertices[k], y.mesh.vertices[k], x.jsonPath);
    expectSameMesh(x.visMesh.get(), y.visMesh.get(), x.jsonPath + " visual mesh");
    expectSameQuaternion(x.rotation, y.rotation, x.jsonPath);
    EXPECT_EQ(x.staticParticles, y.staticParticles);
    EXPECT_EQ(x.restitution, y.restitution);
    EXPECT_EQ(x.friction, y.friction);
    expectSameCollision(x.collision, y.collision, x.jsonPath);
    EXPECT_EQ(x.density, y.density);
    EXPECT_EQ(x.firstParticle, y.firstParticle);
  }
  ASSERT_EQ(a.fluidModels.size(), b.fluidModels.size());
  for (std::size_t i = 0; i < a.fluidModels.size(); ++i) {
    const FluidModelDesc &x = a.fluidModels[i], &y = b.fluidModels[i];
    EXPECT_EQ(x.particleRadius, y.particleRadius);
    EXPECT_EQ(x.density0, y.density0);
    EXPECT_EQ(x.viscosity, y.viscosity);
    EXPECT_EQ(x.iterations, y.iterations);
    ASSERT_EQ(x.blocks.size(), y.blocks.size());
    for (std::size_t k = 0; k < x.blocks.size(); ++k) {
      EXPECT_VEC_EQ(x.blocks[k].min, y.blocks[k].min, x.jsonPath);
      EXPECT_VEC_EQ(x.blocks[k].max, y.blocks[k].max, x.jsonPath);
    }
    ASSERT_EQ(x.container.has_value(), y.container.has_value());
    if (x.container) {
      EXPECT_VEC_EQ(x.container->min, y.container->min, x.jsonPath);
      EXPECT_VEC_EQ(x.container->max, y.container->max, x.jsonPath);
    }
    EXPECT_EQ(x.firstParticle, y.firstParticle);
    EXPECT_EQ(x.particleCount, y.particleCount);
    EXPECT_EQ(x.formulation, y.formulation);
    ASSERT_EQ(x.particles.size(), y.particles.size());
    for (std::size_t k = 0; k < x.particles.size(); ++k)
      EXPECT_VEC_EQ(x.particles[k], y.particles[k], x.jsonPath);
    ASSERT_EQ(x.boundaryWalls.size(), y.boundaryWalls.size());
    for (std::size_t k = 0; k < x.boundaryWalls.size(); ++k) {
      EXPECT_VEC_EQ(x.boundaryWalls[k].min, y.boundaryWalls[k].min, x.jsonPath);
      EXPECT_VEC_EQ(x.boundaryWalls[k].max, y.boundaryWalls[k].max, x.jsonPath);
    }
  }
  ASSERT_EQ(a.particles.size(), b.particles.size());
  for (std::size_t i = 0; i < a.particles.size(); ++i) {
    EXPECT_VEC_EQ(a.particles[i].position, b.particles[i].position, "particle");
    EXPECT_VEC_EQ(a.particles[i].velocity, b.particles[i].velocity, "particle");
    EXPECT_EQ(a.particles[i].mass, b.particles[i].mass);
  }
  ASSERT_EQ(a.contactPairs.size(), b.contactPairs.size());
  for (std::size_t i = 0; i < a.contactPairs.size(); ++i) {
    const ContactPairDesc &x = a.contactPairs[i], &y = b.contactPairs[i];
    EXPECT_EQ(x.bodyId1, y.bodyId1);
    EXPECT_EQ(x.bodyId2, y.bodyId2);
    EXPECT_EQ(x.body1, y.body1);
    EXPECT_EQ(x.body2, y.body2);
    EXPECT_EQ(x.hasFriction, y.hasFriction);
    EXPECT_EQ(x.hasRestitution, y.hasRestitution);
    EXPECT_EQ(x.friction, y.friction);
    EXPECT_EQ(x.restitution, y.restitution);
  }
  EXPECT_EQ(a.validationJson, b.validationJson);
}

/// Loads `text` as if it were `path` (relative mesh paths resolve from its folder), writes it,
/// loads the written text and compares.
void expectRoundTrip(const std::string& text, const std::string& path) {
  const Scene original = parseScene(text, path).scene;
  const std::string written = writeSceneJson(original);
  SCOPED_TRACE(written.substr(0, 4000));
  const Scene reloaded = parseScene(written, path).scene;
  expectSameScene(original, reloaded);
  // Written twice, the same text: nothing drifts on a second round (axes included: a unit
  // vector normalised again is a fixed point after the first round or moves by an ulp).
  EXPECT_EQ(writeSceneJson(parseScene(writeSceneJson(reloaded), path).scene),
            writeSceneJson(reloaded));
}

std::string fileText(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(SceneWriter, EverySceneFileOfTheRepositoryRoundTrips) {
  std::vector<fs::path> files;
  for (const char* folder : {"cases", "tests/data/scenes", "tests/data/seed_reference/scenes"})
    for (const auto& entry : fs::directory_iterator(fs::path(PBDVAL_SOURCE_DIR) / folder))
      if (entry.path().extension() == ".json") files.push_back(entry.path());
  ASSERT_GT(files.size(), 60u);  // 39 cases, the loader's scenes and the seed recordings' scenes
  for (const fs::path& file : files) {
    SCOPED_TRACE(file.string());
    expectRoundTrip(fileText(file), file.string());
  }
}

// ---- the property test: random valid scenes ---------------------------------------------------

class RandomScene {
 public:
  explicit RandomScene(unsigned seed) : random_(seed) {}

  std::string json() {
    std::ostringstream o;
    o.precision(17);
    o << "{\"Name\": \"random\", \"Simulation\": {";
    o << "\"timeStepSize\": " << uniform(1e-4, 0.02) << ", \"subSteps\": " << integer(1, 8)
      << ", \"maxIterations\": " << integer(1, 6) << ", \"maxIterationsV\": " << integer(0, 6)
      << ", \"velocityUpdateMethod\": " << integer(0, 1)
      << ", \"contactTolerance\": " << uniform(0, 0.05)
      << ", \"contactStiffnessRigidBody\": " << uniform(0, 10)
      << ", \"gravitation\": " << vector(-10, 10) << ", \"contactCombineRule\": \""
      << pick({"seed", "product", "average", "min", "max"}) << "\", \"contactModel\": \""
      << pick({"seed", "corrected"}) << "\", \"distanceGrid\": \""
      << pick({"cubicLagrange", "catmullRom"}) << "\", \"pauseAt\": " << uniform(-1, 5)
      << ", \"exportFPS\": " << uniform(1, 60) << ", \"cloth_stiffness\": " << uniform(0, 2)
      << ", \"solid_poissonRatio\": " << uniform(0, 0.49)
      << ", \"renderAABB\": " << pick({"true", "false"}) << "}, \"RigidBodies\": [";
    const int bodies = integer(2, 6);
    for (int b = 0; b < bodies; ++b) {
      if (b) o << ", ";
      o << "{\"id\": " << 10 + b << ", \"isDynamic\": " << (b == 0 ? "false" : "true")
        << ", \"density\": " << uniform(0.1, 3000) << ", \"translation\": " << vector(-5, 5)
        << ", \"velocity\": " << vector(-2, 2) << ", \"angularVelocity\": " << vector(-3, 3)
        << ", \"restitution\": " << uniform(0, 1) << ", \"friction\": " << uniform(0, 1)
        << ", \"collisionObjectType\": " << integer(1, 3)
        << ", \"collisionObjectScale\": " << vector(0.1, 2);
      if (integer(0, 1))
        o << ", \"rotationAxis\": " << vector(-1, 1) << ", \"rotationAngle\": " << uniform(-6, 6);
      if (integer(0, 3) == 0) o << ", \"mass\": " << uniform(0.5, 5);
      if (integer(0, 3) == 0)
        o << ", \"mass\": " << uniform(0.5, 5) << ", \"inertia\": [1, 1.5, 2]";
      o << "}";
    }
    o << ", {\"id\": 99, \"geometryFile\": \"" << PBDVAL_SOURCE_DIR
      << "/cases/models/cube.obj\", \"scale\": " << vector(0.2, 1.5)
      << ", \"collisionObjectType\": 5, \"resolutionSDF\": [" << integer(4, 12) << ", "
      << integer(4, 12) << ", " << integer(4, 12) << "], \"thicknessSDF\": " << uniform(0, 0.2)
      << ", \"invertSDF\": " << pick({"true", "false"}) << "}]";
    o << ", \"TriangleModels\": [{\"id\": 5, \"geometryFile\": \"" << PBDVAL_SOURCE_DIR
      << "/cases/models/triangle.obj\", \"translation\": " << vector(-1, 1)
      << ", \"staticParticles\": [0]"
      << (integer(0, 1) ? ", \"density\": " + std::to_string(uniform(0.1, 3)) : std::string())
      << "}]";
    o << ", \"TetModels\": [{\"id\": 6, \"nodeFile\": \"" << PBDVAL_SOURCE_DIR
      << "/tests/data/meshes/tet.node\", "
      << "\"eleFile\": \"" << PBDVAL_SOURCE_DIR
      << "/tests/data/meshes/tet.ele\", \"rotationAxis\": " << vector(0.1, 1)
      << ", \"rotationAngle\": " << uniform(-3, 3) << ", \"friction\": " << uniform(0, 1) << "}]";
    o << ", \"ContactPairs\": [{\"bodyID1\": 10, \"bodyID2\": 11, \"friction\": " << uniform(0, 1)
      << "}]";
    // Joints between bodies 10 + a and 10 + a + 1, of every two-body type.
    const char* blocks[] = {"BallJoints",
                            "BallOnLineJoints",
                            "HingeJoints",
                            "UniversalJoints",
                            "SliderJoints",
                            "RigidBodySprings",
                            "DistanceJoints",
                            "DamperJoints",
                            "TargetAngleMotorHingeJoints",
                            "TargetVelocityMotorHingeJoints",
                            "TargetPositionMotorSliderJoints",
                            "TargetVelocityMotorSliderJoints"};
    for (const char* block : blocks) {
      const std::string name = block;
      const int a = integer(0, bodies - 2);
      o << ", \"" << name << "\": [{\"bodyID1\": " << 10 + a << ", \"bodyID2\": " << 11 + a;
      o << ", \"position\": " << vector(-2, 2) << ", \"axis\": " << vector(0.2, 1);
      o << ", \"position1\": [0, 0, 0], \"position2\": " << vector(0.5, 1.5);
      o << ", \"axis1\": [1, 0, 0], \"axis2\": [0, " << uniform(0.1, 2) << ", 0]";
      o << ", \"stiffness\": " << uniform(1, 1000);
      if (name.find("Motor") != std::string::npos) {
        if (integer(0, 1))
          o << ", \"target\": " << uniform(-3, 3);
        else
          o << ", \"targetSequence\": [0, " << uniform(-3, 3) << ", " << uniform(0.1, 1) << ", "
            << uniform(-3, 3) << "], \"repeatSequence\": " << pick({"true", "false"});
      }
      o << "}]";
    }
    o << ", \"RigidBodyParticleBallJoints\": [{\"rbID\": 11, \"particleID\": 1}]";
    o << ", \"Validation\": {\"duration\": " << uniform(0.1, 3) << ", \"schema\": 1}}";
    return o.str();
  }

 private:
  double uniform(double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(random_);
  }
  int integer(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(random_); }
  std::string vector(double lo, double hi) {
    std::ostringstream o;
    o.precision(17);
    o << "[" << uniform(lo, hi) << ", " << uniform(lo, hi) << ", " << uniform(lo, hi) << "]";
    return o.str();
  }
  const char* pick(std::initializer_list<const char*> options) {
    return *(options.begin() + integer(0, int(options.size()) - 1));
  }
  std::mt19937 random_;
};

TEST(SceneWriter, RandomScenesRoundTrip) {
  // Keys a joint type does not take are unknown to it: warnings, never errors (not strict).
  for (unsigned seed = 1; seed <= 300; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const std::string text = RandomScene(seed).json();
    Scene original;
    try {
      original = parseScene(text, "random.json").scene;
    } catch (const SceneError& e) {
      FAIL() << "the generator made an invalid scene: " << e.what();
    }
    expectSameScene(original, parseScene(writeSceneJson(original), "random.json").scene);
  }
}

TEST(SceneWriter, NothingIsWrittenThatTheLoaderWouldWarnAbout) {
  // A written scene holds only keys its blocks take: loading it in strict mode (every warning an
  // error) succeeds for a scene that itself loads without warnings.
  const fs::path file = fs::path(PBDVAL_SOURCE_DIR) / "cases" / "car.json";
  LoadOptions strict;
  strict.strict = true;
  const Scene scene = loadScene(file.string(), strict).scene;
  EXPECT_NO_THROW(parseScene(writeSceneJson(scene), file.string(), strict));
}

}  // namespace
}  // namespace pbd
