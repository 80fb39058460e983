// loadScene / parseScene: the top level of the scene file and its `Simulation` block. The
// other blocks are read in rigid_body_reader.cpp, deformable_reader.cpp and joint_reader.cpp.
#include "pbd/io/scene_loader.h"

#include <fstream>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <sstream>

#include "pbd/io/input_checks.h"
#include "scene_reading.h"

namespace pbd {
namespace scene_io {
namespace {

/// Extension: "seed" | "product" | "average" | "min" | "max".
ContactCombineRule combineRule(const JsonValue& value) {
  const std::string name = value.string();
  for (ContactCombineRule rule :
       {ContactCombineRule::Seed, ContactCombineRule::Product, ContactCombineRule::Average,
        ContactCombineRule::Min, ContactCombineRule::Max})
    if (name == contactCombineRuleName(rule)) return rule;
  value.fail("one of \"seed\", \"product\", \"average\", \"min\", \"max\"");
}

/// Extension: "seed" | "corrected".
ContactModel contactModel(const JsonValue& value) {
  const std::string name = value.string();
  for (ContactModel model : {ContactModel::Seed, ContactModel::Corrected})
    if (name == contactModelName(model)) return model;
  value.fail("one of \"seed\", \"corrected\"");
}

/// Extension: "seed" | "corrected".
JointModel jointModel(const JsonValue& value) {
  const std::string name = value.string();
  for (JointModel model : {JointModel::Seed, JointModel::Corrected})
    if (name == jointModelName(model)) return model;
  value.fail("one of \"seed\", \"corrected\"");
}

/// Extension: "samples" | "primitives".
ContactGeometry contactGeometry(const JsonValue& value) {
  const std::string name = value.string();
  for (ContactGeometry geometry : {ContactGeometry::Samples, ContactGeometry::Primitives})
    if (name == contactGeometryName(geometry)) return geometry;
  value.fail("one of \"samples\", \"primitives\"");
}

/// Extension: "single" | "double".
ObjPrecision objPrecision(const JsonValue& value) {
  const std::string name = value.string();
  for (ObjPrecision precision : {ObjPrecision::Single, ObjPrecision::Double})
    if (name == objPrecisionName(precision)) return precision;
  value.fail("one of \"single\", \"double\"");
}

/// Extension: "cubicLagrange" | "catmullRom".
GridInterpolation distanceGrid(const JsonValue& value) {
  const std::string name = value.string();
  for (GridInterpolation kind : {GridInterpolation::CubicLagrange, GridInterpolation::CatmullRom})
    if (name == gridInterpolationName(kind)) return kind;
  value.fail("one of \"cubicLagrange\", \"catmullRom\"");
}

/// `gravity` is parsed by the seed's scene loader but never used: the seed simulates with its
/// `gravitation` (default [0, -9.81, 0]) whatever `gravity` says (its CarScene.json gives
/// [0, -2, 0] and runs at -9.81). Ignored the same way here, with a warning.
void readGravityAlias(JsonObject& object) {
  const auto gravity = object.find("gravity");
  if (!gravity) return;
  const Vector3 value = gravity->vector3();  // still a value that was given: it must be well-formed
  if (object.has("gravitation")) {
    gravity->warn(
        "ignored: \"gravitation\" is also given (PositionBasedDynamics ignores "
        "\"gravity\" always)");
    return;
  }
  gravity->warn("ignored " + formatVector(value) +
                ", as PositionBasedDynamics ignores \"gravity\": the gravitation stays the "
                "default [0, -9.81, 0]; rename the key to \"gravitation\" to use it");
}

/// `renderBVH` is the documented name of the seed's `renderBVHDepth`.
void readRenderBvhAlias(JsonObject& object, ViewerSettings& viewer) {
  const auto alias = object.find("renderBVH");
  if (!alias) return;
  const int depth = alias->integer(atLeast(-1));
  if (object.has("renderBVHDepth")) {
    alias->warn("ignored: \"renderBVHDepth\" is also given");
    return;
  }
  viewer.renderBVHDepth = depth;
}

/// The orthotropic cloth model divides by 1 − ν_xy ν_yx.
void checkClothPoissonRatios(JsonObject& object, const SimulationSettings& settings) {
  if (settings.cloth_xyPoissonRatio * settings.cloth_yxPoissonRatio < 1) return;
  const auto given = object.find("cloth_yxPoissonRatio");
  (given ? *given : *object.find("cloth_xyPoissonRatio"))
      .fail(
          "Poisson ratios with cloth_xyPoissonRatio * cloth_yxPoissonRatio < 1 (the "
          "orthotropic material divides by 1 - their product)");
}

/// The set {m₁, m₂, …} of method numbers as bits.
constexpr unsigned methodSet(std::initializer_list<int> methods) {
  unsigned bits = 0;
  for (int m : methods)
    bits |= 1u << m;
  return bits;
}

/// Which cloth and solid methods read a `Simulation` key (pbd/src/constraints/*: the
/// constraints each method builds).
struct ModelSettingUse {
  const char* key;
  bool cloth;        ///< a cloth key (else a solid key)
  unsigned methods;  ///< methodSet of the methods that read it
};

constexpr ModelSettingUse kModelSettingUses[] = {
    {"clothSimulationMethod", true, methodSet({0, 1, 2, 3, 4})},
    {"clothBendingMethod", true, methodSet({1, 2, 3, 4})},
    {"cloth_stiffness", true, methodSet({1, 4})},
    {"cloth_bendingStiffness", true, methodSet({1, 2, 3, 4})},
    {"cloth_xxStiffness", true, methodSet({2, 3})},
    {"cloth_yyStiffness", true, methodSet({2, 3})},
    {"cloth_xyStiffness", true, methodSet({2, 3})},
    {"cloth_xyPoissonRatio", true, methodSet({2})},
    {"cloth_yxPoissonRatio", true, methodSet({2})},
    {"cloth_normalizeStretch", true, methodSet({3})},
    {"cloth_normalizeShear", true, methodSet({3})},
    {"solidSimulationMethod", false, methodSet({0, 1, 2, 3, 4, 5, 6})},
    {"solid_stiffness", false, methodSet({1, 2, 3, 4, 5, 6})},
    {"solid_poissonRatio", false, methodSet({2, 3})},
    {"solid_volumeStiffness", false, methodSet({1, 6})},
    {"solid_normalizeStretch", false, methodSet({4})},
    {"solid_normalizeShear", false, methodSet({4})},
};

KeyTable<Scene> topLevelKeys() {
  return {
      stringKey("Name", &Scene::name),
      {"cameraPosition",
       [](const JsonValue& v, Scene& s) { s.viewer.cameraPosition = v.vector3(); }},
      {"cameraLookat", [](const JsonValue& v, Scene& s) { s.viewer.cameraLookat = v.vector3(); }},
      // Not interpreted by the library: validation/ parses it (docs/validation-block.md).
      {"Validation", [](const JsonValue& v, Scene& s) { s.validationJson = v.dump(); }},
  };
}

}  // namespace

KeyTable<SimulationSettings> simulationKeys() {
  using S = SimulationSettings;
  return {
      // The bounds below are the only ones: `--set` goes through this table too
      // (applySimulationSetting). They keep every run finite: a step below 1e-7 s or above 10 s
      // is no physical time step, and 10^4 substeps or iterations per step already cost
      // 10^4 times the default; the runner also refuses runs of more than 10^8 steps.
      numberKey("timeStepSize", &S::timeStepSize, between(1e-7, 10)),
      vectorKey("gravitation", &S::gravitation, between(-kMaxGravitation, kMaxGravitation)),
      integerKey("subSteps", &S::subSteps, between(1, kMaxSubSteps)),
      integerKey("maxIterations", &S::maxIterations, between(1, kMaxIterations)),
      integerKey("maxIterationsV", &S::maxIterationsV, between(0, kMaxIterations)),
      integerKey("velocityUpdateMethod", &S::velocityUpdateMethod, between(0, 1)),
      numberKey("contactTolerance", &S::contactTolerance, nonNegative()),
      numberKey("contactStiffnessRigidBody", &S::contactStiffnessRigidBody, nonNegative()),
      numberKey("contactStiffnessParticleRigidBody", &S::contactStiffnessParticleRigidBody,
                nonNegative()),
      {"contactCombineRule",
       [](const JsonValue& v, S& s) { s.contactCombineRule = combineRule(v); }, false,
       [](const S& s, Json& j) {
         writeString(j, "contactCombineRule", contactCombineRuleName(s.contactCombineRule));
       }},
      {"contactModel", [](const JsonValue& v, S& s) { s.contactModel = contactModel(v); }, false,
       [](const S& s, Json& j) {
         writeString(j, "contactModel", contactModelName(s.contactModel));
       }},
      {"distanceGrid", [](const JsonValue& v, S& s) { s.distanceGrid = distanceGrid(v); }, false,
       [](const S& s, Json& j) {
         if (s.distanceGrid) writeString(j, "distanceGrid", gridInterpolationName(*s.distanceGrid));
       }},

      numberKey("femCutoff", &S::femCutoff, nonNegative()),
      {"jointModel", [](const JsonValue& v, S& s) { s.jointModel = jointModel(v); }, false,
       [](const S& s, Json& j) {
         if (s.jointModel) writeString(j, "jointModel", jointModelName(*s.jointModel));
       }},
      {"contactGeometry", [](const JsonValue& v, S& s) { s.contactGeometry = contactGeometry(v); },
       false,
       [](const S& s, Json& j) {
         if (s.contactGeometry)
           writeString(j, "contactGeometry", contactGeometryName(*s.contactGeometry));
       }},
      {"objPrecision", [](const JsonValue& v, S& s) { s.objPrecision = objPrecision(v); }, false,
       [](const S& s, Json& j) {
         if (s.objPrecision != ObjPrecision::Single)
           writeString(j, "objPrecision", objPrecisionName(s.objPrecision));
       }},

      integerKey("clothSimulationMethod", &S::clothSimulationMethod, between(0, 4)),
      integerKey("clothBendingMethod", &S::clothBendingMethod, between(0, 3)),
      numberKey("cloth_stiffness", &S::cloth_stiffness, nonNegative()),
      numberKey("cloth_bendingStiffness", &S::cloth_bendingStiffness, nonNegative()),
      numberKey("cloth_xxStiffness", &S::cloth_xxStiffness, nonNegative()),
      numberKey("cloth_yyStiffness", &S::cloth_yyStiffness, nonNegative()),
      numberKey("cloth_xyStiffness", &S::cloth_xyStiffness, nonNegative()),
      numberKey("cloth_xyPoissonRatio", &S::cloth_xyPoissonRatio),
      numberKey("cloth_yxPoissonRatio", &S::cloth_yxPoissonRatio),
      booleanKey("cloth_normalizeStretch", &S::cloth_normalizeStretch),
      booleanKey("cloth_normalizeShear", &S::cloth_normalizeShear),

      integerKey("solidSimulationMethod", &S::solidSimulationMethod, between(0, 6)),
      numberKey("solid_stiffness", &S::solid_stiffness, nonNegative()),
      // The seed's FEM solve rejects Poisson ratios outside [0, 0.49].
      numberKey("solid_poissonRatio", &S::solid_poissonRatio, between(0, 0.49)),
      numberKey("solid_volumeStiffness", &S::solid_volumeStiffness, nonNegative()),
      booleanKey("solid_normalizeStretch", &S::solid_normalizeStretch),
      booleanKey("solid_normalizeShear", &S::solid_normalizeShear),

      numberKey("rod_stretchingStiffness", &S::rod_stretchingStiffness, nonNegative()),
      numberKey("rod_shearingStiffnessX", &S::rod_shearingStiffnessX, nonNegative()),
      numberKey("rod_shearingStiffnessY", &S::rod_shearingStiffnessY, nonNegative()),
      numberKey("rod_bendingStiffnessX", &S::rod_bendingStiffnessX, nonNegative()),
      numberKey("rod_bendingStiffnessY", &S::rod_bendingStiffnessY, nonNegative()),
      numberKey("rod_twistingStiffness", &S::rod_twistingStiffness, nonNegative()),
  };
}

KeyTable<ViewerSettings> viewerKeys() {
  using V = ViewerSettings;
  return {
      booleanKey("pause", &V::pause),
      numberKey("pauseAt", &V::pauseAt),
      integerKey("numberOfStepsPerRenderUpdate", &V::numberOfStepsPerRenderUpdate, atLeast(1)),
      booleanKey("renderTets", &V::renderTets),
      booleanKey("renderTets0", &V::renderTets0),
      booleanKey("renderContacts", &V::renderContacts),
      booleanKey("renderAABB", &V::renderAABB),
      booleanKey("renderSDF", &V::renderSDF),
      integerKey("renderBVHDepth", &V::renderBVHDepth, atLeast(-1)),
      integerKey("renderBVHDepthTets", &V::renderBVHDepthTets, atLeast(-1)),
      booleanKey("exportOBJ", &V::exportOBJ),
      booleanKey("exportPLY", &V::exportPLY),
      numberKey("exportFPS", &V::exportFPS, positive()),
  };
}

std::string unusedModelSettingReason(const std::string& key, const Scene& scene) {
  const SimulationSettings& settings = scene.simulation;
  for (const ModelSettingUse& use : kModelSettingUses) {
    if (key != use.key) continue;
    const bool haveModels = use.cloth ? !scene.triangleModels.empty() : !scene.tetModels.empty();
    if (!haveModels)
      return std::string("the scene has no ") + (use.cloth ? "TriangleModels" : "TetModels");
    if (key == "cloth_bendingStiffness" && settings.clothBendingMethod == 0 &&
        settings.clothSimulationMethod != 0)
      return "clothBendingMethod 0 has no bending";
    const int method = use.cloth ? settings.clothSimulationMethod : settings.solidSimulationMethod;
    if ((use.methods & (1u << method)) != 0) return "";
    return std::string(use.cloth ? "clothSimulationMethod " : "solidSimulationMethod ") +
           std::to_string(method) +
           (method == 0 ? std::string(" simulates no ") + (use.cloth ? "cloth" : "solid")
                        : std::string(" does not use it"));
  }
  return "";
}

/// `gravitation` is the seed's key; `gravity` is parsed by the seed but never used.
void readSimulation(const JsonValue& block, Scene& scene) {
  JsonObject object = block.object();
  readKeys(object, simulationKeys(), scene.simulation);
  readKeys(object, viewerKeys(), scene.viewer);
  readGravityAlias(object);
  readRenderBvhAlias(object, scene.viewer);
  checkClothPoissonRatios(object, scene.simulation);
  object.warnUnknownKeys();
}

}  // namespace scene_io

std::vector<std::string> simulationSettingKeys() {
  std::vector<std::string> keys;
  for (const auto& entry : scene_io::simulationKeys())
    keys.push_back(entry.key);
  return keys;
}

void applySimulationSetting(SimulationSettings& settings, const std::string& key,
                            const std::string& valueText, const std::string& origin) {
  using namespace scene_io;
  if (key == "objPrecision") {
    // The meshes are read with it while the scene loads; a later change would leave them as
    // they were read.
    throw SceneError(SceneDiagnostic{
        origin, "Simulation.objPrecision",
        "takes effect while the meshes are read: give it in the scene file's Simulation block"});
  }
  for (const auto& entry : simulationKeys()) {
    if (entry.key != key) continue;
    // The value as JSON ("10", "[0, -9.81, 0]", "\"corrected\""); else a list "0,-9.81,0";
    // else the text as a string (contactModel=corrected).
    Json value = Json::parse(valueText, nullptr, false);
    if (value.is_discarded() && valueText.find(',') != std::string::npos)
      value = Json::parse("[" + valueText + "]", nullptr, false);
    if (value.is_discarded()) value = Json(valueText);
    DiagnosticSink sink(origin, /*strict=*/true);
    entry.read(JsonValue(value, "Simulation." + key, sink), settings);
    return;
  }
  std::string known;
  for (const std::string& k : simulationSettingKeys())
    known += (known.empty() ? "" : ", ") + k;
  throw SceneError(SceneDiagnostic{
      origin, "", "unknown Simulation setting '" + key + "' (settings: " + known + ")"});
}

namespace scene_io {
namespace {

/// A cloth or solid setting the scene gives but nothing reads gets a warning that says why
/// (unusedModelSettingReason); the seed reads every such key and silently ignores it, bending
/// on a cloth of method 0 included.
void warnUnusedModelSettings(JsonObject& root, const Scene& scene) {
  const auto block = root.find("Simulation");
  if (!block || !block->isObject()) return;
  JsonObject simulation = block->object();
  for (const ModelSettingUse& use : kModelSettingUses) {
    const auto given = simulation.find(use.key);
    if (!given) continue;
    const std::string reason = unusedModelSettingReason(use.key, scene);
    if (!reason.empty()) given->warn("ignored: " + reason);
  }
}

}  // namespace
}  // namespace scene_io

LoadedScene parseScene(const std::string& jsonText, const std::string& sourcePath,
                       const LoadOptions& options) {
  using namespace scene_io;
  // JSON text (RFC 8259) never contains a NUL byte, not even inside strings (it must be
  // escaped there); one means a binary or truncated-and-padded file, whose bytes after the NUL
  // the parser would otherwise skip or misread (issue 25).
  if (const std::size_t nul = jsonText.find('\0'); nul != std::string::npos) {
    throw SceneError(SceneDiagnostic{
        sourcePath, "",
        "a NUL byte at byte offset " + std::to_string(nul) +
            ": expected JSON text (UTF-8 without NUL bytes); the file is binary or corrupted"});
  }
  DiagnosticSink sink(sourcePath, options.strict);
  const Json document = parseJson(jsonText, sink);
  const JsonValue rootValue(document, "", sink);
  if (!rootValue.isObject()) rootValue.fail("a JSON object at the top level");
  JsonObject root(rootValue);
  LoadContext context(std::filesystem::path(sourcePath).parent_path());

  Scene scene;
  scene.sourceFile = sourcePath;
  readKeys(root, topLevelKeys(), scene);
  if (auto block = root.find("Simulation")) readSimulation(*block, scene);
  context.setObjPrecision(scene.simulation.objPrecision);
  if (auto block = root.find("RigidBodies")) readRigidBodies(*block, context, scene);
  if (auto block = root.find("TriangleModels")) readTriangleModels(*block, context, scene);
  if (auto block = root.find("TetModels")) readTetModels(*block, context, scene);
  if (auto block = root.find("LineModels")) readLineModels(*block, scene);
  warnUnusedRodSettings(root, scene);
  // Keep last among the particle blocks: fluid particles follow every other model's.
  if (auto block = root.find("FluidModels")) readFluidModels(*block, scene);
  if (auto block = root.find("ContactPairs")) readContactPairs(*block, scene);
  readJoints(root, scene);
  warnUnusedModelSettings(root, scene);
  readStiffRods(root, scene);
  root.warnUnknownKeys();
  return LoadedScene{std::move(scene), sink.takeWarnings()};
}

LoadedScene loadScene(const std::string& path, const LoadOptions& options) {
  // A folder, /dev/null or a FIFO would read as empty (or block): say what it is instead.
  const std::string problem = inputFileProblem(path, "scene");
  if (!problem.empty()) throw SceneError(SceneDiagnostic{path, "", problem});
  std::ifstream stream(path, std::ios::binary);
  if (!stream) throw SceneError(SceneDiagnostic{path, "", "cannot open the scene file"});
  std::ostringstream text;
  text << stream.rdbuf();
  return parseScene(text.str(), path, options);
}

}  // namespace pbd
