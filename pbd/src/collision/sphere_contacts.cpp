// Sphere contacts in closed form (primitive_contacts.h).
//
// Sphere–sphere. Centres c_A, c_B, radii r_A, r_B, d = c_A − c_B, L = |d|:
//   n = d / L (e_x when L = 0, the SDF's convention), p_A = c_A − r_A n, p_B = c_B + r_B n,
//   s = L − r_A − r_B.
//
// Sphere against a shape with an exact signed distance φ_B (analytic_shapes.h). For any closed
// set S the distance from a ball of centre c and radius r to S is dist(c, S) − r, and for a
// convex solid the shortest separating translation of a ball whose centre is inside is
// −φ_B(c) + r along ∇φ_B(c). So with φ = φ_B(c) and n = ∇φ_B(c) (unit):
//   p_B = c − φ n (the closest point of B's surface), p_A = c − r n, s = φ − r.
// Exact for the box, cylinder and sphere, for a hollow sphere (outside: a convex solid;
// inside the cavity: the cavity is a ball, so its surface's closest point is the contact),
// and for a hollow box whose wall or outside holds the centre (its outside, φ = φ_box − t, is
// the convex box rounded by t).
//
// Sphere inside a hollow box's cavity. The cavity of a hollow box with half extents b and wall
// half thickness t is the box of half extents h = b − t (the inner offset of a box is a box).
// With the centre c in the cavity (|c_k| < h_k), the wall's closest point to c across the
// wall k± (sign σ = ±1) is c with its k-th coordinate set to σ h_k; it lies inside that face's
// rectangle, so every wall in reach is a separate, exact contact:
//   s = h_k − σ c_k − r, n = −σ e_k (out of the wall, into the cavity),
//   p_B = c + (σ h_k − c_k) e_k, p_A = c + σ r e_k.
// A sphere in a corner touches three walls at once; one SDF sample would report only the
// nearest, and the sphere would sink into the others.
#include <cmath>

#include "pbd/collision/primitive_contacts.h"

namespace pbd {

void sphereSphereContacts(const PlacedPrimitive& a, const PlacedPrimitive& b, Real maxSeparation,
                          PrimitiveManifold& out) {
  const Vector3 d = a.center - b.center;
  const Real length = d.norm();
  const Vector3 normal = length > 0 ? Vector3(d / length) : Vector3::UnitX();
  const Real radiusA = a.size.x(), radiusB = b.size.x();
  const Real separation = length - radiusA - radiusB;
  if (separation > maxSeparation) return;
  out.add({a.center - radiusA * normal, b.center + radiusB * normal, normal, separation});
}

void sphereShapeContacts(const PlacedPrimitive& sphere, const PlacedPrimitive& shape,
                         Real maxSeparation, PrimitiveManifold& out) {
  const DistanceSample sample = shape.evaluateWorld(sphere.center);
  const Real radius = sphere.size.x();
  const Real separation = sample.distance - radius;
  if (separation > maxSeparation) return;
  const Vector3& normal = sample.gradient;
  out.add({sphere.center - radius * normal, sphere.center - sample.distance * normal, normal,
           separation});
}

bool sphereInHollowBoxContacts(const PlacedPrimitive& sphere, const PlacedPrimitive& hollowBox,
                               Real maxSeparation, PrimitiveManifold& out) {
  const Vector3 cavity = hollowBox.size - Vector3::Constant(hollowBox.thickness);  // h
  const Vector3 c = hollowBox.rotation.transpose() * (sphere.center - hollowBox.center);
  if (!(cavity.array() > 0).all() || !(c.cwiseAbs().array() < cavity.array()).all()) return false;
  const Real radius = sphere.size.x();
  for (int k = 0; k < 3; ++k)
    for (const Real sign : {Real(1), Real(-1)}) {
      const Real separation = cavity[k] - sign * c[k] - radius;
      if (separation > maxSeparation) continue;
      const Vector3 axis = hollowBox.rotation.col(k);
      const Vector3 onWall = c + (sign * cavity[k] - c[k]) * Vector3::Unit(k);
      out.add({sphere.center + sign * radius * axis, hollowBox.rotation * onWall + hollowBox.center,
               -sign * axis, separation});
    }
  return true;
}

}  // namespace pbd
