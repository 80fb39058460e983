#include "adapters/features.h"

#include <algorithm>
#include <set>
#include <stdexcept>
#include <utility>

#include "pbd/io/number_text.h"

namespace pbdval {
namespace {

using pbd::CollisionObjectType;
using pbd::JointType;

/// The feature key of each joint type, in JointType order.
constexpr const char* kJointKeys[pbd::kJointTypeCount] = {
    "joint.ball",
    "joint.ballOnLine",
    "joint.hinge",
    "joint.universal",
    "joint.slider",
    "joint.rigidBodyParticleBall",
    "joint.rigidBodySpring",
    "joint.distance",
    "joint.damper",
    "joint.targetAngleMotorHinge",
    "joint.targetVelocityMotorHinge",
    "joint.targetPositionMotorSlider",
    "joint.targetVelocityMotorSlider",
    "joint.stiffRod",
};

const char* clothMethodKey(int method) {
  switch (method) {
    case 0:
      return "cloth.method.none";
    case 1:
      return "cloth.method.distance";
    case 2:
      return "cloth.method.fem";
    case 3:
      return "cloth.method.strainBased";
    case 4:
      return "cloth.method.xpbdDistance";
    default:
      return "cloth.method.other";
  }
}

const char* bendingMethodKey(int method) {
  switch (method) {
    case 0:
      return "cloth.bending.none";
    case 1:
      return "cloth.bending.dihedral";
    case 2:
      return "cloth.bending.isometric";
    case 3:
      return "cloth.bending.isometricXpbd";
    default:
      return "cloth.bending.other";
  }
}

const char* solidMethodKey(int method) {
  switch (method) {
    case 0:
      return "solid.method.none";
    case 1:
      return "solid.method.distanceVolume";
    case 2:
      return "solid.method.fem";
    case 3:
      return "solid.method.femXpbd";
    case 4:
      return "solid.method.strainBased";
    case 5:
      return "solid.method.shapeMatching";
    case 6:
      return "solid.method.distanceVolumeXpbd";
    default:
      return "solid.method.other";
  }
}

/// The key of a rigid body's collision shape, and whether it is built from the body's mesh.
const char* shapeKey(const pbd::RigidBodyDesc& body) {
  const bool mesh = body.mesh != nullptr;
  switch (body.collision.type) {
    case CollisionObjectType::None:
      return "shape.none";
    case CollisionObjectType::Sphere:
      return "shape.sphere";
    case CollisionObjectType::Box:
      return "shape.box";
    case CollisionObjectType::Cylinder:
      return "shape.cylinder";
    case CollisionObjectType::Torus:
      return mesh ? "shape.torus.mesh" : "shape.torus.analytic";
    case CollisionObjectType::SignedDistanceField:
      return mesh ? "shape.sdf.mesh" : "shape.sdf.fileOnly";
    case CollisionObjectType::HollowSphere:
      return "shape.hollowSphere";
    case CollisionObjectType::HollowBox:
      return "shape.hollowBox";
  }
  return "shape.none";
}

bool isPrefixGroup(std::string_view group, std::string_view key) {
  return key.size() > group.size() && key.compare(0, group.size(), group) == 0 &&
         key[group.size()] == '.';
}

bool covers(std::string_view entryKey, std::string_view key) {
  return entryKey == key || isPrefixGroup(entryKey, key);
}

bool forMethod(const FeatureSupport& entry, std::string_view method) {
  return std::find(entry.methods.begin(), entry.methods.end(), method) != entry.methods.end();
}

}  // namespace

const char* supportName(Support support) {
  switch (support) {
    case Support::Native:
      return "native";
    case Support::Approximated:
      return "approximated";
    case Support::Unsupported:
      return "unsupported";
  }
  return "unsupported";
}

Support supportNamed(std::string_view name) {
  for (Support s : {Support::Native, Support::Approximated, Support::Unsupported})
    if (name == supportName(s)) return s;
  throw std::invalid_argument(
      "expected one of \"native\", \"approximated\", \"unsupported\", got \"" + std::string(name) +
      "\"");
}

const std::vector<FeatureInfo>& sceneFeatures() {
  static const std::vector<FeatureInfo> features = {
      // Shapes (RigidBodies[i].collisionObjectType).
      {"shape.none", "no collision shape (collisionObjectType 0)"},
      {"shape.sphere", "sphere (collisionObjectType 1)"},
      {"shape.box", "box (collisionObjectType 2)"},
      {"shape.cylinder", "cylinder, axis y (collisionObjectType 3)"},
      {"shape.torus.mesh", "torus with a geometryFile mesh (collisionObjectType 4)"},
      {"shape.torus.analytic",
       "torus without a geometryFile: the analytic (R, r) only (collisionObjectType 4)"},
      {"shape.sdf.mesh",
       "signed distance field of the body's geometryFile mesh (collisionObjectType 5)"},
      {"shape.sdf.fileOnly",
       "signed distance field without a geometryFile mesh (collisionObjectType 5)"},
      {"shape.sdf.precomputedFile", "a precomputed SDF file (collisionObjectFileName of type 5)"},
      {"shape.hollowSphere", "hollow sphere (collisionObjectType 6)"},
      {"shape.hollowBox", "hollow box (collisionObjectType 7)"},
      {"shape.invertSDF", "inside-out collision shape (invertSDF)"},
      // Joints, one per scene block.
      {"joint.ball", "ball joint (BallJoints)"},
      {"joint.ballOnLine", "ball-on-line joint (BallOnLineJoints)"},
      {"joint.hinge", "hinge joint (HingeJoints)"},
      {"joint.universal", "universal joint (UniversalJoints)"},
      {"joint.slider", "slider joint (SliderJoints)"},
      {"joint.rigidBodyParticleBall",
       "rigid body–particle ball joint (RigidBodyParticleBallJoints)"},
      {"joint.rigidBodySpring", "spring between two rigid bodies (RigidBodySprings)"},
      {"joint.distance", "distance joint (DistanceJoints)"},
      {"joint.damper", "axial spring on a slider (DamperJoints)"},
      {"joint.targetAngleMotorHinge", "angle motor on a hinge (TargetAngleMotorHingeJoints)"},
      {"joint.targetVelocityMotorHinge",
       "velocity motor on a hinge (TargetVelocityMotorHingeJoints)"},
      {"joint.targetPositionMotorSlider",
       "position motor on a slider (TargetPositionMotorSliderJoints)"},
      {"joint.targetVelocityMotorSlider",
       "velocity motor on a slider (TargetVelocityMotorSliderJoints)"},
      {"joint.stiffRod",
       "stiff-rod joint: elastic bending and twisting between rod segments (CosseratJoints, "
       "TreeModels)"},
      {"joint.closingLoop.ballOrHinge",
       "a ball or hinge joint that closes a kinematic loop (reduced-coordinate engines: which "
       "joints close loops depends on the spanning tree the engine builds)",
       false},
      {"joint.closingLoop.other",
       "any other joint that closes a kinematic loop (reduced-coordinate engines, as above)",
       false},
      {"body.initialVelocityOfJointedBody",
       "an initial velocity of a dynamic body jointed to another dynamic body"},
      // Contacts.
      {"contact.rigidPairs",
       "contacts between rigid bodies (two collision shapes, not both static), each pair with "
       "Scene::pairMaterial's friction and restitution (ContactPairs or the contactCombineRule)"},
      {"contact.nonSeparableMaterials",
       "pair friction or restitution that are not products of per-body values (checked by the "
       "engines that need such products, when they run)",
       false},
      {"particle.initialVelocity", "an initial velocity of a dynamic particle of a cloth or solid"},
      // Particles: cloth (TriangleModels).
      {"cloth.method.none", "cloth without constraints: free particles (clothSimulationMethod 0)"},
      {"cloth.method.distance", "cloth, PBD distance constraints (clothSimulationMethod 1)"},
      {"cloth.method.fem", "cloth, PBD FEM triangles (clothSimulationMethod 2)"},
      {"cloth.method.strainBased", "cloth, PBD strain-based triangles (clothSimulationMethod 3)"},
      {"cloth.method.xpbdDistance",
       "cloth, XPBD distance constraints, k in N/m (clothSimulationMethod 4)"},
      {"cloth.method.other", "cloth with a clothSimulationMethod outside 0–4"},
      {"cloth.bending.none", "cloth without bending (clothBendingMethod 0)"},
      {"cloth.bending.dihedral", "cloth, PBD dihedral bending (clothBendingMethod 1)"},
      {"cloth.bending.isometric", "cloth, PBD isometric bending (clothBendingMethod 2)"},
      {"cloth.bending.isometricXpbd", "cloth, XPBD isometric bending (clothBendingMethod 3)"},
      {"cloth.bending.other", "cloth with a clothBendingMethod outside 0–3"},
      // Particles: solids (TetModels).
      {"solid.method.none", "solid without constraints: free particles (solidSimulationMethod 0)"},
      {"solid.method.distanceVolume",
       "solid, PBD distance and volume constraints (solidSimulationMethod 1)"},
      {"solid.method.fem", "solid, PBD FEM tets (solidSimulationMethod 2)"},
      {"solid.method.femXpbd",
       "solid, XPBD FEM tets: linear elasticity (E, ν) (solidSimulationMethod 3)"},
      {"solid.method.strainBased", "solid, PBD strain-based tets (solidSimulationMethod 4)"},
      {"solid.method.shapeMatching", "solid, PBD shape matching (solidSimulationMethod 5)"},
      {"solid.method.distanceVolumeXpbd",
       "solid, XPBD distance and volume constraints (solidSimulationMethod 6)"},
      {"solid.method.other", "solid with a solidSimulationMethod outside 0–6"},
      {"solid.femPoissonOutOfRange",
       "FEM solid (solidSimulationMethod 2 or 3) with solid_poissonRatio outside [0, 0.49]"},
      // Rods and fluids.
      {"rod.cosserat", "Cosserat rod (LineModels)"},
      {"fluid.pbf", "position-based fluid (FluidModels)"},
  };
  return features;
}

const FeatureInfo* findFeature(std::string_view key) {
  for (const FeatureInfo& f : sceneFeatures())
    if (key == f.key) return &f;
  return nullptr;
}

bool isFeatureKeyOrGroup(std::string_view key) {
  if (key.empty()) return false;
  for (const FeatureInfo& f : sceneFeatures())
    if (covers(key, f.key)) return true;
  return false;
}

const FeatureSupport* FeatureTable::resolve(std::string_view key, std::string_view method) const {
  const FeatureSupport* best = nullptr;
  for (bool restricted : {true, false}) {
    for (const FeatureSupport& entry : entries) {
      if (restricted ? !forMethod(entry, method) : !entry.methods.empty()) continue;
      if (!covers(entry.key, key)) continue;
      if (best == nullptr || entry.key.size() > best->key.size()) best = &entry;
    }
    if (best != nullptr) return best;
  }
  return nullptr;
}

std::vector<std::string> checkFeatureTable(const FeatureTable& table,
                                           const std::vector<std::string>& methods) {
  std::vector<std::string> problems;
  std::set<std::pair<std::string, std::string>> seen;  // (key, method or "")
  for (std::size_t i = 0; i < table.entries.size(); ++i) {
    const FeatureSupport& e = table.entries[i];
    const std::string where = "features[" + std::to_string(i) + "]";
    if (!isFeatureKeyOrGroup(e.key))
      problems.push_back(where + ".feature: \"" + e.key +
                         "\" is neither a scene feature nor a group of features "
                         "(docs/engines.md#features lists them)");
    if (e.support != Support::Native && e.text.empty())
      problems.push_back(where + ".text: an " + supportName(e.support) + " feature says " +
                         (e.support == Support::Unsupported ? "why" : "how it differs"));
    for (const std::string& m : e.methods)
      if (std::find(methods.begin(), methods.end(), m) == methods.end())
        problems.push_back(where + ".methods: \"" + m + "\" is not a method of the engine");
    const std::vector<std::string> scopes =
        e.methods.empty() ? std::vector<std::string>{""} : e.methods;
    for (const std::string& scope : scopes)
      if (!seen.insert({e.key, scope}).second)
        problems.push_back(where + ": a second entry for \"" + e.key + "\"" +
                           (scope.empty() ? std::string() : " and method " + scope));
  }
  for (const FeatureInfo& f : sceneFeatures())
    for (const std::string& m : methods)
      if (table.resolve(f.key, m) == nullptr) {
        problems.push_back("features: no entry covers \"" + std::string(f.key) + "\" for " + m);
        break;
      }
  return problems;
}

std::vector<FeatureUse> sceneFeatureUses(const pbd::Scene& scene) {
  std::vector<FeatureUse> uses;
  for (const pbd::RigidBodyDesc& body : scene.rigidBodies) {
    const pbd::CollisionObjectDesc& c = body.collision;
    const std::string type = "collisionObjectType " + std::to_string(int(c.type));
    uses.push_back({shapeKey(body), body.jsonPath, type});
    if (c.type == CollisionObjectType::SignedDistanceField && !c.fileName.empty())
      uses.push_back({"shape.sdf.precomputedFile", body.jsonPath, "collisionObjectFileName"});
    if (c.type != CollisionObjectType::None && c.invertSDF)
      uses.push_back({"shape.invertSDF", body.jsonPath, "invertSDF true"});
  }
  for (const pbd::JointDesc& joint : scene.joints)
    uses.push_back({kJointKeys[int(joint.type)], joint.jsonPath, ""});
  for (const pbd::RigidBodyDesc& body : scene.rigidBodies) {
    if (!body.isDynamic || (body.velocity.isZero(0) && body.angularVelocity.isZero(0))) continue;
    const int index = int(&body - scene.rigidBodies.data());
    for (const pbd::JointDesc& joint : scene.joints) {
      if (joint.body1 < 0 || joint.body2 < 0 || joint.type == JointType::RigidBodyParticleBall)
        continue;
      if (joint.body1 != index && joint.body2 != index) continue;
      const int other = joint.body1 == index ? joint.body2 : joint.body1;
      if (!scene.rigidBodies[std::size_t(other)].isDynamic) continue;
      uses.push_back({"body.initialVelocityOfJointedBody", body.jsonPath, "by " + joint.jsonPath});
      break;
    }
  }
  bool collidingPair = false;
  for (std::size_t a = 0; a < scene.rigidBodies.size() && !collidingPair; ++a)
    for (std::size_t b = a + 1; b < scene.rigidBodies.size() && !collidingPair; ++b) {
      const pbd::RigidBodyDesc& first = scene.rigidBodies[a];
      const pbd::RigidBodyDesc& second = scene.rigidBodies[b];
      collidingPair = first.collision.type != CollisionObjectType::None &&
                      second.collision.type != CollisionObjectType::None &&
                      (first.isDynamic || second.isDynamic);
    }
  if (collidingPair)
    uses.push_back({"contact.rigidPairs", "RigidBodies",
                    std::string("contactCombineRule ") +
                        pbd::contactCombineRuleName(scene.simulation.contactCombineRule)});
  const pbd::SimulationSettings& s = scene.simulation;
  for (const pbd::TriangleModelDesc& model : scene.triangleModels) {
    uses.push_back({clothMethodKey(s.clothSimulationMethod), model.jsonPath,
                    "clothSimulationMethod " + std::to_string(s.clothSimulationMethod)});
    uses.push_back({bendingMethodKey(s.clothBendingMethod), model.jsonPath,
                    "clothBendingMethod " + std::to_string(s.clothBendingMethod)});
  }
  auto movingParticle = [&](int first, std::size_t count) {
    for (std::size_t i = 0; i < count; ++i) {
      const pbd::ParticleDesc& p = scene.particles[std::size_t(first) + i];
      if (p.mass > 0 && !p.velocity.isZero(0)) return true;
    }
    return false;
  };
  for (const pbd::TriangleModelDesc& model : scene.triangleModels)
    if (movingParticle(model.firstParticle, model.mesh.vertices.size()))
      uses.push_back({"particle.initialVelocity", model.jsonPath, ""});
  for (const pbd::TetModelDesc& model : scene.tetModels)
    if (movingParticle(model.firstParticle, model.mesh.vertices.size()))
      uses.push_back({"particle.initialVelocity", model.jsonPath, ""});
  const bool fem = s.solidSimulationMethod == 2 || s.solidSimulationMethod == 3;
  const bool poissonInRange = s.solid_poissonRatio >= 0 && s.solid_poissonRatio <= pbd::Real(0.49);
  for (const pbd::TetModelDesc& model : scene.tetModels) {
    uses.push_back({solidMethodKey(s.solidSimulationMethod), model.jsonPath,
                    "solidSimulationMethod " + std::to_string(s.solidSimulationMethod)});
    if (fem && !poissonInRange)
      uses.push_back({"solid.femPoissonOutOfRange", model.jsonPath,
                      "solid_poissonRatio " + pbd::formatReal(double(s.solid_poissonRatio))});
  }
  for (const pbd::LineModelDesc& model : scene.lineModels)
    uses.push_back(
        {"rod.cosserat", model.jsonPath,
         model.usesModuli() ? "XPBD, youngsModulus and shearModulus" : "PBD, rod_* fractions"});
  for (const pbd::FluidModelDesc& model : scene.fluidModels)
    uses.push_back({"fluid.pbf", model.jsonPath, ""});
  return uses;
}

std::vector<UnsupportedUse> unsupportedUses(const FeatureTable& table,
                                            const std::vector<FeatureUse>& uses,
                                            std::string_view method) {
  std::vector<UnsupportedUse> found;
  std::set<std::pair<std::string, const FeatureSupport*>> reported;
  for (const FeatureUse& use : uses) {
    const FeatureSupport* entry = table.resolve(use.key, method);
    if (entry != nullptr && entry->support != Support::Unsupported) continue;
    if (!reported.insert({use.jsonPath, entry}).second) continue;
    const FeatureInfo* info = findFeature(use.key);
    std::string message = use.jsonPath + ": " + (info ? info->description : use.key);
    if (!use.detail.empty() &&
        (info == nullptr ||
         std::string_view(info->description).find(use.detail) == std::string_view::npos))
      message += " [" + use.detail + "]";
    message +=
        ": " + (entry != nullptr ? entry->text
                                 : "not declared in the engine's feature table (" + use.key + ")");
    found.push_back({use.key, use.jsonPath, std::move(message)});
  }
  return found;
}

std::vector<std::string> unsupportedFeatures(const FeatureTable& table, const pbd::Scene& scene,
                                             std::string_view method) {
  std::vector<std::string> messages;
  for (UnsupportedUse& use : unsupportedUses(table, sceneFeatureUses(scene), method))
    messages.push_back(std::move(use.message));
  return messages;
}

}  // namespace pbdval
