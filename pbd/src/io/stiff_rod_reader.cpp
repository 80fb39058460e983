// The seed's stiff-rods format (its StiffRodsSceneLoader): `CosseratJoints` and `TreeModels`.
// A CosseratJoint takes its material (E, G) from the TreeModel that lists it and its
// cross-section and length from its two segments' shapes; see docs/scene-format.md.
#include <algorithm>
#include <map>
#include <nlohmann/json.hpp>

#include "scene_reading.h"

namespace pbd::scene_io {
namespace {

/// The seed's solverType values: 12 = direct (its default); 0 = iterative (pbdval extension).
StiffRodSolver readSolverType(const JsonValue& value) {
  const int type = value.integer();
  if (type == static_cast<int>(StiffRodSolver::Direct)) return StiffRodSolver::Direct;
  if (type == static_cast<int>(StiffRodSolver::Iterative)) return StiffRodSolver::Iterative;
  value.fail("12 (the direct tree solver, the seed's value) or 0 (the iterative per-joint solver)");
}

struct CosseratInput {
  JointDesc desc;
};

KeyTable<CosseratInput> cosseratKeys() {
  using C = CosseratInput;
  return {
      required(
          KeyReader<C>{"bodyID1", [](const JsonValue& v, C& c) { c.desc.bodyId1 = v.integer(); }}),
      required(
          KeyReader<C>{"bodyID2", [](const JsonValue& v, C& c) { c.desc.bodyId2 = v.integer(); }}),
      required(
          KeyReader<C>{"id", [](const JsonValue& v, C& c) { c.desc.stiffRod.id = v.integer(); }}),
      required(KeyReader<C>{"position",
                            [](const JsonValue& v, C& c) { c.desc.position = v.vector3(); }}),
      {"stiffnessModifier",
       [](const JsonValue& v, C& c) { c.desc.stiffRod.stiffnessModifier = v.vector3(positive()); }},
  };
}

/// (width, length, height) of a segment: the rod axis is its local y (docs/scene-format.md).
Vector3 segmentDimensions(const RigidBodyDesc& body, const JsonValue& where) {
  if (!body.geometryFile.empty()) return body.scale;  // the seed: scale = (2 r_x, L, 2 r_z)
  const Vector3& s = body.collision.scale;
  switch (body.collision.type) {
    case CollisionObjectType::Box:
      return s;  // full extents
    case CollisionObjectType::Cylinder:
      return Vector3(2 * s(0), s(1), 2 * s(0));  // radius s(0), height s(1) along y
    default:
      where.error(body.jsonPath +
                  " is a stiff-rod segment without geometryFile: it must be a box (type 2) or "
                  "cylinder (type 3) primitive, whose dimensions give the rod's cross-section "
                  "and segment length");
  }
}

void readTree(const JsonValue& element, Scene& scene, const std::map<int, int>& jointById,
              int treeIndex) {
  JsonObject object = element.object();
  StiffRodTreeDesc tree;
  tree.jsonPath = element.path();
  if (auto v = object.find("id")) tree.id = v->integer();
  if (auto v = object.find("translation"); v && !v->vector3().isZero(0))
    v->fail(
        "[0, 0, 0] (a TreeModel transform is not supported: place the segments and joints "
        "in world coordinates)");
  if (auto v = object.find("rotationAngle"); v && v->number() != 0)
    v->fail(
        "0 (a TreeModel rotation is not supported: place the segments and joints in world "
        "coordinates)");
  if (auto v = object.find("rotationAxis")) v->vector3();
  tree.youngsModulus = object.require("youngsModulus").number(positive());
  tree.torsionModulus = object.require("torsionModulus").number(positive());
  if (auto v = object.find("solverType")) tree.solver = readSolverType(*v);

  for (const JsonValue& id : object.require("rbIds").elements("rigid-body ids")) {
    const int body = resolveBodyId(id, scene);
    if (std::find(tree.bodies.begin(), tree.bodies.end(), body) != tree.bodies.end())
      id.error("rigid body id " + std::to_string(id.integer()) + " is listed twice");
    tree.bodies.push_back(body);
  }
  const auto inTree = [&](int body) {
    return std::find(tree.bodies.begin(), tree.bodies.end(), body) != tree.bodies.end();
  };
  if (auto block = object.find("staticSegments")) {
    for (const JsonValue& id : block->elements("rigid-body ids")) {
      const int body = resolveBodyId(id, scene);
      if (!inTree(body)) id.fail("the id of a segment listed in rbIds");
      tree.staticSegments.push_back(body);
      scene.rigidBodies[static_cast<std::size_t>(body)].isDynamic = false;  // as the seed: mass 0
    }
  }
  for (const JsonValue& idValue : object.require("jIds").elements("CosseratJoint ids")) {
    const int id = idValue.integer();
    const auto it = jointById.find(id);
    if (it == jointById.end()) idValue.fail("the id of a CosseratJoint (none has this id)");
    JointDesc& joint = scene.joints[static_cast<std::size_t>(it->second)];
    if (joint.stiffRod.tree >= 0) {
      idValue.error("CosseratJoint id " + std::to_string(id) + " (" + joint.jsonPath +
                    ") is already in " +
                    scene.stiffRodTrees[static_cast<std::size_t>(joint.stiffRod.tree)].jsonPath);
    }
    if (!inTree(joint.body1) || !inTree(joint.body2)) {
      idValue.error(joint.jsonPath + " joins rigid bodies " + std::to_string(joint.bodyId1) +
                    " and " + std::to_string(joint.bodyId2) +
                    ", which must both be listed in rbIds");
    }
    const Vector3 a = segmentDimensions(scene.rigidBodies[std::size_t(joint.body1)], idValue);
    const Vector3 b = segmentDimensions(scene.rigidBodies[std::size_t(joint.body2)], idValue);
    StiffRodJointParams& p = joint.stiffRod;
    p.tree = treeIndex;
    p.youngsModulus = tree.youngsModulus;
    p.torsionModulus = tree.torsionModulus;
    p.averageRadius = (a(0) + a(2) + b(0) + b(2)) / 8;  // mean of the four half-widths
    p.averageSegmentLength = (a(1) + b(1)) / 2;
    if (!(p.averageRadius > 0) || !(p.averageSegmentLength > 0))
      idValue.error(joint.jsonPath + ": its segments have zero cross-section or length");
    tree.joints.push_back(it->second);
  }
  object.warnUnknownKeys();
  scene.stiffRodTrees.push_back(std::move(tree));
}

}  // namespace

void readStiffRods(JsonObject& root, Scene& scene) {
  for (const char* key : {"CompactTreeModels", "SkinningMeshes", "RodAnimators"}) {
    const auto block = root.find(key);
    if (!block) continue;
    const bool empty = block->node().is_array() && block->node().empty();
    const std::string what = std::string(key) +
                             " of the seed's stiff-rods format is not supported (supported: "
                             "CosseratJoints and TreeModels with RigidBodies as segments)";
    if (empty)
      block->warn("ignored (empty): " + what);
    else
      block->error(what);
  }
  std::map<int, int> jointById;  // CosseratJoint id → index into scene.joints
  if (auto block = root.find("CosseratJoints")) {
    for (const JsonValue& element : block->elements("joint objects")) {
      JsonObject object = element.object();
      CosseratInput in;
      in.desc.type = JointType::StiffRod;
      in.desc.jsonPath = element.path();
      readKeys(object, cosseratKeys(), in);
      in.desc.body1 = resolveBodyId(*object.find("bodyID1"), scene);
      in.desc.body2 = resolveBodyId(*object.find("bodyID2"), scene);
      if (in.desc.body1 == in.desc.body2)
        object.error("bodyID1 and bodyID2 are the same body; a joint connects two segments");
      const int index = static_cast<int>(scene.joints.size());
      if (!jointById.emplace(in.desc.stiffRod.id, index).second) {
        object.find("id")->error(
            "id " + std::to_string(in.desc.stiffRod.id) + " is also the id of " +
            scene.joints[std::size_t(jointById[in.desc.stiffRod.id])].jsonPath);
      }
      object.warnUnknownKeys();
      scene.joints.push_back(in.desc);
    }
  }
  if (auto block = root.find("TreeModels")) {
    const auto elements = block->elements("tree-model objects");
    for (std::size_t t = 0; t < elements.size(); ++t)
      readTree(elements[t], scene, jointById, static_cast<int>(t));
  }
  for (const JointDesc& joint : scene.joints) {
    if (joint.type != JointType::StiffRod || joint.stiffRod.tree >= 0) continue;
    DiagnosticSink& sink = root.value().sink();
    sink.error(joint.jsonPath,
               "CosseratJoint id " + std::to_string(joint.stiffRod.id) +
                   " is in no TreeModel's jIds; its stiffness needs the tree's youngsModulus "
                   "and torsionModulus (the seed silently drops such joints)");
  }
}

}  // namespace pbd::scene_io
