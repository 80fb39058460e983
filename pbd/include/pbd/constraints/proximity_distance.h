// Proximity distance constraints: keep a point at distance d from an edge or a triangle, or two
// edges at distance d from each other (the seed's solve_EdgePointDistanceConstraint,
// solve_TrianglePointDistanceConstraint and solve_EdgeEdgeDistanceConstraint, which nothing in
// the seed's simulation uses; here too they are pure functions, not part of World).
//
// Every constraint is C = |p − q| − d, with p and q the closest points of the two features:
//   point–edge      p = x₀,                 q = (1 − t) x₁ + t x₂,         t ∈ [0, 1]
//   point–triangle  p = x₀,                 q = u x₁ + v x₂ + w x₃,        u + v + w = 1, all ≥ 0
//   edge–edge       p = (1 − s) x₀ + s x₁,  q = (1 − t) x₂ + t x₃,         s, t ∈ [0, 1]
// The difference vector is linear in the positions, p − q = Σᵢ bᵢ xᵢ, with signed barycentric
// coefficients b (point–edge: (1, −(1 − t), −t); point–triangle: (1, −u, −v, −w); edge–edge:
// (1 − s, s, −(1 − t), −t)); Σᵢ bᵢ = 0. The barycentrics come from the closest-point computation
// and are held constant in the gradient (the standard treatment, and the seed's): with
// n = (p − q)/|p − q|,  ∇ᵢC = bᵢ n.
// PBD projection with stiffness k ∈ [0, 1] (the compression stiffness when C < 0, the stretch
// stiffness when C > 0):
//   Δxᵢ = −k C wᵢ bᵢ n / Σⱼ wⱼ bⱼ²        (w the inverse masses).
// Since Σᵢ bᵢ Δxᵢ = −k C n, one projection with k = 1 makes |p − q| = d exactly for the fixed
// barycentrics (C is linear along n); Σᵢ Δxᵢ/wᵢ = −k C n Σᵢ bᵢ / Σⱼ wⱼ bⱼ² = 0 (linear momentum
// is conserved when every particle is dynamic); a static particle (w = 0) does not move.
// No correction when p = q (no direction) or when Σⱼ wⱼ bⱼ² = 0 (every particle that the
// constraint could move is static).
// Degenerate features: a zero-length edge is treated as the point at its midpoint (t = 1/2);
// a triangle with |(x₂ − x₁) × (x₃ − x₁)|² ≤ ε |x₂ − x₁|² |x₃ − x₁|² (sin² of its angle at x₁
// at most ε: collinear to round-off) is treated as its three edges (the closest of them,
// ties to the first of x₁x₂, x₂x₃, x₃x₁), because the face formula would divide by its area;
// two edges whose directions
// have sin² of their angle ≤ ε are treated as parallel: s = 0, t the closest to x₀, then s
// the closest to the clamped t (one pair of closest points; they are not unique there).
// Nothing allocates.
#pragma once

#include <array>

#include "pbd/math/types.h"

namespace pbd {

/// The closest point of the segment [a, b] to p is (1 − t) a + t b; returns t ∈ [0, 1]
/// (1/2 for a zero-length segment).
Real closestPointOnSegment(const Vector3& p, const Vector3& a, const Vector3& b);

/// The closest point of the triangle (a, b, c) to p is u a + v b + w c; returns (u, v, w),
/// all ≥ 0 and summing to 1.
Vector3 closestPointOnTriangle(const Vector3& p, const Vector3& a, const Vector3& b,
                               const Vector3& c);

/// Closest points of the segments [a₀, a₁] and [b₀, b₁]: (1 − s) a₀ + s a₁ and (1 − t) b₀ + t b₁.
struct SegmentPairParameters {
  Real s = 0;
  Real t = 0;
};
SegmentPairParameters closestPointsOfSegments(const Vector3& a0, const Vector3& a1,
                                              const Vector3& b0, const Vector3& b1);

/// The corrections of the N particles of a proximity constraint, in the order of the
/// function's arguments, and the constraint's value C = |p − q| − d before the correction.
template <int N>
struct ProximityCorrection {
  std::array<Vector3, N> delta{};  ///< Δxᵢ (zero when there is no correction)
  Real value = 0;                  ///< C before the correction
  bool applied = false;            ///< false when there was no direction or nothing can move
};

/// Stiffnesses of a proximity constraint (PBD, dimensionless, in [0, 1]).
struct ProximityStiffness {
  Real compression = 1;  ///< used when C < 0 (closer than d)
  Real stretch = 1;      ///< used when C > 0 (farther than d)
};

/// Point x₀ against the edge [x₁, x₂]; inverse masses in the same order.
ProximityCorrection<3> pointEdgeDistancePbd(const std::array<Vector3, 3>& positions,
                                            const std::array<Real, 3>& inverseMasses,
                                            Real restDistance, ProximityStiffness stiffness);

/// Point x₀ against the triangle (x₁, x₂, x₃).
ProximityCorrection<4> pointTriangleDistancePbd(const std::array<Vector3, 4>& positions,
                                                const std::array<Real, 4>& inverseMasses,
                                                Real restDistance, ProximityStiffness stiffness);

/// Edge [x₀, x₁] against edge [x₂, x₃].
ProximityCorrection<4> edgeEdgeDistancePbd(const std::array<Vector3, 4>& positions,
                                           const std::array<Real, 4>& inverseMasses,
                                           Real restDistance, ProximityStiffness stiffness);

}  // namespace pbd
