// The dispatch of closed-form contacts by pair type (primitive_contacts.h); the formulas are
// in sphere_contacts.cpp and box_contacts.cpp.
#include "pbd/collision/primitive_contacts.h"

#include <limits>
#include <utility>

namespace pbd {
namespace {

bool isSphere(const PlacedPrimitive& p) {
  return p.type == CollisionObjectType::Sphere;
}

/// Shapes whose SDF is exact and whose solid a sphere meets in one closest point.
bool sphereMeetsInOnePoint(CollisionObjectType type) {
  return type == CollisionObjectType::Sphere || type == CollisionObjectType::Box ||
         type == CollisionObjectType::Cylinder || type == CollisionObjectType::HollowSphere;
}

/// The contacts with A and B in this order; false when this order has no closed form.
bool orderedContacts(const PlacedPrimitive& a, const PlacedPrimitive& b, Real maxSeparation,
                     PrimitiveManifold& out) {
  using T = CollisionObjectType;
  if (isSphere(a)) {
    if (b.type == T::Sphere) {
      sphereSphereContacts(a, b, maxSeparation, out);
      return true;
    }
    if (sphereMeetsInOnePoint(b.type)) {
      sphereShapeContacts(a, b, maxSeparation, out);
      return true;
    }
    if (b.type == T::HollowBox) {
      if (sphereInHollowBoxContacts(a, b, maxSeparation, out)) return true;
      sphereShapeContacts(a, b, maxSeparation, out);  // outside or in the wall: one point
      return true;
    }
    return false;
  }
  if (a.type == T::Box && b.type == T::Box) {
    boxBoxContacts(a, b, maxSeparation, out);
    return true;
  }
  if (a.type == T::Box && b.type == T::HollowBox)
    return boxInHollowBoxContacts(a, b, maxSeparation, out);
  return false;
}

}  // namespace

DistanceSample PlacedPrimitive::evaluateWorld(const Vector3& point) const {
  const Vector3 local = rotation.transpose() * (point - center);
  DistanceSample sample;
  switch (type) {
    case CollisionObjectType::Sphere:
      sample = sdf::sphere(local, size.x());
      break;
    case CollisionObjectType::Box:
      sample = sdf::box(local, size);
      break;
    case CollisionObjectType::Cylinder:
      sample = sdf::cylinder(local, size.x(), size.y());
      break;
    case CollisionObjectType::HollowSphere:
      sample = sdf::hollowSphere(local, size.x(), thickness);
      break;
    case CollisionObjectType::HollowBox:
      sample = sdf::hollowBox(local, size, thickness);
      break;
    case CollisionObjectType::Torus:
      sample = sdf::torus(local, size.x(), size.y());
      break;
    default:
      sample.distance = std::numeric_limits<Real>::infinity();
  }
  sample.gradient = rotation * sample.gradient;
  return sample;
}

PlacedPrimitive placePrimitive(const CollisionShape& shape, const Matrix3& rotation,
                               const Vector3& center) {
  PlacedPrimitive placed;
  placed.type = shape.type();
  placed.size = shape.size();
  placed.thickness = shape.thickness();
  placed.inverted = shape.inverted();
  placed.rotation = rotation;
  placed.center = center;
  return placed;
}

void PrimitiveManifold::swapBodies() {
  for (int i = 0; i < count; ++i) {
    PrimitiveContact& c = contacts[std::size_t(i)];
    std::swap(c.pointOnA, c.pointOnB);
    c.normal = -c.normal;
  }
  normalFixedInA = !normalFixedInA;
}

bool hasPrimitiveContacts(CollisionObjectType a, CollisionObjectType b) {
  using T = CollisionObjectType;
  const auto ordered = [](T x, T y) {
    return (x == T::Sphere && (sphereMeetsInOnePoint(y) || y == T::HollowBox)) ||
           (x == T::Box && (y == T::Box || y == T::HollowBox));
  };
  return ordered(a, b) || ordered(b, a);
}

bool primitiveContacts(const PlacedPrimitive& a, const PlacedPrimitive& b, Real maxSeparation,
                       PrimitiveManifold& out) {
  out.clear();
  if (a.inverted || b.inverted) return false;
  if (orderedContacts(a, b, maxSeparation, out)) return true;
  out.clear();
  if (!orderedContacts(b, a, maxSeparation, out)) {
    out.clear();
    return false;
  }
  out.swapBodies();
  return true;
}

}  // namespace pbd
