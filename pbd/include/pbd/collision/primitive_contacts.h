// Closed-form contacts of primitive pairs (Simulation.contactGeometry "primitives", an option
// of both methods; docs/contacts.md#primitive-contacts).
//
// The seed finds contacts by testing the surface samples of one body against the signed
// distance function of the other, both ways (collision_detection.h): a sphere of the default
// resolution carries 642 samples, and a resting sphere reports a cap of them. For the pairs
// below the contact has a closed form instead: a few points that are exactly the closest (or
// deepest) points of the two solids, found in O(1):
//
//   pair                              file                          points
//   sphere–sphere                     sphere_contacts.cpp           1
//   sphere–box, –cylinder,            sphere_contacts.cpp           1 (φ_B at the centre)
//     –hollow sphere, –hollow box
//     from outside
//   sphere inside a hollow box        sphere_contacts.cpp           1 per inner wall in reach
//   box–box                           box_contacts.cpp              ≤ 4 (clipped face) or 1 (edges)
//   box inside a hollow box           box_contacts.cpp              corners in reach, per wall
//
// Every other pair (cylinder–box, cylinder–cylinder, tori, grid SDFs, invertSDF, a box that
// overlaps a hollow box's wall from outside) has no closed form here: primitiveContacts
// returns false and the detector keeps the samples for it.
//
// Conventions. A and B are placed primitives (their scene frame's pose and the shape's size as
// the SDF formulas use it: analytic_shapes.h). Each contact holds a point on (or in) A, a
// point on (or in) B, the unit normal n pointing from B to A, and the separation
// s = n·(p_A − p_B): the gap when s > 0, minus the depth when s < 0 (the shortest
// translation of A along n that separates the two features). Only contacts with
// s ≤ maxSeparation are reported (speculative contacts: XPBD's detection tolerance).
// `normalFixedInA` says which body's face carries the normal (a clipped box–box manifold on a
// face of A, or a sphere against a box given as (box, sphere)): the detector reports that
// body as the SDF side, so that the contact's normal turns with the body that defines it.
#pragma once

#include <array>

#include "pbd/collision/collision_shape.h"

namespace pbd {

/// A primitive shape and the world pose of the frame its formula is written in.
struct PlacedPrimitive {
  CollisionObjectType type = CollisionObjectType::None;
  Vector3 size = Vector3::Zero();          ///< CollisionShape::size(): radius, half extents, ...
  Real thickness = 0;                      ///< hollow shapes: the wall's half thickness
  bool inverted = false;                   ///< invertSDF: never a closed form
  Matrix3 rotation = Matrix3::Identity();  ///< shape frame → world
  Vector3 center = Vector3::Zero();        ///< world origin of the shape frame

  /// The signed distance sample of the shape at a world point, in world coordinates.
  DistanceSample evaluateWorld(const Vector3& point) const;
};

/// `shape` placed at (rotation, center).
PlacedPrimitive placePrimitive(const CollisionShape& shape, const Matrix3& rotation,
                               const Vector3& center);

struct PrimitiveContact {
  Vector3 pointOnA = Vector3::Zero();
  Vector3 pointOnB = Vector3::Zero();
  Vector3 normal = Vector3::UnitY();  ///< unit, from B towards A
  Real separation = 0;                ///< n·(pointOnA − pointOnB)
};

/// The contacts of one pair, in a fixed order; allocates nothing.
struct PrimitiveManifold {
  static constexpr int kCapacity = 16;
  std::array<PrimitiveContact, kCapacity> contacts;
  int count = 0;
  int dropped = 0;              ///< contacts beyond the capacity
  bool normalFixedInA = false;  ///< the normal is a face normal of A (else of B)

  void clear() {
    count = 0;
    dropped = 0;
    normalFixedInA = false;
  }
  void add(const PrimitiveContact& contact) {
    if (count == kCapacity) {
      ++dropped;
      return;
    }
    contacts[static_cast<std::size_t>(count++)] = contact;
  }
  /// Exchanges the roles of A and B (points swapped, normal negated).
  void swapBodies();
};

/// Whether some configuration of a pair of these types has a closed form (the detector asks
/// primitiveContacts only then).
bool hasPrimitiveContacts(CollisionObjectType a, CollisionObjectType b);

/// The contacts of A and B with separation ≤ maxSeparation, in `out` (cleared first). Returns
/// false, leaving `out` empty, when this pair in this configuration has no closed form here.
bool primitiveContacts(const PlacedPrimitive& a, const PlacedPrimitive& b, Real maxSeparation,
                       PrimitiveManifold& out);

// The pair families (each file states its math at the top).

/// sphere_contacts.cpp: two spheres.
void sphereSphereContacts(const PlacedPrimitive& a, const PlacedPrimitive& b, Real maxSeparation,
                          PrimitiveManifold& out);
/// sphere_contacts.cpp: sphere A against a shape B with an exact, convex-solid SDF (box,
/// cylinder, sphere, hollow sphere; a hollow box seen from outside or from inside its wall).
void sphereShapeContacts(const PlacedPrimitive& sphere, const PlacedPrimitive& shape,
                         Real maxSeparation, PrimitiveManifold& out);
/// sphere_contacts.cpp: sphere A whose centre is inside hollow box B's cavity: one contact per
/// inner wall. Returns false when the centre is not in the cavity.
bool sphereInHollowBoxContacts(const PlacedPrimitive& sphere, const PlacedPrimitive& hollowBox,
                               Real maxSeparation, PrimitiveManifold& out);
/// box_contacts.cpp: two boxes (separating axes, then a clipped face or an edge pair).
void boxBoxContacts(const PlacedPrimitive& a, const PlacedPrimitive& b, Real maxSeparation,
                    PrimitiveManifold& out);
/// box_contacts.cpp: box A whose centre is inside hollow box B's cavity: its corners against
/// every inner wall. Returns false when the centre is not in the cavity.
bool boxInHollowBoxContacts(const PlacedPrimitive& box, const PlacedPrimitive& hollowBox,
                            Real maxSeparation, PrimitiveManifold& out);

}  // namespace pbd
