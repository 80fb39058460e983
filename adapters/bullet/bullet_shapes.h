// Collision shapes for the Scene's rigid bodies.
//
// A Bullet rigid body's frame is its principal frame at the centre of mass; the Scene gives
// geometry in the body's scene frame. Shapes are therefore placed at the scene→principal
// transform: meshes are transformed vertex by vertex; primitives (centred at the scene origin,
// in the scene axes) go into a btCompoundShape when that transform is not the identity.
//
// collisionObjectType   Bullet shape
//   0 none              no shape (btEmptyShape, filtered out of the broad phase)
//   1 sphere            btSphereShape(r)
//   2 box               btBoxShape(extents / 2)
//   3 cylinder          btCylinderShape (axis y, as the Scene's)
//   4 torus, 5 SDF      the body's mesh: btConvexHullShape when the mesh is convex, else a
//                       triangle mesh (btBvhTriangleMeshShape if static, btGImpactMeshShape if
//                       dynamic)
//   6 hollow sphere     unsupported
//   7 hollow box        a compound of six wall boxes, thickness 2 × thicknessSDF
// Margins: boxes, cylinders and hulls get the method's `margin`, kept inside the geometry
// (boxes and cylinders keep their outer size; hulls are shrunk by the margin first), so only
// edges and corners round off by the margin; a sphere's margin is its radius; triangle
// meshes are thickened by the margin on both sides.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "adapters/bullet/bullet_convert.h"
#include "pbd/model/scene.h"

namespace pbdval::bullet {

/// True when every vertex lies on the inner side of every triangle's plane (within
/// `relativeTolerance` × the mesh's bounding-box diagonal).
bool isConvex(const pbd::TriangleMesh& mesh, double relativeTolerance = 1e-7);

/// Creates and owns the shapes of one Bullet world.
class ShapeStore {
 public:
  explicit ShapeStore(double margin) : margin_(margin) {}

  /// The body's collision shape in its principal frame; nullptr for collisionObjectType 0.
  /// Throws EngineError when Bullet cannot build it (degenerate mesh).
  btCollisionShape* shapeFor(const pbd::RigidBodyDesc& body);
  /// A shape without geometry, for bodies that do not collide.
  btCollisionShape* emptyShape();

  double margin() const { return margin_; }
  /// How many bodies got each kind of shape ("box": 2, "convex hull": 1).
  const std::map<std::string, int>& kindCounts() const { return kindCounts_; }

 private:
  struct Part {
    btCollisionShape* shape;
    btTransform inPrincipalFrame;
  };

  template <typename Shape, typename... Args>
  Shape* make(Args&&... args);
  std::vector<Part> primitiveParts(const pbd::RigidBodyDesc& body, const btTransform& principal);
  btCollisionShape* meshShape(const pbd::RigidBodyDesc& body, const btTransform& principal);
  btCollisionShape* convexHull(const std::vector<pbd::Vector3>& vertices, const std::string& where);
  btCollisionShape* triangleMesh(const std::vector<pbd::Vector3>& vertices,
                                 const pbd::TriangleMesh& mesh, bool dynamic);
  btCollisionShape* assemble(const std::vector<Part>& parts);
  btCollisionShape* withMargin(btConvexInternalShape* shape);

  double margin_;
  std::vector<std::unique_ptr<btTriangleMesh>> meshes_;  ///< outlive the shapes referencing them
  std::vector<std::unique_ptr<btCollisionShape>> shapes_;
  btCollisionShape* empty_ = nullptr;
  std::map<std::string, int> kindCounts_;
};

}  // namespace pbdval::bullet
