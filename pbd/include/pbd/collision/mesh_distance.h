// Exact signed distance from a point to a closed triangle mesh.
//
// Distance: the distance to the closest point on any triangle, found with an AABB tree over
// the triangles (closest-point-on-triangle by Voronoi regions; Ericson, "Real-Time Collision
// Detection", 2005, §5.1.5).
// Sign: the sign of (p − q)·N, where q is the closest point and N the angle-weighted
// pseudonormal of the feature q lies on: the face normal inside a face, the sum of the two
// face normals on an edge, the sum of the incident face normals weighted by their angles at a
// vertex (Bærentzen & Aanæs, "Signed distance computation using the angle weighted
// pseudonormal", IEEE TVCG 11(3), 2005). This is exact for closed, consistently oriented
// (outward) manifold meshes. Vertices at identical positions are welded first, so meshes
// split along seams count as closed.
#pragma once

#include <array>
#include <vector>

#include "pbd/model/mesh.h"

namespace pbd {

class MeshDistance {
 public:
  explicit MeshDistance(const TriangleMesh& mesh);

  /// Signed distance of `point` (negative inside) in the mesh's frame.
  Real signedDistance(const Vector3& point) const;
  /// Unsigned distance and the closest point on the surface.
  Real closestPoint(const Vector3& point, Vector3& closest) const;
  /// The closest point on the surface and the index of its triangle (in the order of the
  /// mesh's `triangles`).
  int closestTriangle(const Vector3& point, Vector3& closest) const;

 private:
  enum class Feature : int { Face, EdgeAB, EdgeBC, EdgeCA, VertexA, VertexB, VertexC };
  struct Node {
    Eigen::AlignedBox<Real, 3> box;
    int firstTriangle = 0, triangleCount = 0;
    int child = -1;  ///< left child; the right child is child + 1; -1 for a leaf
  };
  struct Query {
    Real squaredDistance;
    int triangle = -1;
    Feature feature = Feature::Face;
    Vector3 point = Vector3::Zero();
  };

  void computePseudonormals();
  void buildTree();
  Query closest(const Vector3& point) const;
  void testTriangle(int triangle, const Vector3& point, Query& best) const;
  Vector3 pseudonormal(int triangle, Feature feature) const;

  std::vector<Vector3> vertices_;
  std::vector<std::array<int, 3>> triangles_;
  std::vector<Vector3> faceNormals_;                 ///< unit (zero for degenerate faces)
  std::vector<std::array<Vector3, 3>> edgeNormals_;  ///< per triangle: AB, BC, CA
  std::vector<Vector3> vertexNormals_;               ///< angle-weighted
  std::vector<int> triangleOrder_;                   ///< tree leaves index into this
  std::vector<Node> nodes_;
};

}  // namespace pbd
