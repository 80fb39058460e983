// Signed distance functions of the seed's analytic collision shapes, with analytic gradients.
//
// Every function takes a point x in the shape's frame (the body's scene frame) and returns
// φ(x) (negative inside) and ∇φ(x) (unit length wherever φ is differentiable). With
// p = |x| componentwise, ρ = |x_xz| and ρ̂ = (x, 0, z)/ρ:
//
//   sphere (radius r)                φ = |x| − r                         ∇φ = x/|x|
//   box (half extents b)             q = p − b
//                                    φ = |max(q, 0)| + min(max_k q_k, 0)
//                                    ∇φ = sgn(x) ∘ max(q, 0)/|max(q, 0)|  (outside)
//                                         sgn(x_k) e_k, k = argmax q     (inside)
//   cylinder (radius r, half height  q = (ρ − r, |y| − h), then the 2D box formula on q,
//     h, axis y)                     with ∂ρ/∂x = ρ̂ and ∂|y|/∂x = sgn(y) e_y
//   torus (radii R, r, in xz)        q = (ρ − R, y),  φ = |q| − r,        ∇φ = (q₀ ρ̂ + q₁ e_y)/|q|
//   hollow sphere (r, thickness t)   φ = ||x| − r| − t,                   ∇φ = sgn(|x| − r) x/|x|
//   hollow box (b, thickness t)      φ = |φ_box| − t,                     ∇φ = sgn(φ_box) ∇φ_box
//
// These are exact Euclidean distances (1-Lipschitz), as in the seed
// (DistanceFieldCollisionDetection.cpp; docs/seed.md#analytic-shapes), which differentiates all but
// the spheres numerically; here every gradient is analytic. On the sets where φ is not
// differentiable (the centre of a sphere, the medial surfaces of a box, the axis of a cylinder
// or torus) the functions return one of the one-sided gradients, chosen deterministically:
// sgn(0) = +1, ties in argmax go to the lowest axis, and ρ̂ = e_x on the axis.
#pragma once

#include "pbd/math/types.h"

namespace pbd {

/// A signed distance and its gradient at one point.
struct DistanceSample {
  Real distance = 0;
  Vector3 gradient = Vector3::Zero();
};

namespace sdf {

DistanceSample sphere(const Vector3& x, Real radius);
DistanceSample box(const Vector3& x, const Vector3& halfExtents);
/// Axis y, from −halfHeight to +halfHeight.
DistanceSample cylinder(const Vector3& x, Real radius, Real halfHeight);
/// In the xz-plane: the centre circle has radius `majorRadius`, the tube `minorRadius`.
DistanceSample torus(const Vector3& x, Real majorRadius, Real minorRadius);
DistanceSample hollowSphere(const Vector3& x, Real radius, Real thickness);
DistanceSample hollowBox(const Vector3& x, const Vector3& halfExtents, Real thickness);

}  // namespace sdf
}  // namespace pbd
