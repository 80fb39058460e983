// Internal to the distance oracle (includes FCL; never include it from a public header): the
// FCL geometry of each rigid body, built from the Scene.
#pragma once

#include <fcl/geometry/collision_geometry.h>

#include <memory>
#include <string>
#include <vector>

#include "pbd/model/mesh.h"
#include "validation/measure/oracle/distance_oracle.h"

namespace pbdval::fcl_oracle {

/// A non-convex mesh with what the vertex-depth query needs, in the geometry frame.
struct MeshData {
  pbd::TriangleMesh mesh;
  std::vector<std::vector<int>> neighbours;  ///< vertex adjacency
};

struct BodyGeometry {
  OracleShape shape = OracleShape::None;
  std::shared_ptr<fcl::CollisionGeometryd> geometry;  ///< null for None and Unsupported
  /// The geometry frame in the body's scene frame (FCL's cylinder axis z onto the seed's y).
  fcl::Transform3d geometryInSceneFrame = fcl::Transform3d::Identity();
  std::shared_ptr<const MeshData> mesh;  ///< TriangleMesh only
  double sphereRadius = 0;               ///< Sphere only
  std::string description;
};

struct SceneGeometry {
  std::vector<BodyGeometry> bodies;  ///< Scene::rigidBodies order
  std::vector<UnsupportedBody> unsupported;
  std::vector<std::string> notes;
};

/// Builds one geometry per rigid body (docs/fcl-oracle.md, "Geometry"). Throws
/// std::invalid_argument for a malformed mesh (indices out of range, no triangles).
SceneGeometry buildSceneGeometry(const pbd::Scene& scene);

}  // namespace pbdval::fcl_oracle
