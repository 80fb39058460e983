#include "validation/measure/oracle/fcl_geometry.h"

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/convex.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/math/bv/OBBRSS.h>

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "validation/measure/oracle/mesh_geometry.h"

namespace pbdval::fcl_oracle {
namespace {

using pbd::CollisionObjectType;
using pbd::RigidBodyDesc;

std::string format(double value) {
  std::ostringstream out;
  out.precision(4);
  out << value;
  return out.str();
}

std::string formatVector(const Vector3& v) {
  return "(" + format(v.x()) + ", " + format(v.y()) + ", " + format(v.z()) + ")";
}

/// Throws std::invalid_argument unless every triangle indexes an existing vertex.
void checkMesh(const RigidBodyDesc& body, const pbd::TriangleMesh& mesh) {
  if (mesh.triangles.empty()) {
    throw std::invalid_argument(body.jsonPath + ": the collision mesh has no triangles");
  }
  const int vertexCount = static_cast<int>(mesh.vertices.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (const int index : mesh.triangles[t]) {
      if (index < 0 || index >= vertexCount) {
        throw std::invalid_argument(body.jsonPath + ": triangle " + std::to_string(t) +
                                    " refers to vertex " + std::to_string(index) +
                                    ", the mesh has " + std::to_string(vertexCount));
      }
    }
  }
}

BodyGeometry sphereGeometry(double radius) {
  BodyGeometry g;
  g.shape = OracleShape::Sphere;
  g.geometry = std::make_shared<fcl::Sphered>(radius);
  g.sphereRadius = radius;
  g.description = "sphere r = " + format(radius);
  return g;
}

BodyGeometry boxGeometry(const Vector3& extents) {
  BodyGeometry g;
  g.shape = OracleShape::Box;
  g.geometry = std::make_shared<fcl::Boxd>(extents.cast<double>());
  g.description =
      "box " + format(extents.x()) + " × " + format(extents.y()) + " × " + format(extents.z());
  return g;
}

/// FCL's cylinder is centred on its origin with its axis along z; the seed's along y.
BodyGeometry cylinderGeometry(double radius, double height) {
  BodyGeometry g;
  g.shape = OracleShape::Cylinder;
  g.geometry = std::make_shared<fcl::Cylinderd>(radius, height);
  g.geometryInSceneFrame.linear() =
      fcl::AngleAxisd(-M_PI / 2, fcl::Vector3d::UnitX()).toRotationMatrix();  // z → y
  g.description = "cylinder r = " + format(radius) + ", h = " + format(height) + " (axis y)";
  return g;
}

std::shared_ptr<fcl::Convexd> makeConvex(const pbd::TriangleMesh& mesh) {
  auto vertices = std::make_shared<std::vector<fcl::Vector3d>>();
  vertices->reserve(mesh.vertices.size());
  for (const Vector3& v : mesh.vertices) {
    vertices->push_back(v.cast<double>());
  }
  auto faces = std::make_shared<std::vector<int>>();
  faces->reserve(4 * mesh.triangles.size());
  for (const auto& triangle : mesh.triangles) {
    faces->insert(faces->end(), {3, triangle[0], triangle[1], triangle[2]});
  }
  return std::make_shared<fcl::Convexd>(vertices, static_cast<int>(mesh.triangles.size()), faces,
                                        /*throw_if_invalid=*/true);
}

std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> makeBvh(const pbd::TriangleMesh& mesh) {
  std::vector<fcl::Vector3d> vertices;
  vertices.reserve(mesh.vertices.size());
  for (const Vector3& v : mesh.vertices) {
    vertices.push_back(v.cast<double>());
  }
  std::vector<fcl::Triangle> triangles;
  triangles.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles) {
    triangles.emplace_back(t[0], t[1], t[2]);
  }
  auto model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
  model->beginModel(static_cast<int>(triangles.size()), static_cast<int>(vertices.size()));
  model->addSubModel(vertices, triangles);
  model->endModel();
  model->computeLocalAABB();
  return model;
}

BodyGeometry triangleMeshGeometry(const pbd::TriangleMesh& mesh) {
  BodyGeometry g;
  g.shape = OracleShape::TriangleMesh;
  g.geometry = makeBvh(mesh);
  auto data = std::make_shared<MeshData>();
  data->mesh = mesh;
  data->neighbours = vertexNeighbours(mesh);
  g.mesh = std::move(data);
  g.description = "triangle mesh (" + std::to_string(mesh.triangles.size()) + " triangles)";
  return g;
}

/// A convex mesh becomes an FCL Convex (exact GJK/EPA), any other a BVH of triangles. A convex
/// mesh that FCL's Convex rejects (not closed) falls back to the BVH, with a note.
BodyGeometry meshGeometry(const RigidBodyDesc& body, const pbd::TriangleMesh& mesh,
                          std::vector<std::string>& notes) {
  checkMesh(body, mesh);
  if (!isConvex(mesh)) return triangleMeshGeometry(mesh);
  try {
    BodyGeometry g;
    g.shape = OracleShape::ConvexMesh;
    g.geometry = makeConvex(mesh);
    g.description = "convex mesh (" + std::to_string(mesh.vertices.size()) + " vertices)";
    return g;
  } catch (const std::exception& error) {
    notes.push_back(body.jsonPath + ": convex mesh rejected by FCL's Convex (" + error.what() +
                    "); represented as a triangle mesh");
    return triangleMeshGeometry(mesh);
  }
}

BodyGeometry unsupportedBody(int index, const RigidBodyDesc& body, std::string reason,
                             std::vector<UnsupportedBody>& unsupported) {
  unsupported.push_back({index, body.jsonPath, std::move(reason)});
  BodyGeometry g;
  g.shape = OracleShape::Unsupported;
  g.description = "unsupported: " + unsupported.back().reason;
  return g;
}

/// The seed places analytic collision shapes in the body's principal frame; the oracle (like
/// every pbdval engine) in the scene frame. Say so where the two differ.
void notePrimitiveFrame(const RigidBodyDesc& body, const std::string& shapeName,
                        std::vector<std::string>& notes) {
  const pbd::MassProperties& mass = body.massProperties;
  const bool centred = mass.centerOfMass.norm() <= 1e-12;
  const bool aligned = mass.principalRotation.angularDistance(Quaternion::Identity()) <= 1e-12;
  if (centred && aligned) return;
  notes.push_back(body.jsonPath + ": the " + shapeName +
                  " is placed in the scene frame; the seed places it on the centre of mass " +
                  formatVector(mass.centerOfMass) + ", in the principal axes");
}

BodyGeometry torusBody(int index, const RigidBodyDesc& body, SceneGeometry& out) {
  const double major = body.collision.scale.x(), minor = body.collision.scale.y();
  if (!body.mesh) {
    return unsupportedBody(index, body,
                           "torus without geometryFile: FCL has no torus primitive and there is "
                           "no mesh to stand for it",
                           out.unsupported);
  }
  BodyGeometry g = meshGeometry(body, *body.mesh, out.notes);
  out.notes.push_back(body.jsonPath + ": torus (R = " + format(major) + ", r = " + format(minor) +
                      ") represented by its mesh, which deviates from it by up to " +
                      format(torusDeviation(*body.mesh, major, minor)) + " m");
  notePrimitiveFrame(body, "torus", out.notes);
  return g;
}

/// The seed builds the SDF from the unscaled geometry file and scales it by
/// collisionObjectScale; Scene meshes are scaled by `scale`.
BodyGeometry sdfBody(int index, const RigidBodyDesc& body, SceneGeometry& out) {
  if (!body.collision.fileName.empty()) {
    return unsupportedBody(index, body,
                           "SDF read from " + body.collision.fileName +
                               ": the oracle does not read SDF files (leave "
                               "collisionObjectFileName empty to use the geometry's mesh)",
                           out.unsupported);
  }
  if (!body.mesh) {
    return unsupportedBody(index, body, "SDF without geometryFile: no mesh to build it from",
                           out.unsupported);
  }
  pbd::TriangleMesh mesh = *body.mesh;
  const Vector3 rescale = body.collision.scale.cwiseQuotient(body.scale);
  for (Vector3& v : mesh.vertices) {
    v = v.cwiseProduct(rescale);
  }
  BodyGeometry g = meshGeometry(body, mesh, out.notes);
  out.notes.push_back(body.jsonPath +
                      ": SDF represented by the mesh it is built from (the seed samples it on a " +
                      "grid; the oracle uses the mesh itself)");
  return g;
}

BodyGeometry buildBody(int index, const RigidBodyDesc& body, SceneGeometry& out) {
  const pbd::CollisionObjectDesc& c = body.collision;
  if (c.type == CollisionObjectType::None) {
    BodyGeometry none;
    none.description = "no collision object";
    return none;
  }
  if (c.invertSDF) {
    return unsupportedBody(index, body,
                           "invertSDF: the solid is the outside of the shape, which FCL cannot "
                           "represent",
                           out.unsupported);
  }
  switch (c.type) {
    case CollisionObjectType::Sphere:
      notePrimitiveFrame(body, "sphere", out.notes);
      return sphereGeometry(c.scale.x());
    case CollisionObjectType::Box:
      notePrimitiveFrame(body, "box", out.notes);
      return boxGeometry(c.scale);
    case CollisionObjectType::Cylinder:
      notePrimitiveFrame(body, "cylinder", out.notes);
      return cylinderGeometry(c.scale.x(), c.scale.y());
    case CollisionObjectType::Torus:
      return torusBody(index, body, out);
    case CollisionObjectType::SignedDistanceField:
      return sdfBody(index, body, out);
    case CollisionObjectType::HollowSphere:
      return unsupportedBody(index, body,
                             "hollow sphere (a shell of thickness 2·thicknessSDF): FCL has no "
                             "hollow shapes",
                             out.unsupported);
    case CollisionObjectType::HollowBox:
      return unsupportedBody(index, body,
                             "hollow box (a shell of thickness 2·thicknessSDF): FCL has no "
                             "hollow shapes",
                             out.unsupported);
    case CollisionObjectType::None:
      break;
  }
  return unsupportedBody(index, body,
                         "collision object type " + std::to_string(static_cast<int>(c.type)),
                         out.unsupported);
}

}  // namespace

SceneGeometry buildSceneGeometry(const pbd::Scene& scene) {
  SceneGeometry out;
  out.bodies.reserve(scene.rigidBodies.size());
  for (std::size_t i = 0; i < scene.rigidBodies.size(); ++i) {
    out.bodies.push_back(buildBody(static_cast<int>(i), scene.rigidBodies[i], out));
  }
  return out;
}

}  // namespace pbdval::fcl_oracle
