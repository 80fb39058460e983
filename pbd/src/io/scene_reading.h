// Private to the scene loader: the readers of the scene blocks and what they share (file
// resolution, the mesh cache, the pose and collision keys).
#pragma once

#include <array>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "json_reader.h"
#include "pbd/model/scene.h"

namespace pbd::scene_io {

// ---- physical ranges checked at load (docs/scene-format.md#ranges) --------------------------
// Beyond them results stop being finite or meaningful in double precision; each is checked with
// the key's JSON path.

/// |x| of a position component (m): the runner counts positions beyond 10⁶ m as a blow-up
/// (validation/run/simulation.h, kDivergenceLimit), and there double's spacing is 1.2·10⁻¹⁰ m, the
/// scale of the contact sinks the methods resolve (g h_s² = 6·10⁻⁷ m at h_s = 0.25 ms).
inline constexpr double kMaxCoordinate = 1e6;
/// |v| of a velocity component (m/s): the runner's blow-up limit for speeds (kDivergenceLimit).
inline constexpr double kMaxSpeed = 1e6;
/// |ω| of an angular-velocity component (rad/s): 10⁶ rad/s turns a body by 800 revolutions per
/// 5 ms step, and a point 1 m out moves at the blow-up speed limit; at 10³⁰⁰ the quaternion
/// update ½ h ω ⊗ q overflows and normalises to zero.
inline constexpr double kMaxAngularSpeed = 1e6;
/// |g| of a gravitation component (m/s²): 10⁶ m/s² (10⁵ g) takes a body from rest to the
/// blow-up speed (kMaxSpeed) in 1 s. At 10³⁰⁸ ODE's quaternion normalisation failed inside the
/// first step (found by the `simulate` fuzz target; docs/fuzzing.md).
inline constexpr double kMaxGravitation = 1e6;
/// A dynamic rigid body's mass (kg), given or computed: 10⁻¹² kg (a 10 µm dust grain) to
/// 10¹² kg (a mountain). Within it 1/m, m v² and m L² stay finite and well inside double's
/// range for the speeds and sizes above; masses like 10⁻³⁰⁰ or 10³⁰⁰ overflow them.
inline constexpr double kMinMass = 1e-12;
inline constexpr double kMaxMass = 1e12;
/// A tet with |volume| below this fraction of L³ (a triangle: area below this fraction of L²),
/// L the model's bounding-box diagonal, is degenerate: its volume (area) gradient is round-off,
/// so the volume, FEM and strain constraints divide by nothing (a flat tet's centre of mass
/// drifted 4 mm in 0.5 s). Scale-free, far above the round-off of a regular element's volume
/// (ε L³ ≈ 2·10⁻¹⁶ L³), far below any element a mesher makes on purpose.
inline constexpr double kDegenerateElementFraction = 1e-12;

/// SDF grids (type 5) beyond this many cells per axis (or 256³ in total) would take minutes and
/// gigabytes to build.
inline constexpr int kMaxGridCellsPerAxis = 512;

/// State shared by the readers of one scene: the scene's folder and the meshes loaded so far.
class LoadContext {
 public:
  explicit LoadContext(std::filesystem::path sceneFolder);

  /// How OBJ coordinates are read from now on (Simulation.objPrecision, read first).
  void setObjPrecision(ObjPrecision precision) { objPrecision_ = precision; }

  /// The resolved path of a file key (relative paths against the scene folder); fails, naming
  /// the key, when the string is empty or the file does not exist.
  std::string existingFile(const JsonValue& fileKey) const;

  /// The OBJ at `path` scaled component-wise; each file is read once, and bodies with the same
  /// file and scale share one mesh. Mesh errors are reported at `fileKey`.
  std::shared_ptr<const TriangleMesh> scaledObj(const std::string& path, const Vector3& scale,
                                                const JsonValue& fileKey);
  /// A TetGen mesh; errors are reported at `fileKey`.
  TetMesh tetGen(const std::string& nodePath, const std::string& elePath,
                 const JsonValue& fileKey) const;

 private:
  const TriangleMesh& obj(const std::string& path, const JsonValue& fileKey);

