#include "pbd/collision/collision_shape.h"

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace pbd {
namespace {

[[noreturn]] void fail(const RigidBodyDesc& body, const std::string& message) {
  throw std::invalid_argument((body.jsonPath.empty() ? std::string("rigid body") : body.jsonPath) +
                              ": " + message);
}

/// How many leading components of collisionObjectScale a type reads.
int usedScaleComponents(CollisionObjectType type) {
  switch (type) {
    case CollisionObjectType::Sphere:
    case CollisionObjectType::HollowSphere:
      return 1;
    case CollisionObjectType::Cylinder:
    case CollisionObjectType::Torus:
      return 2;
    case CollisionObjectType::None:
      return 0;
    default:
      return 3;
  }
}

/// The grid of a type-5 body, and the bounds of its collision mesh in the scene frame.
CachedGrid buildGrid(const RigidBodyDesc& body, const CollisionShapeOptions& options,
                     Eigen::AlignedBox<Real, 3>& bounds) {
  const TriangleMesh mesh = collisionMesh(body);
  bounds.setEmpty();
  for (const Vector3& v : mesh.vertices)
    bounds.extend(v);
  if (options.gridInterpolation == GridInterpolation::CubicLagrange &&
      body.collision.discregridGrid) {
    // The seed's grid read from its Discregrid file (collisionObjectFileName .csdf).
    return {body.collision.discregridGrid, GridCacheOutcome::Disabled, ""};
  }
  if (options.gridInterpolation == GridInterpolation::CubicLagrange) {
    // The seed's grid: the unscaled mesh's box padded by 0.1 (SceneLoaderDemo's generateSDF).
    const TriangleMesh unscaled = collisionMesh(body, /*scaled=*/false);
    Eigen::AlignedBox<Real, 3> box;
    for (const Vector3& v : unscaled.vertices)
      box.extend(v);
    const Vector3 margin = Vector3::Constant(Real(0.1));
    return loadOrBuildMeshGrid(unscaled, box.min() - margin, box.max() + margin,
                               body.collision.resolutionSDF, options.gridInterpolation,
                               options.gridCacheFolder);
  }
  const Vector3 margin = Vector3::Constant(
      std::max(Real(0.1) * bounds.sizes().maxCoeff(), options.minimumGridPadding));
  return loadOrBuildMeshGrid(mesh, bounds.min() - margin, bounds.max() + margin,
                             body.collision.resolutionSDF, options.gridInterpolation,
                             options.gridCacheFolder);
}

}  // namespace

TriangleMesh collisionMesh(const RigidBodyDesc& body, bool scaled) {
  const CollisionObjectDesc& c = body.collision;
  const Vector3 scale = scaled ? c.scale : Vector3::Ones();
  TriangleMesh mesh;
  if (c.mesh) {
    mesh = *c.mesh;
    for (Vector3& v : mesh.vertices)
      v = v.cwiseProduct(scale);
  } else if (body.mesh) {
    mesh = *body.mesh;
    for (Vector3& v : mesh.vertices)
      v = v.cwiseQuotient(body.scale).cwiseProduct(scale);
  } else {
    fail(body,
         "collisionObjectType 5 (signed distance field) needs a mesh: a geometryFile or a "
         "collisionObjectFileName");
  }
  if (mesh.triangles.empty()) fail(body, "the collision mesh has no triangles");
  return mesh;
}

CollisionShape makeCollisionShape(const RigidBodyDesc& body, const CollisionShapeOptions& options) {
  const CollisionObjectDesc& c = body.collision;
  CollisionShape shape;
  shape.type_ = c.type;
  if (c.type == CollisionObjectType::None) return shape;
  const int used = usedScaleComponents(c.type);
  if (!(c.scale.head(used).array() > 0).all())
    fail(body, "collisionObjectScale: the components collisionObjectType " +
                   std::to_string(static_cast<int>(c.type)) + " uses must be > 0");
  if (!(c.thicknessSDF >= 0)) fail(body, "thicknessSDF must be >= 0");
  shape.sign_ = c.invertSDF ? Real(-1) : Real(1);
  shape.size_ = c.scale;
  shape.thickness_ = c.thicknessSDF;
  switch (c.type) {
    case CollisionObjectType::Box:
    case CollisionObjectType::HollowBox:
      shape.size_ = c.scale / 2;  // the formulas use half extents
      break;
    case CollisionObjectType::Cylinder:
      shape.size_.y() = c.scale.y() / 2;  // half height
      break;
    case CollisionObjectType::SignedDistanceField: {
      if ((c.resolutionSDF.array() < 1).any()) fail(body, "resolutionSDF must be >= 1 per axis");
      const CachedGrid grid = buildGrid(body, options, shape.meshBounds_);
      shape.grid_ = grid.grid;
      shape.gridOutcome_ = grid.outcome;
      if (options.gridInterpolation == GridInterpolation::CubicLagrange) shape.gridScale_ = c.scale;
      break;
    }
    default:
      break;
  }
  return shape;
}

DistanceSample CollisionShape::evaluateUninverted(const Vector3& p) const {
  switch (type_) {
    case CollisionObjectType::None:
      return {std::numeric_limits<Real>::infinity(), Vector3::Zero()};
    case CollisionObjectType::Sphere:
      return sdf::sphere(p, size_.x());
    case CollisionObjectType::Box:
      return sdf::box(p, size_);
    case CollisionObjectType::Cylinder:
      return sdf::cylinder(p, size_.x(), size_.y());
    case CollisionObjectType::Torus:
      return sdf::torus(p, size_.x(), size_.y());
    case CollisionObjectType::SignedDistanceField: {
      // As the seed's CubicSDFCollisionObject::distance: x ⊙ scale⁻¹, times scale[0].
      DistanceSample sample = grid_->evaluate(p.cwiseProduct(gridScale_.cwiseInverse()));
      sample.distance *= gridScale_.x();
      return sample;
    }
    case CollisionObjectType::HollowSphere:
      return sdf::hollowSphere(p, size_.x(), thickness_);
    case CollisionObjectType::HollowBox:
      return sdf::hollowBox(p, size_, thickness_);
  }
  return {std::numeric_limits<Real>::infinity(), Vector3::Zero()};
}

DistanceSample CollisionShape::evaluateGrid(const Vector3& gridPoint) const {
  DistanceSample sample = grid_->evaluate(gridPoint);
  if (sign_ < 0) {
    sample.distance = -sample.distance;
    sample.gradient = -sample.gradient;
  }
  return sample;
}

DistanceSample CollisionShape::evaluate(const Vector3& p) const {
  DistanceSample sample = evaluateUninverted(p);
  if (sign_ < 0) {
    sample.distance = -sample.distance;
    sample.gradient = -sample.gradient;
  }
  return sample;
}

Eigen::AlignedBox<Real, 3> CollisionShape::bounds() const {
  using Box = Eigen::AlignedBox<Real, 3>;
  switch (type_) {
    case CollisionObjectType::None:
      return Box();  // empty
    case CollisionObjectType::Sphere:
      return Box(Vector3::Constant(-size_.x()), Vector3::Constant(size_.x()));
    case CollisionObjectType::HollowSphere: {
      const Real r = size_.x() + thickness_;
      return Box(Vector3::Constant(-r), Vector3::Constant(r));
    }
    case CollisionObjectType::Box:
      return Box(-size_, size_);
    case CollisionObjectType::HollowBox: {
      const Vector3 outer = size_ + Vector3::Constant(thickness_);
      return Box(-outer, outer);
    }
    case CollisionObjectType::Cylinder: {
      const Vector3 half(size_.x(), size_.y(), size_.x());
      return Box(-half, half);
    }
    case CollisionObjectType::Torus: {
      const Real outer = size_.x() + size_.y();
      const Vector3 half(outer, size_.y(), outer);
      return Box(-half, half);
    }
    case CollisionObjectType::SignedDistanceField:
      return meshBounds_;
  }
  return Box();
}

}  // namespace pbd
