// The collision shape of a rigid body: its signed distance function in the body's scene frame
// (the frame of its geometry file), as the seed defines it per `collisionObjectType`.
//
// Usage, outside any simulation:
//
//   const pbd::CollisionShape shape = pbd::makeCollisionShape(scene.rigidBodies[i]);
//   const pbd::Vector3 p = ...;                 // a point in the body's scene frame
//   pbd::Real d = shape.distance(p);            // < 0 inside, > 0 outside (m)
//   pbd::Vector3 n = shape.gradient(p);         // unit outward normal where defined
//
// For a world point x and a body whose scene frame has pose (R, o) — World::sceneFrameState,
// or translation/rotation of the RigidBodyDesc at t = 0 — the scene-frame point is
// Rᵀ(x − o).
//
// The distance includes `invertSDF` (the sign flips: the inside becomes the outside) and
// `thicknessSDF` (hollow shapes only), and excludes `contactTolerance`: the seed's
// collision test subtracts the tolerance from this value.
//
//   type 1 sphere       radius r = collisionObjectScale[0]
//   type 2 box          full extents collisionObjectScale
//   type 3 cylinder     radius [0], height [1], axis y
//   type 4 torus        radii R = [0], r = [1], in the xz-plane
//   type 5 SDF          a grid (distance_grid.h) sampled from the collision mesh: the
//                       geometry file (or collisionObjectFileName's OBJ) with its vertices
//                       scaled by collisionObjectScale; see makeCollisionShape
//   type 6 hollow sphere  radius [0], wall half-thickness thicknessSDF
//   type 7 hollow box   full extents, wall half-thickness thicknessSDF
// Formulas and gradients: analytic_shapes.h. Type 0 (none) has no shape: distance() is +∞.
#pragma once

#include <memory>
#include <string>

#include "pbd/collision/analytic_shapes.h"
#include "pbd/collision/distance_grid.h"
#include "pbd/collision/grid_cache.h"
#include "pbd/model/scene.h"

namespace pbd {

struct CollisionShapeOptions {
  /// Cache folder for type-5 grids, chosen by the caller; empty (the default): no cache.
  std::string gridCacheFolder;
  /// Padding of a type-5 grid around the collision mesh, on every side: the larger of 10 % of
  /// the mesh's largest extent and this value (m). The world passes 2 × contactTolerance, so
  /// every point inside the contact shell lies inside the grid.
  Real minimumGridPadding = 0;
  /// How type-5 grids are interpolated and how far they are padded: the seed's cubic Lagrange
  /// grid pads the collision mesh's box by 0.1 × collisionObjectScale on every side (the
  /// seed's 0.1 in the mesh file's units) and ignores minimumGridPadding; Catmull-Rom uses
  /// the rule above. The collision detector takes it from the scene (distanceGridFor).
  GridInterpolation gridInterpolation = GridInterpolation::CubicLagrange;
};

class CollisionShape {
 public:
  CollisionShape() = default;

  CollisionObjectType type() const { return type_; }
  bool exists() const { return type_ != CollisionObjectType::None; }

  /// Signed distance (m) of a point given in the body's scene frame.
  Real distance(const Vector3& pointInSceneFrame) const {
    return evaluate(pointInSceneFrame).distance;
  }
  /// ∇ distance: the unit outward normal (inverted with invertSDF) where it is defined.
  Vector3 gradient(const Vector3& pointInSceneFrame) const {
    return evaluate(pointInSceneFrame).gradient;
  }
  DistanceSample evaluate(const Vector3& pointInSceneFrame) const;

  /// The shape's size parameters as the formulas use them: the radius in [0] (sphere, hollow
  /// sphere, cylinder), half extents (box, hollow box), half height in [1] (cylinder), the
  /// radii (R, r) (torus), the grid's scale (type 5).
  const Vector3& size() const { return size_; }
  /// Hollow shapes: the wall's half thickness (thicknessSDF).
  Real thickness() const { return thickness_; }
  /// invertSDF: the inside and the outside swapped.
  bool inverted() const { return sign_ < 0; }

  /// The grid of a type-5 shape (null otherwise), and how it was obtained.
  const DistanceGrid* grid() const { return grid_.get(); }
  /// The frame the grid is sampled in: a point p of the scene frame is looked up at
  /// p ⊙ gridScale⁻¹. The seed's cubic Lagrange grid is the unscaled mesh's (gridScale =
  /// collisionObjectScale, and distance() multiplies by its first component, as the seed's
  /// does: exact for uniform scales); a Catmull-Rom grid is the scaled mesh's (gridScale = 1).
  const Vector3& gridScale() const { return gridScale_; }
  /// Type 5 only: the signed distance sample in the grid's own frame (unscaled units),
  /// invertSDF applied; `gridPoint` = p ⊙ gridScale⁻¹.
  DistanceSample evaluateGrid(const Vector3& gridPoint) const;
  GridCacheOutcome gridOutcome() const { return gridOutcome_; }

  /// An axis-aligned box in the scene frame that contains the shape's surface (the solid's
  /// bounds; for hollow shapes the outer wall).
  Eigen::AlignedBox<Real, 3> bounds() const;

 private:
  friend CollisionShape makeCollisionShape(const RigidBodyDesc&, const CollisionShapeOptions&);

  DistanceSample evaluateUninverted(const Vector3& point) const;

  CollisionObjectType type_ = CollisionObjectType::None;
  Vector3 size_ = Vector3::Ones();  ///< collisionObjectScale, halved where the formula uses halves
  Real thickness_ = 0;
  Real sign_ = 1;  ///< −1 with invertSDF
  std::shared_ptr<const DistanceGrid> grid_;
  Vector3 gridScale_ = Vector3::Ones();
  Eigen::AlignedBox<Real, 3> meshBounds_;  ///< type 5: bounds of the collision mesh
  GridCacheOutcome gridOutcome_ = GridCacheOutcome::Disabled;
};

/// Builds the shape of `body` (its `collision` keys). Type 5 samples the exact signed distance
/// of the collision mesh on resolutionSDF cells over the mesh's bounds plus the padding, or
/// loads it from the cache. Throws std::invalid_argument, naming the body, when the
/// parameters cannot describe a shape (a non-positive size, type 5 without a mesh).
CollisionShape makeCollisionShape(const RigidBodyDesc& body,
                                  const CollisionShapeOptions& options = {});

/// The mesh a type-5 shape of `body` is built from, in the scene frame: the vertices of
/// collisionObjectFileName's mesh, or of the geometry file (undoing `scale`), multiplied
/// component-wise by collisionObjectScale (`scaled`) or not (the mesh file's own units, the
/// frame of the seed's grid). Throws std::invalid_argument without a mesh.
TriangleMesh collisionMesh(const RigidBodyDesc& body, bool scaled = true);

}  // namespace pbd
