#include "scene_reading.h"

#include <cctype>
#include <system_error>

#include "pbd/io/mesh_loader.h"

namespace pbd::scene_io {

LoadContext::LoadContext(std::filesystem::path sceneFolder)
    : sceneFolder_(sceneFolder.empty() ? std::filesystem::path(".") : std::move(sceneFolder)) {}

std::string LoadContext::existingFile(const JsonValue& fileKey) const {
  const std::string given = fileKey.string();
  if (given.empty()) fileKey.fail("a file path");
  std::filesystem::path path(given);
  if (path.is_relative()) path = sceneFolder_ / path;
  std::error_code ignored;
  const std::filesystem::path absolute = std::filesystem::absolute(path, ignored);
  path = (absolute.empty() ? path : absolute).lexically_normal();
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) {
    fileKey.fail("an existing file (relative paths start at the scene's folder; resolved to " +
                 path.string() + ")");
  }
  return path.string();
}

const TriangleMesh& LoadContext::obj(const std::string& path, const JsonValue& fileKey) {
  auto it = objFiles_.find(path);
  if (it == objFiles_.end()) {
    try {
      it = objFiles_.emplace(path, loadSurfaceMesh(path, objPrecision_)).first;
    } catch (const SceneError& e) {
      fileKey.error(std::string("cannot load the mesh: ") + e.what());
    }
  }
  return it->second;
}

std::shared_ptr<const TriangleMesh> LoadContext::scaledObj(const std::string& path,
                                                           const Vector3& scale,
                                                           const JsonValue& fileKey) {
  const auto key = std::make_pair(path, std::array<Real, 3>{scale.x(), scale.y(), scale.z()});
  auto& cached = scaledObjs_[key];
  if (!cached) {
    TriangleMesh mesh = obj(path, fileKey);
    for (auto& vertex : mesh.vertices)
      vertex = vertex.cwiseProduct(scale);
    cached = std::make_shared<const TriangleMesh>(std::move(mesh));
  }
  return cached;
}

TetMesh LoadContext::tetGen(const std::string& nodePath, const std::string& elePath,
                            const JsonValue& fileKey) const {
  try {
    return loadTetGen(nodePath, elePath);
  } catch (const SceneError& e) {
    fileKey.error(std::string("cannot load the tet mesh: ") + e.what());
  }
}

// ---- pose -----------------------------------------------------------------------------------

KeyTable<PoseInput> poseKeys() {
  return {
      vectorKey("translation", &PoseInput::translation, between(-kMaxCoordinate, kMaxCoordinate)),
      {"scale",
       [](const JsonValue& v, PoseInput& pose) {
         // Positive: a mirroring scale would turn meshes and tetrahedra inside out.
         pose.scale = v.vector3(positive());
         pose.scaleGiven = true;
       }},
      {"rotationAxis",
       [](const JsonValue& v, PoseInput& pose) { pose.rotationAxis = v.vector3(); }},
      {"rotationAngle",
       [](const JsonValue& v, PoseInput& pose) { pose.rotationAngle = v.number(); }},
  };
}

Quaternion resolveRotation(const PoseInput& pose, JsonObject& object) {
  if (pose.rotationAxis.has_value() != pose.rotationAngle.has_value()) {
    const char* given = pose.rotationAxis ? "rotationAxis" : "rotationAngle";
    const char* missing = pose.rotationAxis ? "rotationAngle" : "rotationAxis";
    object.find(given)->warn(std::string("no rotation is applied: \"") + missing +
                             "\" is missing, and the seed rotates only when both are given");
    return Quaternion::Identity();
  }
  if (!pose.rotationAngle || *pose.rotationAngle == 0) return Quaternion::Identity();
  const Vector3& axis = *pose.rotationAxis;
  const Real norm = axis.stableNorm();
  if (!(norm > 0)) object.find("rotationAxis")->fail("a non-zero axis for a non-zero angle");
  return Quaternion(AngleAxis(*pose.rotationAngle, axis / norm));
}

std::optional<GivenRotation> givenRotation(const PoseInput& pose) {
  if (!pose.rotationAxis || !pose.rotationAngle) return std::nullopt;
  return GivenRotation{*pose.rotationAxis, *pose.rotationAngle};
}

Vector3 toWorld(const Vector3& vertex, const Vector3& scale, const Quaternion& rotation,
                const Vector3& translation) {
  return rotation * vertex.cwiseProduct(scale) + translation;
}

// ---- collision keys -------------------------------------------------------------------------

KeyTable<CollisionObjectDesc> collisionKeys(const LoadContext& context) {
  using C = CollisionObjectDesc;
  return {
      {"collisionObjectType",
       [](const JsonValue& v, C& c) {
         c.type = static_cast<CollisionObjectType>(v.integer(between(0, 7)));
       },
       false, [](const C& c, Json& j) { writeInteger(j, "collisionObjectType", int(c.type)); }},
      {"collisionObjectFileName",
       [&context](const JsonValue& v, C& c) {
         // Empty: the SDF is generated from the geometry (the seed's default).
         c.fileName = v.string().empty() ? std::string() : context.existingFile(v);
       },
       false,
       [](const C& c, Json& j) {
         if (!c.fileName.empty()) writeString(j, "collisionObjectFileName", c.fileName);
         if (!c.discregridFile.empty()) writeString(j, "collisionObjectFileName", c.discregridFile);
       }},
      booleanKey("testMesh", &C::testMesh),
      vectorKey("collisionObjectScale", &C::scale),
      booleanKey("invertSDF", &C::invertSDF),
      numberKey("thicknessSDF", &C::thicknessSDF, nonNegative()),
      {"resolutionSDF",
       [](const JsonValue& v, C& c) {
         c.resolutionSDF = v.integerVector3(between(1, kMaxGridCellsPerAxis));
       },
       false, [](const C& c, Json& j) { writeIntegerVector(j, "resolutionSDF", c.resolutionSDF); }},
  };
}

namespace {

// Which leading components of collisionObjectScale a collision type reads, and their meaning.
struct ScaleUse {
  int components;
  const char* meaning;
};

ScaleUse scaleUse(CollisionObjectType type) {
  switch (type) {
    case CollisionObjectType::None:
      return {0, ""};
    case CollisionObjectType::Sphere:
    case CollisionObjectType::HollowSphere:
      return {1, "[radius, -, -]"};
    case CollisionObjectType::Cylinder:
      return {2, "[radius, height, -]"};
    case CollisionObjectType::Torus:
      return {2, "[R, r, -]"};
    case CollisionObjectType::Box:
    case CollisionObjectType::HollowBox:
      return {3, "the full extents"};
    case CollisionObjectType::SignedDistanceField:
      return {3, "the SDF scale"};
  }
  return {0, ""};
}

}  // namespace

void checkCollisionScale(const CollisionObjectDesc& collision, JsonObject& object) {
  const ScaleUse use = scaleUse(collision.type);
  if ((collision.scale.head(use.components).array() > 0).all()) return;
  // The default [1, 1, 1] passes, so the key is present here.
  object.find("collisionObjectScale")
      ->fail("positive values for " + std::string(use.meaning) + " (collisionObjectType " +
             std::to_string(static_cast<int>(collision.type)) + ")");
}

}  // namespace pbd::scene_io
