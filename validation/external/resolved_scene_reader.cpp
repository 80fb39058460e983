#include "validation/external/resolved_scene_reader.h"

#include <map>
#include <memory>
#include <stdexcept>
#include <string>

#include "pbd/io/mesh_loader.h"

namespace pbdval {
namespace {

using nlohmann::json;
using pbd::Quaternion;
using pbd::Real;
using pbd::Vector3;

[[noreturn]] void fail(const std::string& path, const std::string& expected) {
  throw std::invalid_argument("resolved scene: " + path + ": expected " + expected);
}

const json& at(const json& node, const std::string& path, const char* key) {
  if (!node.is_object() || !node.contains(key)) fail(path + "/" + key, "a value (missing)");
  return node.at(key);
}

double number(const json& node, const std::string& path, const char* key) {
  const json& v = at(node, path, key);
  if (!v.is_number()) fail(path + "/" + key, "a number");
  return v.get<double>();
}

Vector3 vec3(const json& node, const std::string& path, const char* key) {
  const json& v = at(node, path, key);
  if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() || !v[2].is_number())
    fail(path + "/" + key, "3 numbers");
  return Vector3(Real(v[0].get<double>()), Real(v[1].get<double>()), Real(v[2].get<double>()));
}

Quaternion quat(const json& node, const std::string& path, const char* key) {
  const json& v = at(node, path, key);
  if (!v.is_array() || v.size() != 4) fail(path + "/" + key, "4 numbers (w, x, y, z)");
  for (const json& c : v)
    if (!c.is_number()) fail(path + "/" + key, "4 numbers (w, x, y, z)");
  return Quaternion(Real(v[0].get<double>()), Real(v[1].get<double>()), Real(v[2].get<double>()),
                    Real(v[3].get<double>()));
}

pbd::CollisionObjectDesc collision(const json& shape, const std::string& path) {
  pbd::CollisionObjectDesc c;
  const json& type = at(shape, path, "collisionObjectType");
  if (!type.is_number_integer() || type.get<int>() < 0 || type.get<int>() > 7)
    fail(path + "/collisionObjectType", "an integer 0 to 7");
  c.type = pbd::CollisionObjectType(type.get<int>());
  c.invertSDF = shape.value("inverted", false);
  switch (c.type) {
    case pbd::CollisionObjectType::Sphere:
    case pbd::CollisionObjectType::HollowSphere:
      c.scale = Vector3::Constant(Real(number(shape, path, "radius")));
      break;
    case pbd::CollisionObjectType::Box:
    case pbd::CollisionObjectType::HollowBox:
      c.scale = 2 * vec3(shape, path, "halfExtents");  // exact: the writer halved it
      break;
    case pbd::CollisionObjectType::Cylinder:
      c.scale =
          Vector3(Real(number(shape, path, "radius")), Real(number(shape, path, "height")), 1);
      break;
    case pbd::CollisionObjectType::Torus:
      c.scale = Vector3(Real(number(shape, path, "majorRadius")),
                        Real(number(shape, path, "minorRadius")), 1);
      break;
    case pbd::CollisionObjectType::SignedDistanceField:
      c.scale = vec3(shape, path, "meshScale");
      break;
    case pbd::CollisionObjectType::None:
      break;
  }
  return c;
}

pbd::RigidBodyDesc body(const json& b, const std::string& path) {
  pbd::RigidBodyDesc body;
  const json& id = at(b, path, "id");
  if (!id.is_number_integer()) fail(path + "/id", "an integer");
  body.id = id.get<int>();
  body.jsonPath = at(b, path, "jsonPath").get<std::string>();
  body.isDynamic = at(b, path, "dynamic").get<bool>();
  const json& frame = at(b, path, "principalFrame");
  const json& pose = at(b, path, "pose");
  body.massProperties.mass = Real(number(b, path, "mass"));
  body.massProperties.principalInertia = vec3(b, path, "principalInertia");
  body.massProperties.centerOfMass = vec3(frame, path + "/principalFrame", "centerOfMass");
  body.massProperties.principalRotation = quat(frame, path + "/principalFrame", "rotation");
  body.translation = vec3(pose, path + "/pose", "sceneOrigin");
  body.rotation = quat(pose, path + "/pose", "rotation");
  body.velocity = vec3(b, path, "velocity");
  body.angularVelocity = vec3(b, path, "angularVelocity");
  body.collision = collision(at(b, path, "shape"), path + "/shape");
  if (b.contains("geometry")) {
    const json& geometry = b.at("geometry");
    body.geometryFile = at(geometry, path + "/geometry", "file").get<std::string>();
    body.scale = vec3(geometry, path + "/geometry", "scale");
    // As the scene's loader read it (older resolved scenes: the seed's single precision).
    pbd::ObjPrecision precision = pbd::ObjPrecision::Single;
    if (geometry.contains("precision")) {
      const json& name = geometry.at("precision");
      if (name == "double")
        precision = pbd::ObjPrecision::Double;
      else if (name != "single")
        fail(path + "/geometry/precision", "\"single\" or \"double\"");
    }
    pbd::TriangleMesh mesh = pbd::loadObj(body.geometryFile, precision);
    for (Vector3& vertex : mesh.vertices)
      vertex = vertex.cwiseProduct(body.scale);  // as the scene loader scales it
    body.mesh = std::make_shared<const pbd::TriangleMesh>(std::move(mesh));
  }
  return body;
}

pbd::JointType jointType(const json& j, const std::string& path) {
  const std::string name = at(j, path, "type").get<std::string>();
  for (int t = 0; t < pbd::kJointTypeCount; ++t)
    if (name == pbd::jointTypeName(pbd::JointType(t))) return pbd::JointType(t);
  fail(path + "/type", "a joint type (ball, hinge, ...), got \"" + name + "\"");
}

}  // namespace

