// RigidBodies[]: the seed's keys, the extension keys `mass` / `inertia`, and the mass
// properties every engine uses (volume integration of the scaled mesh, or the closed forms of
// the primitives).
#include <cctype>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>

#include "pbd/collision/distance_grid.h"
#include "pbd/io/discregrid_file.h"
#include "pbd/io/scene_loader.h"
#include "scene_reading.h"

namespace pbd::scene_io {
namespace {

struct RigidBodyInput {
  RigidBodyDesc desc;
  PoseInput pose;
  std::optional<Real> mass;
  std::optional<Vector3> inertia;  ///< principal moments about the centre of mass, scene axes
};

/// Principal moments must be positive and satisfy Ia + Ib >= Ic for every ordering.
Vector3 readPrincipalInertia(const JsonValue& value) {
  const Vector3 moments = value.vector3(positive());
  // Relative slack of 1e-6: moments written with 7 significant digits, such as those of a
  // thin plate (Ic = Ia + Ib), must not fail on the rounding of the last digit.
  const Real slack = Real(1e-6) * moments.maxCoeff();
  for (int c = 0; c < 3; ++c) {
    if (moments[(c + 1) % 3] + moments[(c + 2) % 3] + slack < moments[c]) {
      value.fail(
          "principal moments [Ixx, Iyy, Izz] > 0 with Ia + Ib >= Ic (triangle "
          "inequality of a physical body)");
    }
  }
  return moments;
}

KeyTable<RigidBodyDesc> rigidBodyKeys(const LoadContext& context) {
  using B = RigidBodyDesc;
  return {
      integerKey("id", &B::id),
      booleanKey("isDynamic", &B::isDynamic),
      numberKey("density", &B::density, nonNegative()),  // > 0 for dynamic bodies, see below
      {"geometryFile",
       [&context](const JsonValue& v, B& b) { b.geometryFile = context.existingFile(v); }},
      vectorKey("velocity", &B::velocity, between(-kMaxSpeed, kMaxSpeed)),
      vectorKey("angularVelocity", &B::angularVelocity,
                between(-kMaxAngularSpeed, kMaxAngularSpeed)),
      numberKey("restitution", &B::restitution, between(0, 1)),
      numberKey("friction", &B::friction, nonNegative()),
      booleanKey("flatShading", &B::flatShading),
  };
}

KeyTable<RigidBodyInput> massOverrideKeys() {
  return {
      {"mass", [](const JsonValue& v,
                  RigidBodyInput& in) { in.mass = v.number(between(kMinMass, kMaxMass)); }},
      {"inertia",
       [](const JsonValue& v, RigidBodyInput& in) { in.inertia = readPrincipalInertia(v); }},
  };
}

/// A closed surface has a vanishing vector area: Σ (b − a) × (c − a) = 0. The check is
/// geometric, so meshes whose vertices are duplicated along seams still count as closed.
bool isClosedSurface(const TriangleMesh& mesh) {
  Vector3 vectorArea = Vector3::Zero();
  Real totalArea = 0;
  for (const auto& t : mesh.triangles) {
    const Vector3& a = mesh.vertices[static_cast<std::size_t>(t[0])];
    const Vector3 normal = (mesh.vertices[static_cast<std::size_t>(t[1])] - a)
                               .cross(mesh.vertices[static_cast<std::size_t>(t[2])] - a);
    vectorArea += normal;
    totalArea += normal.norm();
  }
  // √ε relative: far above the summation round-off of a closed mesh, far below the vector area
  // of any real hole.
  return totalArea > 0 && vectorArea.norm() <= std::sqrt(kEpsilon) * totalArea;
}

MassProperties meshMassProperties(RigidBodyInput& in, JsonObject& object, LoadContext& context) {
  RigidBodyDesc& body = in.desc;
  const JsonValue fileKey = *object.find("geometryFile");
  body.mesh = context.scaledObj(body.geometryFile, in.pose.scale, fileKey);
  const SolidMoments moments = integrateSolid(*body.mesh, body.density);
  const bool closed = isClosedSurface(*body.mesh);
  if (closed && moments.volume > 0) return toPrincipal(moments);
  if (body.isDynamic && !(in.mass && in.inertia)) {
    fileKey.error("the mesh " + body.geometryFile + " encloses no positive volume (" +
                  (closed ? "inside-out: volume " + formatNumber(moments.volume) : "open surface") +
                  "); a dynamic body needs a closed, outward-oriented mesh: fix the mesh, or "
                  "give \"mass\" and \"inertia\"");
  }
  return MassProperties{};  // no solid: zero, at the scene origin, in the scene axes
}

MassProperties primitiveMassProperties(const RigidBodyInput& in, JsonObject& object) {
  const RigidBodyDesc& body = in.desc;
  const Vector3& size = body.collision.scale;
  SolidMoments moments;
  switch (body.collision.type) {
    case CollisionObjectType::Sphere:
      moments = sphereMoments(size.x(), body.density);
      break;
    case CollisionObjectType::Box:
      moments = boxMoments(size, body.density);
      break;
    case CollisionObjectType::Cylinder:
      moments = cylinderMoments(size.x(), size.y(), body.density);
      break;
    default:
      return MassProperties{};
  }
  if (in.pose.scaleGiven && in.pose.scale != Vector3::Ones()) {
    object.find("scale")->warn(
        "ignored: a primitive without \"geometryFile\" takes its size from "
        "\"collisionObjectScale\"");
  }
  return toPrincipal(moments);
}

bool isPrimitiveWithClosedForm(CollisionObjectType type) {
  return type == CollisionObjectType::Sphere || type == CollisionObjectType::Box ||
         type == CollisionObjectType::Cylinder;
}

/// Applies `mass` (scaling the inertia when `inertia` is absent) and `inertia`.
void applyMassOverrides(const RigidBodyInput& in, JsonObject& object, MassProperties& props) {
  if (in.mass) {
    if (!in.inertia) {
      if (!(props.mass > 0)) {
        object.find("mass")->error(
            "cannot scale the inertia to this mass: the body has no computed mass; give "
            "\"inertia\" too");
      }
      props.principalInertia *= *in.mass / props.mass;
    }
    props.mass = *in.mass;
  }
  if (in.inertia) {
    props.principalInertia = *in.inertia;
    props.principalRotation = Quaternion::Identity();
  }
}

/// A dynamic body's mass from its density and volume must lie in [kMinMass, kMaxMass] (a given
/// `mass` is checked where it is read).
void checkMassRange(const RigidBodyInput& in, JsonObject& object, const MassProperties& props) {
  if (!in.desc.isDynamic || in.mass) return;
  if (props.mass >= kMinMass && props.mass <= kMaxMass) return;
  const std::string message =
      "the body's mass, density x volume = " + formatNumber(props.mass) + " kg, must lie in [" +
      formatNumber(kMinMass) + ", " + formatNumber(kMaxMass) +
      "] kg (results are not meaningful in double precision beyond it): change \"density\" or "
      "the size, or give \"mass\"";
  if (const auto density = object.find("density")) density->error(message);
  object.error(message);
}

MassProperties massProperties(RigidBodyInput& in, JsonObject& object, LoadContext& context) {
  MassProperties props;
  if (!in.desc.geometryFile.empty()) {
    props = meshMassProperties(in, object, context);
  } else if (isPrimitiveWithClosedForm(in.desc.collision.type)) {
    props = primitiveMassProperties(in, object);
  } else if (!(in.mass && in.inertia)) {
    object.require("geometryFile",
                   "needed unless collisionObjectType is 1, 2 or 3, or both \"mass\" and "
                   "\"inertia\" are given");
  }
  applyMassOverrides(in, object, props);
  checkMassRange(in, object, props);
  return props;
}

/// At most 256³ cells in total (kMaxGridCellsPerAxis, scene_reading.h, bounds each axis).
constexpr long long kMaxGridCells = 256LL * 256 * 256;

std::string lowerCaseExtension(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  for (char& c : extension)
    c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension;
}

/// Type 5 builds a grid from a closed mesh: collisionObjectFileName's OBJ, else the geometry. A
/// Discregrid `.csdf` (the seed reads its grid from it) is read (io/discregrid_file.h): the
/// cubic Lagrange grid is the file's; the Catmull-Rom grid is rebuilt from the geometry at the
/// file's resolution.
void readSignedDistanceFieldMesh(RigidBodyDesc& body, JsonObject& object, LoadContext& context) {
  CollisionObjectDesc& c = body.collision;
  const Vector3i& r = c.resolutionSDF;
  if (r.maxCoeff() > kMaxGridCellsPerAxis ||
      static_cast<long long>(r.x()) * r.y() * r.z() > kMaxGridCells) {
    object.find("resolutionSDF")
        ->fail("at most " + std::to_string(kMaxGridCellsPerAxis) +
               " cells per axis and 256^3 cells in total");
  }
  std::shared_ptr<const TriangleMesh> mesh = body.mesh;
  std::optional<JsonValue> meshKey = object.find("geometryFile");
  if (!c.fileName.empty() && lowerCaseExtension(c.fileName) == ".csdf") {
    const JsonValue key = *object.find("collisionObjectFileName");
    if (!mesh)
      key.fail(
          "a geometryFile beside a .csdf grid (its mass properties, and the Catmull-Rom grid, "
          "come from the mesh)");
    try {
      c.discregridGrid = std::make_shared<const DistanceGrid>(readDiscregridGrid(c.fileName));
    } catch (const SceneError& e) {
      key.error(e.what());
    }
    c.resolutionSDF = c.discregridGrid->cells();
    c.discregridFile = c.fileName;
    c.fileName.clear();
  } else if (!c.fileName.empty()) {
    meshKey = object.find("collisionObjectFileName");
    if (lowerCaseExtension(c.fileName) != ".obj" && lowerCaseExtension(c.fileName) != ".ply") {
      meshKey->fail(
          "an OBJ or PLY mesh to build the signed distance field from, or a Discregrid .csdf "
          "grid");
    }
    c.mesh = context.scaledObj(c.fileName, Vector3::Ones(), *meshKey);
    mesh = c.mesh;
  }
  if (!mesh) {
    object.find("collisionObjectType")
        ->error(
            "collisionObjectType 5 (signed distance field) needs a mesh: give "
            "\"geometryFile\" or \"collisionObjectFileName\"");
  }
  if (!isClosedSurface(*mesh)) {
    meshKey->error(
        "the mesh must be closed for its signed distance field (type 5) to have an "
        "inside: " +
        (c.fileName.empty() ? body.geometryFile : c.fileName) + " has an open surface");
  }
}

/// Checks the collision keys beyond their ranges (those need the whole body). Only type 5
/// reads collisionObjectFileName; other types ignore it, as in the seed.
void checkCollisionObject(RigidBodyDesc& body, JsonObject& object, LoadContext& context) {
  if (body.collision.type == CollisionObjectType::SignedDistanceField)
    readSignedDistanceFieldMesh(body, object, context);
}

RigidBodyDesc readRigidBody(const JsonValue& element, LoadContext& context) {
  JsonObject object = element.object();
  RigidBodyInput in;
  in.desc.jsonPath = element.path();
  readKeys(object, rigidBodyKeys(context), in.desc);
  readKeys(object, poseKeys(), in.pose);
  readKeys(object, collisionKeys(context), in.desc.collision);
  readKeys(object, massOverrideKeys(), in);

  RigidBodyDesc& body = in.desc;
  if (body.isDynamic && !(body.density > 0)) {
    object.find("density")->fail("a number > 0 for a dynamic body");
  }
  checkCollisionScale(body.collision, object);
  body.translation = in.pose.translation;
  body.scale = in.pose.scale;
  body.rotation = resolveRotation(in.pose, object);
  body.givenRotation = givenRotation(in.pose);
  body.massProperties = massProperties(in, object, context);
  body.givenMass = in.mass;
  body.givenInertia = in.inertia;
  checkCollisionObject(body, object, context);
  object.warnUnknownKeys();
  return body;
}

/// One warning per id shared by several bodies (the seed's default id is 0 for every body).
void warnDuplicateIds(const Scene& scene, DiagnosticSink& sink) {
  std::map<int, std::vector<std::size_t>> bodiesById;
  for (std::size_t i = 0; i < scene.rigidBodies.size(); ++i)
    bodiesById[scene.rigidBodies[i].id].push_back(i);
  for (const auto& [id, bodies] : bodiesById) {
    if (bodies.size() < 2) continue;
    std::string list;
    for (std::size_t i : bodies)
      list += (list.empty() ? "" : ", ") + scene.rigidBodies[i].jsonPath;
    sink.warn(scene.rigidBodies[bodies[1]].jsonPath + ".id",
              "id " + std::to_string(id) + " is shared by " + list +
                  "; CSV rows and joints can't tell these bodies apart");
  }
}

}  // namespace

void readRigidBodies(const JsonValue& block, LoadContext& context, Scene& scene) {
  for (const JsonValue& element : block.elements("rigid-body objects"))
    scene.rigidBodies.push_back(readRigidBody(element, context));
  warnDuplicateIds(scene, block.sink());
}

}  // namespace pbd::scene_io
