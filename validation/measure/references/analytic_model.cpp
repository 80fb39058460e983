#include "validation/measure/references/analytic_model.h"

#include <stdexcept>

namespace pbdval {

namespace {

std::vector<int> bodiesWhere(const pbd::Scene& scene, bool dynamic) {
  std::vector<int> out;
  for (std::size_t i = 0; i < scene.rigidBodies.size(); ++i)
    if (scene.rigidBodies[i].isDynamic == dynamic) out.push_back(int(i));
  return out;
}

int indexOfId(const ReferenceParameters& parameters, const pbd::Scene& scene, int id,
              const std::string& key) {
  const int index = scene.bodyIndexById(id);
  if (index < 0)
    parameters.fail(key, "the id of a rigid body (no body has id " + std::to_string(id) + ")");
  return index;
}

}  // namespace

const pbd::RigidBodyDesc& bodyAt(const pbd::Scene& scene, int index) {
  return scene.rigidBodies.at(static_cast<std::size_t>(index));
}

int describedBody(const ModelContext& context, const ReferenceParameters& parameters) {
  const pbd::Scene& scene = *context.scene;
  const std::vector<int>& ids = context.spec->bodyIds;
  int index = -1;
  if (const std::optional<int> id = parameters.integer("body")) {
    index = indexOfId(parameters, scene, *id, "body");
    if (!ids.empty() && (ids.size() != 1 || ids.front() != *id))
      parameters.fail("body", "the body named in Validation.reference.bodies");
  } else if (ids.size() == 1) {
    index = scene.bodyIndexById(ids.front());
    if (index < 0)
      parameters.failModel("Validation.reference.bodies: no body has id " +
                           std::to_string(ids.front()));
  } else if (ids.size() > 1) {
    parameters.failModel("describes one body, but Validation.reference.bodies names " +
                         std::to_string(ids.size()));
  } else {
    const std::vector<int> dynamic = bodiesWhere(scene, true);
    if (dynamic.size() != 1)
      parameters.fail("body", "the scene id of the body (the scene has " +
                                  std::to_string(dynamic.size()) + " dynamic bodies)");
    index = dynamic.front();
  }
  if (!bodyAt(scene, index).isDynamic)
    parameters.fail("body", "a dynamic body (" + bodyAt(scene, index).jsonPath + " is static)");
  return index;
}

std::vector<int> describedBodies(const ModelContext& context,
                                 const ReferenceParameters& parameters) {
  const pbd::Scene& scene = *context.scene;
  std::vector<int> out;
  for (const int id : context.spec->bodyIds) {
    const int index = scene.bodyIndexById(id);
    if (index < 0)
      parameters.failModel("Validation.reference.bodies: no body has id " + std::to_string(id));
    if (!bodyAt(scene, index).isDynamic)
      parameters.failModel("Validation.reference.bodies: " + bodyAt(scene, index).jsonPath +
                           " is static");
    out.push_back(index);
  }
  if (out.empty()) out = bodiesWhere(scene, true);
  if (out.empty()) parameters.failModel("the scene has no dynamic body");
  return out;
}

int groundBody(const ModelContext& context, const ReferenceParameters& parameters) {
  const pbd::Scene& scene = *context.scene;
  if (const std::optional<int> id = parameters.integer("ground")) {
    const int index = indexOfId(parameters, scene, *id, "ground");
    if (bodyAt(scene, index).isDynamic) parameters.fail("ground", "the id of a static body");
    return index;
  }
  const std::vector<int> fixed = bodiesWhere(scene, false);
  if (fixed.size() != 1)
    parameters.fail("ground", "the scene id of the static ground body (the scene has " +
                                  std::to_string(fixed.size()) + " static bodies)");
  return fixed.front();
}

Vector3 planeNormal(const ModelContext& context, const ReferenceParameters& parameters,
                    int ground) {
  if (const std::optional<Vector3> normal = parameters.direction("normal")) return *normal;
  return bodyAt(*context.scene, ground).rotation.normalized() * Vector3::UnitY();
}

double sphereRadius(const ModelContext& context, const ReferenceParameters& parameters, int body) {
  if (const std::optional<double> radius = parameters.positiveNumber("radius")) return *radius;
  const pbd::RigidBodyDesc& desc = bodyAt(*context.scene, body);
  if (desc.collision.type != pbd::CollisionObjectType::Sphere || !(desc.collision.scale[0] > 0))
    parameters.fail("radius", "a positive number (" + desc.jsonPath +
                                  " has no sphere collision object to take it from)");
  return double(desc.collision.scale[0]);
}

Quaternion rotationAbout(const Vector3& axis, double angle) {
  return Quaternion(Eigen::AngleAxis<pbd::Real>(pbd::Real(angle), axis.normalized()));
}

}  // namespace pbdval