pbd::Scene rigidSceneFromResolvedJson(const json& resolved) {
  pbd::Scene scene;
  scene.simulation.timeStepSize = Real(number(resolved, "", "timeStepSize"));
  scene.simulation.gravitation = vec3(resolved, "", "gravity");
  std::map<int, int> indexOfId;
  const json& bodies = at(resolved, "", "bodies");
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    scene.rigidBodies.push_back(body(bodies[i], "/bodies/" + std::to_string(i)));
    indexOfId[scene.rigidBodies.back().id] = int(i);
  }
  auto index = [&](const json& id, const std::string& path) {
    if (id.is_null()) return -1;
    if (!id.is_number_integer() || !indexOfId.count(id.get<int>()))
      fail(path, "the id of one of the bodies, or null");
    return indexOfId.at(id.get<int>());
  };
  const json& joints = at(resolved, "", "joints");
  for (std::size_t k = 0; k < joints.size(); ++k) {
    const json& j = joints[k];
    const std::string path = "/joints/" + std::to_string(k);
    pbd::JointDesc joint;
    joint.type = jointType(j, path);
    joint.jsonPath = at(j, path, "jsonPath").get<std::string>();
    joint.body1 = index(at(j, path, "body1"), path + "/body1");
    joint.body2 = index(at(j, path, "body2"), path + "/body2");
    joint.bodyId1 = joint.body1 < 0 ? -1 : scene.rigidBodies[std::size_t(joint.body1)].id;
    joint.bodyId2 = joint.body2 < 0 ? -1 : scene.rigidBodies[std::size_t(joint.body2)].id;
    const json& points = at(j, path, "points");
    const json& axes = at(j, path, "axes");
    if (points.contains("anchor"))
      joint.position = vec3(points.at("anchor"), path + "/points/anchor", "world");
    if (points.contains("anchor1"))
      joint.position1 = vec3(points.at("anchor1"), path + "/points/anchor1", "world");
    if (points.contains("anchor2"))
      joint.position2 = vec3(points.at("anchor2"), path + "/points/anchor2", "world");
    if (axes.contains("axis")) joint.axis = vec3(axes.at("axis"), path + "/axes/axis", "world");
    if (axes.contains("axis1")) joint.axis1 = vec3(axes.at("axis1"), path + "/axes/axis1", "world");
    if (axes.contains("axis2")) joint.axis2 = vec3(axes.at("axis2"), path + "/axes/axis2", "world");
    if (j.contains("stiffness")) joint.stiffness = Real(number(j, path, "stiffness"));
    if (j.contains("particle")) joint.particle = at(j, path, "particle").get<int>();
    if (j.contains("target")) {
      const json& target = j.at("target");
      joint.target.constant = Real(number(target, path + "/target", "constant"));
      for (const json& t : at(target, path + "/target", "times"))
        joint.target.times.push_back(Real(t.get<double>()));
      for (const json& v : at(target, path + "/target", "values"))
        joint.target.values.push_back(Real(v.get<double>()));
      joint.target.repeat = at(target, path + "/target", "repeat").get<bool>();
    }
    scene.joints.push_back(joint);
  }
  const json& pairs = at(resolved, "", "contactPairs");
  for (std::size_t p = 0; p < pairs.size(); ++p) {
    const std::string path = "/contactPairs/" + std::to_string(p);
    const json& ids = at(pairs[p], path, "bodies");
    if (!ids.is_array() || ids.size() != 2) fail(path + "/bodies", "two body ids");
    pbd::ContactPairDesc pair;
    pair.jsonPath = path;
    pair.body1 = index(ids[0], path + "/bodies/0");
    pair.body2 = index(ids[1], path + "/bodies/1");
    pair.bodyId1 = ids[0].get<int>();
    pair.bodyId2 = ids[1].get<int>();
    pair.hasFriction = pair.hasRestitution = true;
    pair.friction = Real(number(pairs[p], path, "friction"));
    pair.restitution = Real(number(pairs[p], path, "restitution"));
    scene.contactPairs.push_back(pair);
  }
  return scene;
}

}  // namespace pbdval