  std::filesystem::path sceneFolder_;
  ObjPrecision objPrecision_ = ObjPrecision::Single;
  std::map<std::string, TriangleMesh> objFiles_;
  std::map<std::pair<std::string, std::array<Real, 3>>, std::shared_ptr<const TriangleMesh>>
      scaledObjs_;
};

/// The pose keys shared by rigid bodies, triangle models and tet models.
struct PoseInput {
  Vector3 translation = Vector3::Zero();
  Vector3 scale = Vector3::Ones();
  std::optional<Vector3> rotationAxis;
  std::optional<Real> rotationAngle;
  bool scaleGiven = false;
};
KeyTable<PoseInput> poseKeys();
/// The seed's rotation rule: applied only when both rotationAxis and rotationAngle are given;
/// angle 0 is the identity; otherwise the axis must be non-zero (it is normalised).
Quaternion resolveRotation(const PoseInput& pose, JsonObject& object);
/// The rotation keys as given, when both are (what resolveRotation was made from).
std::optional<GivenRotation> givenRotation(const PoseInput& pose);

/// The Simulation block's keys: the solver settings and the viewer's (each row reads its key
/// and writes it back: scene_writer.cpp).
KeyTable<SimulationSettings> simulationKeys();
KeyTable<ViewerSettings> viewerKeys();
/// Why nothing reads the cloth or solid `Simulation` setting `key` in `scene` ("the scene has no
/// TetModels", "clothSimulationMethod 1 does not use it", …), or "" when something does (and
/// for every other key).
std::string unusedModelSettingReason(const std::string& key, const Scene& scene);

/// The collision keys shared by rigid bodies and tet models.
KeyTable<CollisionObjectDesc> collisionKeys(const LoadContext& context);
/// Checks that the collisionObjectScale components the type uses are positive.
void checkCollisionScale(const CollisionObjectDesc& collision, JsonObject& object);

/// Transforms a point of a model file to the world: R · (v ∘ scale) + translation.
Vector3 toWorld(const Vector3& vertex, const Vector3& scale, const Quaternion& rotation,
                const Vector3& translation);

// The block readers, in the order parseScene calls them (joints need the bodies and particles).
void readSimulation(const JsonValue& block, Scene& scene);
void readRigidBodies(const JsonValue& block, LoadContext& context, Scene& scene);
void readTriangleModels(const JsonValue& block, LoadContext& context, Scene& scene);
void readTetModels(const JsonValue& block, LoadContext& context, Scene& scene);
/// Extension: Cosserat rods (line_model_reader.cpp); call after the tet models.
void readLineModels(const JsonValue& block, Scene& scene);
/// Warns at each rod_* key of the Simulation block when the scene has no line models.
void warnUnusedRodSettings(JsonObject& root, const Scene& scene);
/// Extension: position-based fluids; must stay the last particle block read (its particles come
/// after every other model's).
void readFluidModels(const JsonValue& block, Scene& scene);
/// FluidModels' scalar keys (read and written back).
KeyTable<FluidModelDesc> fluidModelKeys();
/// Extension: explicit friction/restitution per pair of rigid bodies.
void readContactPairs(const JsonValue& block, Scene& scene);
/// The index of the rigid body with id `idValue`'s value; fails (naming the key) when no body or
/// several bodies have that id.
int resolveBodyId(const JsonValue& idValue, const Scene& scene);
// The key groups of the joint blocks.
enum JointKeys : unsigned {
  kTwoBodies = 1u << 0,        // bodyID1, bodyID2
  kBodyAndParticle = 1u << 1,  // rbID, particleID
  kPosition = 1u << 2,         // position
  kAxis = 1u << 3,             // axis
  kTwoAxes = 1u << 4,          // axis1, axis2
  kTwoPositions = 1u << 5,     // position1, position2
  kStiffness = 1u << 6,        // stiffness
  kMotor = 1u << 7,            // target, targetSequence, repeatSequence
};

inline unsigned jointKeys(JointType type) {
  switch (type) {
    case JointType::Ball:
      return kTwoBodies | kPosition;
    case JointType::BallOnLine:
    case JointType::Hinge:
      return kTwoBodies | kPosition | kAxis;
    case JointType::Universal:
      return kTwoBodies | kPosition | kTwoAxes;
    case JointType::Slider:
      return kTwoBodies | kAxis;
    case JointType::RigidBodyParticleBall:
      return kBodyAndParticle;
    case JointType::RigidBodySpring:
      return kTwoBodies | kTwoPositions | kStiffness;
    case JointType::Distance:
      return kTwoBodies | kTwoPositions;
    case JointType::Damper:
      return kTwoBodies | kAxis | kStiffness;
    case JointType::TargetAngleMotorHinge:
    case JointType::TargetVelocityMotorHinge:
      return kTwoBodies | kPosition | kAxis | kMotor;
    case JointType::TargetPositionMotorSlider:
    case JointType::TargetVelocityMotorSlider:
      return kTwoBodies | kAxis | kMotor;
    case JointType::StiffRod:  // read by readStiffRods (stiff_rod_reader.cpp)
      return kTwoBodies | kPosition;
  }
  return 0;
}

/// Reads the 13 joint blocks of the seed's SceneLoader, in JointType order.
void readJoints(JsonObject& root, Scene& scene);
/// Reads the seed's stiff-rods blocks `CosseratJoints` (JointType::StiffRod, appended to
/// Scene::joints) and `TreeModels` (Scene::stiffRodTrees); refuses CompactTreeModels,
/// SkinningMeshes and RodAnimators.
void readStiffRods(JsonObject& root, Scene& scene);

}  // namespace pbd::scene_io
