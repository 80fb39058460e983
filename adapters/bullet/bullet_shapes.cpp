#include "adapters/bullet/bullet_shapes.h"

#include <BulletCollision/Gimpact/btGImpactShape.h>
#include <LinearMath/btConvexHullComputer.h>

#include "adapters/engine.h"

namespace pbdval::bullet {
namespace {

using pbd::CollisionObjectType;
using pbd::Vector3;

/// Scene frame → principal frame: p_principal = R_pᵀ (p_scene − c).
btTransform principalFromScene(const pbd::MassProperties& mass) {
  const pbd::Quaternion inverse = mass.principalRotation.conjugate();
  return toBullet(inverse, -(inverse * mass.centerOfMass));
}

std::vector<Vector3> verticesInPrincipalFrame(const pbd::TriangleMesh& mesh,
                                              const btTransform& principal) {
  std::vector<Vector3> vertices;
  vertices.reserve(mesh.vertices.size());
  for (const Vector3& v : mesh.vertices)
    vertices.push_back(toEigen(principal * toBullet(v)));
  return vertices;
}

bool isMeshType(CollisionObjectType type) {
  return type == CollisionObjectType::Torus || type == CollisionObjectType::SignedDistanceField;
}

// A hull shrunk by more than this fraction of its inner radius would lose its shape; the
// margin is then reduced to what the hull allows (btConvexHullComputer's shrinkClamp).
constexpr btScalar kHullShrinkClamp = 0.25;

}  // namespace

bool isConvex(const pbd::TriangleMesh& mesh, double relativeTolerance) {
  if (mesh.vertices.empty()) return false;
  Eigen::AlignedBox<pbd::Real, 3> box;
  for (const Vector3& v : mesh.vertices)
    box.extend(v);
  const double tolerance = relativeTolerance * double(box.diagonal().norm());
  for (const auto& t : mesh.triangles) {
    const Vector3& a = mesh.vertices[static_cast<std::size_t>(t[0])];
    const Vector3 normal = (mesh.vertices[static_cast<std::size_t>(t[1])] - a)
                               .cross(mesh.vertices[static_cast<std::size_t>(t[2])] - a);
    if (normal.norm() == 0) continue;
    const Vector3 unit = normal.normalized();
    for (const Vector3& v : mesh.vertices)
      if (double(unit.dot(v - a)) > tolerance) return false;
  }
  return true;
}

template <typename Shape, typename... Args>
Shape* ShapeStore::make(Args&&... args) {
  auto shape = std::make_unique<Shape>(std::forward<Args>(args)...);
  Shape* raw = shape.get();
  shapes_.push_back(std::move(shape));
  return raw;
}

btCollisionShape* ShapeStore::emptyShape() {
  if (!empty_) empty_ = make<btEmptyShape>();
  return empty_;
}

btCollisionShape* ShapeStore::withMargin(btConvexInternalShape* shape) {
  shape->setMargin(margin_);  // boxes and cylinders keep their outer size (btBoxShape::setMargin)
  return shape;
}

btCollisionShape* ShapeStore::shapeFor(const pbd::RigidBodyDesc& body) {
  const CollisionObjectType type = body.collision.type;
  if (type == CollisionObjectType::None) return nullptr;
  const btTransform principal = principalFromScene(body.massProperties);
  return isMeshType(type) ? meshShape(body, principal) : assemble(primitiveParts(body, principal));
}

std::vector<ShapeStore::Part> ShapeStore::primitiveParts(const pbd::RigidBodyDesc& body,
                                                         const btTransform& principal) {
  const Vector3& scale = body.collision.scale;
  switch (body.collision.type) {
    case CollisionObjectType::Sphere:
      ++kindCounts_["sphere"];
      return {{make<btSphereShape>(scale.x()), principal}};
    case CollisionObjectType::Box:
      ++kindCounts_["box"];
      return {{withMargin(make<btBoxShape>(toBullet(Vector3(scale / 2)))), principal}};
    case CollisionObjectType::Cylinder:
      ++kindCounts_["cylinder"];
      return {{withMargin(make<btCylinderShape>(btVector3(scale.x(), scale.y() / 2, scale.x()))),
               principal}};
    case CollisionObjectType::HollowBox: {
      // |box SDF| ≤ t: six walls of thickness 2t centred on the faces, each long enough to
      // close the edges (square instead of rounded outer edges).
      ++kindCounts_["hollow box (6 wall boxes)"];
      const Vector3 half = scale / 2;
      const pbd::Real t = body.collision.thicknessSDF;
      std::vector<Part> walls;
      for (int axis = 0; axis < 3; ++axis)
        for (int side : {-1, 1}) {
          Vector3 wallHalf = half + Vector3::Constant(t);
          wallHalf[axis] = t;
          Vector3 centre = Vector3::Zero();
          centre[axis] = side * half[axis];
          btTransform inScene(btQuaternion::getIdentity(), toBullet(centre));
          walls.push_back({withMargin(make<btBoxShape>(toBullet(wallHalf))), principal * inScene});
        }
      return walls;
    }
    default:
      throw EngineError(body.jsonPath + ": no Bullet primitive for collisionObjectType " +
                        std::to_string(static_cast<int>(body.collision.type)));
  }
}

btCollisionShape* ShapeStore::meshShape(const pbd::RigidBodyDesc& body,
                                        const btTransform& principal) {
  const std::vector<Vector3> vertices = verticesInPrincipalFrame(*body.mesh, principal);
  if (isConvex(*body.mesh)) {
    ++kindCounts_["convex hull"];
    return convexHull(vertices, body.jsonPath);
  }
  ++kindCounts_[body.isDynamic ? "triangle mesh (GImpact)" : "triangle mesh (BVH)"];
  return triangleMesh(vertices, *body.mesh, body.isDynamic);
}

btCollisionShape* ShapeStore::convexHull(const std::vector<Vector3>& vertices,
                                         const std::string& where) {
  // Shrink the hull by the margin so that hull ⊕ margin has the mesh's faces exactly.
  btConvexHullComputer hull;
  const btScalar shrink =
      hull.compute(vertices.front().data(), static_cast<int>(sizeof(Vector3)),
                   static_cast<int>(vertices.size()), margin_, kHullShrinkClamp);
  if (shrink < 0 || hull.vertices.size() < 4)
    throw EngineError(where + ": Bullet could not build a convex hull of the mesh (" +
                      std::to_string(vertices.size()) + " vertices, degenerate?)");
  auto* shape = make<btConvexHullShape>();
  for (int i = 0; i < hull.vertices.size(); ++i)
    shape->addPoint(hull.vertices[i], false);
  shape->recalcLocalAabb();
  shape->setMargin(shrink);
  return shape;
}

btCollisionShape* ShapeStore::triangleMesh(const std::vector<Vector3>& vertices,
                                           const pbd::TriangleMesh& mesh, bool dynamic) {
  auto triangles = std::make_unique<btTriangleMesh>();
  for (const auto& t : mesh.triangles)
    triangles->addTriangle(toBullet(vertices[static_cast<std::size_t>(t[0])]),
                           toBullet(vertices[static_cast<std::size_t>(t[1])]),
                           toBullet(vertices[static_cast<std::size_t>(t[2])]));
  btTriangleMesh* data = triangles.get();
  meshes_.push_back(std::move(triangles));
  if (!dynamic) {
    auto* shape = make<btBvhTriangleMeshShape>(data, true);
    shape->setMargin(margin_);
    return shape;
  }
  auto* shape = make<btGImpactMeshShape>(data);
  shape->setMargin(margin_);
  shape->updateBound();
  return shape;
}

btCollisionShape* ShapeStore::assemble(const std::vector<Part>& parts) {
  if (parts.size() == 1 && isExactIdentity(parts.front().inPrincipalFrame))
    return parts.front().shape;
  auto* compound = make<btCompoundShape>();
  for (const Part& part : parts)
    compound->addChildShape(part.inPrincipalFrame, part.shape);
  return compound;
}

}  // namespace pbdval::bullet
