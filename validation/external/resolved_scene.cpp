#include "validation/external/resolved_scene.h"

#include <array>
#include <filesystem>
#include <optional>
#include <stdexcept>

#include "pbd/model/mesh.h"
#include "validation/run/case_spec.h"

namespace pbdval {
namespace {

using nlohmann::json;
using pbd::CollisionObjectType;
using pbd::JointType;
using pbd::Quaternion;
using pbd::Vector3;

json vec(const Vector3& v) {
  return json::array({double(v.x()), double(v.y()), double(v.z())});
}

/// w, x, y, z with w ≥ 0 (the trajectory CSV's convention).
json quat(const Quaternion& q) {
  const Quaternion n = q.w() < 0 ? Quaternion(-q.coeffs()) : q;
  return json::array({double(n.w()), double(n.x()), double(n.y()), double(n.z())});
}

std::string absolutePath(const std::string& path) {
  if (path.empty()) return {};
  return std::filesystem::absolute(path).lexically_normal().string();
}

const char* shapeTypeName(CollisionObjectType type) {
  switch (type) {
    case CollisionObjectType::None:
      return "none";
    case CollisionObjectType::Sphere:
      return "sphere";
    case CollisionObjectType::Box:
      return "box";
    case CollisionObjectType::Cylinder:
      return "cylinder";
    case CollisionObjectType::Torus:
      return "torus";
    case CollisionObjectType::SignedDistanceField:
      return "sdf";
    case CollisionObjectType::HollowSphere:
      return "hollowSphere";
    case CollisionObjectType::HollowBox:
      return "hollowBox";
  }
  return "none";
}

/// The collision shape in the body's scene frame (pbd/collision/collision_shape.h).
json shapeJson(const pbd::RigidBodyDesc& body) {
  const pbd::CollisionObjectDesc& c = body.collision;
  json shape = {{"type", shapeTypeName(c.type)}, {"collisionObjectType", static_cast<int>(c.type)}};
  if (c.type == CollisionObjectType::None) return shape;
  shape["inverted"] = c.invertSDF;
  switch (c.type) {
    case CollisionObjectType::Sphere:
      shape["radius"] = double(c.scale.x());
      break;
    case CollisionObjectType::Box:
      shape["halfExtents"] = vec(c.scale / 2);
      break;
    case CollisionObjectType::Cylinder:
      shape["radius"] = double(c.scale.x());
      shape["height"] = double(c.scale.y());
      shape["axis"] = vec(Vector3::UnitY());
      break;
    case CollisionObjectType::Torus:
      shape["majorRadius"] = double(c.scale.x());
      shape["minorRadius"] = double(c.scale.y());
      shape["axis"] = vec(Vector3::UnitY());
      break;
    case CollisionObjectType::SignedDistanceField:
      shape["meshFile"] = absolutePath(c.fileName.empty() ? body.geometryFile : c.fileName);
      shape["meshScale"] = vec(c.scale);
      shape["resolution"] =
          json::array({c.resolutionSDF.x(), c.resolutionSDF.y(), c.resolutionSDF.z()});
      break;
    case CollisionObjectType::HollowSphere:
      shape["radius"] = double(c.scale.x());
      shape["wallHalfThickness"] = double(c.thicknessSDF);
      break;
    case CollisionObjectType::HollowBox:
      shape["halfExtents"] = vec(c.scale / 2);
      shape["wallHalfThickness"] = double(c.thicknessSDF);
      break;
    case CollisionObjectType::None:
      break;
  }
  return shape;
}

json bodyJson(const pbd::RigidBodyDesc& body, int index, pbd::ObjPrecision objPrecision) {
  const pbd::MassProperties& m = body.massProperties;
  json b = {
      {"id", body.id},
      {"index", index},
      {"jsonPath", body.jsonPath},
      {"dynamic", body.isDynamic},
      {"mass", body.isDynamic ? double(m.mass) : 0.0},
      {"principalInertia", body.isDynamic ? vec(m.principalInertia) : vec(Vector3::Zero())},
      {"principalFrame",
       {{"centerOfMass", vec(m.centerOfMass)}, {"rotation", quat(m.principalRotation)}}},
      {"pose",
       {{"position", vec(body.initialCenterOfMass())},
        {"rotation", quat(body.rotation)},
        {"sceneOrigin", vec(body.translation)},
        {"principalRotation", quat(body.initialPrincipalRotation())}}},
      {"velocity", vec(body.velocity)},
      {"angularVelocity", vec(body.angularVelocity)},
      {"shape", shapeJson(body)},
      {"material",
       {{"friction", double(body.friction)}, {"restitution", double(body.restitution)}}},
  };
  // `precision`: how the scene's loader read the OBJ's coordinates (Simulation.objPrecision),
  // so that a reader of the file gets the vertices the built-in engines got.
  if (!body.geometryFile.empty())
    b["geometry"] = {{"file", absolutePath(body.geometryFile)},
                     {"scale", vec(body.scale)},
                     {"precision", pbd::objPrecisionName(objPrecision)}};
  return b;
}

/// A world point or direction at t = 0 in one body's scene frame and principal frame.
json pointInBody(const pbd::RigidBodyDesc& body, const Vector3& world) {
  const Vector3 scene = body.rotation.conjugate() * (world - body.translation);
  const pbd::MassProperties& m = body.massProperties;
  const Vector3 principal = m.principalRotation.conjugate() * (scene - m.centerOfMass);
  return {{"scene", vec(scene)}, {"principal", vec(principal)}};
}

json axisInBody(const pbd::RigidBodyDesc& body, const Vector3& world) {
  const Vector3 scene = body.rotation.conjugate() * world;
  const Vector3 principal = body.massProperties.principalRotation.conjugate() * scene;
  return {{"scene", vec(scene)}, {"principal", vec(principal)}};
}

bool hasAnchorPosition(JointType type) {
  return type != JointType::Distance && type != JointType::RigidBodySpring &&
         type != JointType::RigidBodyParticleBall;
}

bool hasSingleAxis(JointType type) {
  switch (type) {
    case JointType::Hinge:
    case JointType::Slider:
    case JointType::BallOnLine:
    case JointType::Damper:
    case JointType::TargetAngleMotorHinge:
    case JointType::TargetVelocityMotorHinge:
    case JointType::TargetPositionMotorSlider:
    case JointType::TargetVelocityMotorSlider:
      return true;
    default:
      return false;
  }
}

bool isMotor(JointType type) {
  return type == JointType::TargetAngleMotorHinge || type == JointType::TargetVelocityMotorHinge ||
         type == JointType::TargetPositionMotorSlider ||
         type == JointType::TargetVelocityMotorSlider;
}

json jointJson(const pbd::Scene& scene, const pbd::JointDesc& joint) {
  const pbd::RigidBodyDesc* body1 =
      joint.body1 >= 0 ? &scene.rigidBodies[static_cast<std::size_t>(joint.body1)] : nullptr;
  const pbd::RigidBodyDesc* body2 =
      joint.body2 >= 0 ? &scene.rigidBodies[static_cast<std::size_t>(joint.body2)] : nullptr;
  json j = {{"type", pbd::jointTypeName(joint.type)},
            {"block", pbd::jointBlockName(joint.type)},
            {"jsonPath", joint.jsonPath},
            {"body1", body1 ? json(body1->id) : json(nullptr)},
            {"body2", body2 ? json(body2->id) : json(nullptr)}};
  auto point = [&](const Vector3& world) {
    json p = {{"world", vec(world)}};
    if (body1) p["body1"] = pointInBody(*body1, world);
    if (body2) p["body2"] = pointInBody(*body2, world);
    return p;
  };
  auto axis = [&](const Vector3& world) {
    json a = {{"world", vec(world)}};
    if (body1) a["body1"] = axisInBody(*body1, world);
    if (body2) a["body2"] = axisInBody(*body2, world);
    return a;
  };
  json points = json::object(), axes = json::object();
  if (hasAnchorPosition(joint.type)) points["anchor"] = point(joint.position);
  if (joint.type == JointType::Distance || joint.type == JointType::RigidBodySpring) {
    points["anchor1"] = point(joint.position1);
    points["anchor2"] = point(joint.position2);
    j["restLength"] = double((joint.position2 - joint.position1).norm());
  }
  if (joint.type == JointType::RigidBodyParticleBall) {
    j["particle"] = joint.particle;
    points["anchor"] = point(scene.particles[static_cast<std::size_t>(joint.particle)].position);
  }
  if (hasSingleAxis(joint.type)) axes["axis"] = axis(joint.axis);
  if (joint.type == JointType::Universal) {
    axes["axis1"] = axis(joint.axis1);
    axes["axis2"] = axis(joint.axis2);
  }
  j["points"] = points;
  j["axes"] = axes;
  if (joint.type == JointType::RigidBodySpring || joint.type == JointType::Damper)
    j["stiffness"] = double(joint.stiffness);
  if (isMotor(joint.type)) {
    json values = json::array(), times = json::array();
    for (std::size_t i = 0; i < joint.target.times.size(); ++i) {
      times.push_back(double(joint.target.times[i]));
      values.push_back(double(joint.target.values[i]));
    }
    j["target"] = {{"constant", double(joint.target.constant)},
                   {"times", times},
                   {"values", values},
                   {"repeat", joint.target.repeat}};
  }
  return j;
}

json contactPairsJson(const pbd::Scene& scene) {
  json pairs = json::array();
  const auto& bodies = scene.rigidBodies;
  for (std::size_t a = 0; a < bodies.size(); ++a)
    for (std::size_t b = a + 1; b < bodies.size(); ++b) {
      if (bodies[a].collision.type == CollisionObjectType::None ||
          bodies[b].collision.type == CollisionObjectType::None)
        continue;
      if (!bodies[a].isDynamic && !bodies[b].isDynamic) continue;
      bool isExplicit = false;
      for (const pbd::ContactPairDesc& p : scene.contactPairs)
        if ((p.body1 == int(a) && p.body2 == int(b)) || (p.body1 == int(b) && p.body2 == int(a)))
          isExplicit = true;
      const pbd::ContactMaterial m = scene.pairMaterial(int(a), int(b));
      pairs.push_back({{"bodies", json::array({bodies[a].id, bodies[b].id})},
                       {"friction", double(m.friction)},
                       {"restitution", double(m.restitution)},
                       {"explicit", isExplicit}});
    }
  return pairs;
}

/// Element index lists made local to a model (global particle index − firstParticle).
template <std::size_t N>
json localElements(const std::vector<std::array<int, N>>& elements) {
  json list = json::array();
  for (const std::array<int, N>& element : elements) {
    json indices = json::array();
    for (int i : element)
      indices.push_back(i);
    list.push_back(std::move(indices));
  }
  return list;
}

json optionalNumber(const std::optional<pbd::Real>& value) {
  return value ? json(double(*value)) : json(nullptr);
}

const char* clothMethodName(int method) {
  static const char* const kNames[] = {"none", "distance", "fem", "strain", "xpbd_distance"};
  return method >= 0 && method < 5 ? kNames[method] : "unknown";
}

const char* clothBendingMethodName(int method) {
  static const char* const kNames[] = {"none", "dihedral", "isometric", "isometric_xpbd"};
  return method >= 0 && method < 4 ? kNames[method] : "unknown";
}

const char* solidMethodName(int method) {
  static const char* const kNames[] = {
      "none",           "distance_volume",     "fem", "fem_xpbd", "strain",
      "shape_matching", "xpbd_distance_volume"};
  return method >= 0 && method < 7 ? kNames[method] : "unknown";
}

/// A triangle model with its topology and the cloth settings resolved for it (the Simulation
/// block's, with the seed's forced defaults applied).
json triangleModelJson(const pbd::TriangleModelDesc& model, const pbd::SimulationSettings& sim) {
  const int method = sim.clothSimulationMethod;
  return {{"id", model.id},
          {"jsonPath", model.jsonPath},
          {"firstParticle", model.firstParticle},
          {"particleCount", model.mesh.vertices.size()},
          {"triangles", localElements(model.mesh.triangles)},
          {"staticParticles", model.staticParticles},
          {"density", optionalNumber(model.density)},
          {"friction", double(model.friction)},
          {"restitution", double(model.restitution)},
          {"simulationMethod", method},
          {"methodName", clothMethodName(method)},
          {"bendingMethod", method == 0 ? 0 : sim.clothBendingMethod},
          {"bendingMethodName", clothBendingMethodName(method == 0 ? 0 : sim.clothBendingMethod)},
          {"material",
           {{"stiffness", double(pbd::clothStiffnessFor(sim))},
            {"bendingStiffness", double(pbd::clothBendingStiffnessFor(sim))},
            {"xxStiffness", double(sim.cloth_xxStiffness)},
            {"yyStiffness", double(sim.cloth_yyStiffness)},
            {"xyStiffness", double(sim.cloth_xyStiffness)},
            {"xyPoissonRatio", double(sim.cloth_xyPoissonRatio)},
            {"yxPoissonRatio", double(sim.cloth_yxPoissonRatio)},
            {"normalizeStretch", sim.cloth_normalizeStretch},
            {"normalizeShear", sim.cloth_normalizeShear}}}};
}

/// A tet model with its topology, its boundary faces (counter-clockwise seen from outside) and
/// the solid settings resolved for it.
json tetModelJson(const pbd::TetModelDesc& model, const pbd::SimulationSettings& sim) {
  const int method = sim.solidSimulationMethod;
  return {{"id", model.id},
          {"jsonPath", model.jsonPath},
          {"firstParticle", model.firstParticle},
          {"particleCount", model.mesh.vertices.size()},
          {"tets", localElements(model.mesh.tetrahedra)},
          {"boundaryFaces", localElements(pbd::boundaryFaces(model.mesh))},
          {"staticParticles", model.staticParticles},
          {"density", optionalNumber(model.density)},
          {"friction", double(model.friction)},
          {"restitution", double(model.restitution)},
          {"simulationMethod", method},
          {"methodName", solidMethodName(method)},
          {"material",
           {{"stiffness", double(pbd::solidStiffnessFor(sim))},
            {"poissonRatio", double(sim.solid_poissonRatio)},
            {"volumeStiffness", double(pbd::solidVolumeStiffnessFor(sim))},
            {"normalizeStretch", sim.solid_normalizeStretch},
            {"normalizeShear", sim.solid_normalizeShear}}}};
}

}  // namespace

RunLength caseRunLength(const pbd::Scene& scene, const EngineRegistry& registry) {
  const CaseSpec spec = parseCaseSpec(scene, registry);
  RunLength length;
  length.duration = defaultDuration(scene, spec);
  length.sampleInterval = spec.sampleInterval.value_or(0);
  return length;
}

json resolvedSceneJson(const pbd::Scene& scene, const std::string& methodName,
                       const json& methodParameters, const RunLength& length) {
  if (!methodParameters.is_object())
    throw std::invalid_argument("method parameters: expected a JSON object, got " +
                                std::string(methodParameters.type_name()));
  const double h = double(scene.simulation.timeStepSize);
  const StepPlan plan = planSteps(length, h);
  const pbd::SimulationSettings& sim = scene.simulation;

  json bodies = json::array();
  for (std::size_t i = 0; i < scene.rigidBodies.size(); ++i)
    bodies.push_back(bodyJson(scene.rigidBodies[i], int(i), scene.simulation.objPrecision));
  json joints = json::array();
  for (const pbd::JointDesc& joint : scene.joints)
    joints.push_back(jointJson(scene, joint));
  json particles = json::array();
  for (const pbd::ParticleDesc& p : scene.particles)
    particles.push_back(
        {{"position", vec(p.position)}, {"velocity", vec(p.velocity)}, {"mass", double(p.mass)}});

  json triangleModels = json::array();
  for (const pbd::TriangleModelDesc& model : scene.triangleModels)
    triangleModels.push_back(triangleModelJson(model, sim));
  json tetModels = json::array();
  for (const pbd::TetModelDesc& model : scene.tetModels)
    tetModels.push_back(tetModelJson(model, sim));

  return {
      {"format", kResolvedSceneFormat},
      {"version", kResolvedSceneVersion},
      {"source", absolutePath(scene.sourceFile)},
      {"name", scene.name},
      {"units", {{"length", "m"}, {"mass", "kg"}, {"time", "s"}, {"angle", "rad"}}},
      {"conventions",
       {{"quaternion",
         "w,x,y,z (w >= 0), unit, rotating body-frame coordinates into the "
         "parent frame"},
        {"world", "right-handed; gravity as given (the seed's scenes use -y)"},
        {"sceneFrame", "a body's frame of its geometry file; pose.rotation maps it to world"},
        {"principalFrame",
         "at the centre of mass along the principal axes; "
         "principalFrame.rotation maps it into the scene frame, "
         "principalFrame.centerOfMass is its origin in the scene frame"}}},
      {"method", {{"name", methodName}, {"parameters", methodParameters}}},
      {"gravity", vec(sim.gravitation)},
      {"timeStepSize", h},
      {"duration", length.duration},
      {"sampleInterval", length.sampleInterval},
      {"steps", plan.steps},
      {"sampleStride", plan.stride},
      {"contactTolerance", double(sim.contactTolerance)},
      {"contactCombineRule", pbd::contactCombineRuleName(sim.contactCombineRule)},
      {"bodies", bodies},
      {"joints", joints},
      {"contactPairs", contactPairsJson(scene)},
      {"particles", particles},
      {"deformables",
       {{"triangleModels", scene.triangleModels.size()},
        {"tetModels", scene.tetModels.size()},
        {"lineModels", scene.lineModels.size()},
        {"fluidModels", scene.fluidModels.size()}}},
      {"triangleModels", triangleModels},
      {"tetModels", tetModels},
  };
}

nlohmann::json methodParametersJson(const Method& method) {
  nlohmann::json parameters = nlohmann::json::object();
  for (const auto& [key, value] : method.values) {
    switch (value.kind) {
      case ParameterKind::Real:
        parameters[key] = value.number;
        break;
      case ParameterKind::Integer:
        parameters[key] = static_cast<std::int64_t>(value.number);
        break;
      case ParameterKind::Bool:
        parameters[key] = value.number != 0;
        break;
      case ParameterKind::Choice:
        parameters[key] = value.choice;
        break;
      case ParameterKind::Duration:
        parameters[key] = value.text();  // "4h" or seconds: external kinds have no duration
        break;
    }
  }
  return parameters;
}

}  // namespace pbdval
