// Proximity distance constraints (constraints/proximity_distance.h): the closest points against
// closed forms (point over an edge's interior or beyond a vertex, point over a triangle's face,
// beyond a vertex or an edge, crossing, skew and parallel edges, degenerate features); one PBD
// projection with k = 1 reaches |p − q| = d for the fixed barycentrics; linear momentum;
// static particles; the compression and stretch stiffness each on its side; no direction.
#include <gtest/gtest.h>

#include <cmath>

#include "pbd/constraints/proximity_distance.h"

namespace pbd {
namespace {

// Closed-form closest points are exact or a few roundings of O(1) numbers away.
const Real kClosedFormTolerance = 8 * kEpsilon;

TEST(ProximityDistance, ClosestPointOnSegment) {
  const Vector3 a(0, 0, 0), b(2, 0, 0);
  EXPECT_NEAR(closestPointOnSegment(Vector3(0.5, 1, 0), a, b), 0.25, kClosedFormTolerance);
  EXPECT_EQ(closestPointOnSegment(Vector3(3, 1, -1), a, b), 1);     // beyond b
  EXPECT_EQ(closestPointOnSegment(Vector3(-1, -1, 2), a, b), 0);    // beyond a
  EXPECT_EQ(closestPointOnSegment(Vector3(-1, -1, 2), a, a), 0.5);  // zero length: midpoint
}

Vector3 pointFromBarycentrics(const Vector3& bary, const Vector3& a, const Vector3& b,
                              const Vector3& c) {
  return bary.x() * a + bary.y() * b + bary.z() * c;
}

TEST(ProximityDistance, ClosestPointOnTriangle) {
  const Vector3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  struct Case {
    Vector3 p, expected;  // expected barycentrics (u, v, w)
  };
  const Case cases[] = {
      {Vector3(0.2, 0.3, 0.7), Vector3(0.5, 0.2, 0.3)},  // over the face: projection (0.2, 0.3)
      {Vector3(2, -1, 0.5), Vector3(0, 1, 0)},           // beyond vertex b
      {Vector3(-1, -0.5, -3), Vector3(1, 0, 0)},         // beyond vertex a
      {Vector3(-0.2, 3, 0.1), Vector3(0, 0, 1)},         // beyond vertex c
      {Vector3(1, 1, -0.4), Vector3(0, 0.5, 0.5)},       // beyond edge bc: (0.5, 0.5)
      {Vector3(0.3, -2, 1), Vector3(0.7, 0.3, 0)},       // beyond edge ab: (0.3, 0)
      {Vector3(-1, 0.6, 0.2), Vector3(0.4, 0, 0.6)},     // beyond edge ca: (0, 0.6)
  };
  for (const Case& k : cases) {
    const Vector3 bary = closestPointOnTriangle(k.p, a, b, c);
    EXPECT_NEAR((bary - k.expected).norm(), 0, kClosedFormTolerance) << k.p.transpose();
    EXPECT_NEAR(bary.sum(), 1, kClosedFormTolerance);
  }
  // A collinear triangle: the closest point of its edges, (1.5, 0, 0).
  const Vector3 c2(2, 0, 0);
  const Vector3 bary = closestPointOnTriangle(Vector3(1.5, 1, 0), a, b, c2);
  EXPECT_TRUE(bary.allFinite());
  EXPECT_NEAR((pointFromBarycentrics(bary, a, b, c2) - Vector3(1.5, 0, 0)).norm(), 0,
              kClosedFormTolerance);
  // All three vertices in one point.
  const Vector3 point = closestPointOnTriangle(Vector3(1, 1, 1), a, a, a);
  EXPECT_TRUE(point.allFinite());
  EXPECT_NEAR(point.sum(), 1, kClosedFormTolerance);
}

TEST(ProximityDistance, ClosestPointsOfSegments) {
  // Crossing at a distance 1 (x axis and a line along y at z = 1): both midpoints.
  SegmentPairParameters st = closestPointsOfSegments(Vector3(-1, 0, 0), Vector3(1, 0, 0),
                                                     Vector3(0, -1, 1), Vector3(0, 1, 1));
  EXPECT_NEAR(st.s, 0.5, kClosedFormTolerance);
  EXPECT_NEAR(st.t, 0.5, kClosedFormTolerance);
  // Skew, the second beyond the first's end: s = 1, t = 1/2.
  st = closestPointsOfSegments(Vector3(0, 0, 0), Vector3(1, 0, 0), Vector3(2, -1, 1),
                               Vector3(2, 1, 1));
  EXPECT_NEAR(st.s, 1, kClosedFormTolerance);
  EXPECT_NEAR(st.t, 0.5, kClosedFormTolerance);
  // Parallel and overlapping on x ∈ [1, 2], 1 apart: any pair over the overlap, at distance 1
  // and orthogonal to both.
  const Vector3 a0(0, 0, 0), a1(2, 0, 0), b0(1, 1, 0), b1(3, 1, 0);
  st = closestPointsOfSegments(a0, a1, b0, b1);
  const Vector3 difference = ((1 - st.s) * a0 + st.s * a1) - ((1 - st.t) * b0 + st.t * b1);
  EXPECT_NEAR(difference.norm(), 1, kClosedFormTolerance);
  EXPECT_NEAR(difference.x(), 0, kClosedFormTolerance);
  EXPECT_GE(st.s, 0);
  EXPECT_LE(st.s, 1);
  EXPECT_GE(st.t, 0);
  EXPECT_LE(st.t, 1);
  // Parallel and disjoint along x: the facing ends, a₁ = (2, 0, 0) and b₀ = (3, 1, 0).
  st = closestPointsOfSegments(a0, a1, Vector3(3, 1, 0), Vector3(5, 1, 0));
  EXPECT_NEAR(st.s, 1, kClosedFormTolerance);
  EXPECT_NEAR(st.t, 0, kClosedFormTolerance);
  // A zero-length first edge: its point against the second edge.
  st = closestPointsOfSegments(Vector3(0.5, 2, 0), Vector3(0.5, 2, 0), a0, a1);
  EXPECT_EQ(st.s, 0.5);
  EXPECT_NEAR(st.t, 0.25, kClosedFormTolerance);
}

// The difference vector p − q = Σ bᵢ xᵢ for given coefficients.
template <int N>
Vector3 difference(const std::array<Vector3, N>& x, const std::array<Real, N>& b) {
  Vector3 d = Vector3::Zero();
  for (std::size_t i = 0; i < std::size_t(N); ++i)
    d += b[i] * x[i];
  return d;
}

template <int N>
std::array<Vector3, N> corrected(std::array<Vector3, N> x, const ProximityCorrection<N>& c) {
  for (std::size_t i = 0; i < std::size_t(N); ++i)
    x[i] += c.delta[i];
  return x;
}

// The three constraints in one general configuration each, with their barycentric
// coefficients (from the closest-point functions, tested above).
struct PointEdgeCase {
  std::array<Vector3, 3> x{Vector3(0.3, 0.8, -0.2), Vector3(-0.5, 0.1, 0.2),
                           Vector3(0.9, -0.2, 0.1)};
  std::array<Real, 3> coefficients() const {
    const Real t = closestPointOnSegment(x[0], x[1], x[2]);
    return {1, -(1 - t), -t};
  }
};
struct PointTriangleCase {
  std::array<Vector3, 4> x{Vector3(0.2, 0.25, 0.6), Vector3(-0.1, 0, 0.05), Vector3(0.9, 0.1, 0),
                           Vector3(0.1, 0.8, -0.1)};
  std::array<Real, 4> coefficients() const {
    const Vector3 b = closestPointOnTriangle(x[0], x[1], x[2], x[3]);
    return {1, -b.x(), -b.y(), -b.z()};
  }
};
struct EdgeEdgeCase {
  std::array<Vector3, 4> x{Vector3(-0.6, 0.1, 0), Vector3(0.7, -0.1, 0.1), Vector3(0.1, -0.5, 0.7),
                           Vector3(-0.2, 0.6, 0.5)};
  std::array<Real, 4> coefficients() const {
    const SegmentPairParameters st = closestPointsOfSegments(x[0], x[1], x[2], x[3]);
    return {1 - st.s, st.s, -(1 - st.t), -st.t};
  }
};

// Checks one projection: the value, |p − q| after it with the barycentrics held, momentum.
template <int N>
void checkProjection(const std::array<Vector3, N>& x, const std::array<Real, N>& b,
                     const std::array<Real, N>& w, Real rest, ProximityStiffness stiffness,
                     const ProximityCorrection<N>& c) {
  const Real before = difference<N>(x, b).norm();
  // The closest-point barycentrics are inside the features (interior configurations).
  ASSERT_GT(before, 0);
  EXPECT_NEAR(c.value, before - rest, kClosedFormTolerance);
  ASSERT_TRUE(c.applied);
  const Real k = c.value < 0 ? stiffness.compression : stiffness.stretch;
  // The constraint is linear along n: C after = (1 − k) C. Round-off: a few ε of the O(1)
  // positions per coordinate (16 ε).
  const Real after = difference<N>(corrected<N>(x, c), b).norm();
  EXPECT_NEAR(after - rest, (1 - k) * c.value, 16 * kEpsilon);
  // Momentum: Σ Δxᵢ/wᵢ = 0 up to the round-off of N terms of size |C| |bᵢ| / Σ wⱼ bⱼ² ≤ ~4.
  Vector3 momentum = Vector3::Zero();
  for (std::size_t i = 0; i < std::size_t(N); ++i)
    if (w[i] > 0) momentum += c.delta[i] / w[i];
  bool allDynamic = true;
  for (Real wi : w)
    allDynamic = allDynamic && wi > 0;
  if (allDynamic) {
    EXPECT_NEAR(momentum.norm(), 0, 64 * kEpsilon);
  }
  for (std::size_t i = 0; i < std::size_t(N); ++i) {
    if (w[i] == 0) {
      EXPECT_EQ(c.delta[i], Vector3::Zero());
    }
  }
}

TEST(ProximityDistance, UnitStiffnessReachesTheRestDistanceAndConservesMomentum) {
  const ProximityStiffness unit{1, 1};
  for (Real rest : {Real(0.05), Real(1.5)}) {  // stretch (C > 0) and compression (C < 0)
    const PointEdgeCase pe;
    const std::array<Real, 3> w3{1, 0.5, 2};
    checkProjection<3>(pe.x, pe.coefficients(), w3, rest, unit,
                       pointEdgeDistancePbd(pe.x, w3, rest, unit));
    const PointTriangleCase pt;
    const std::array<Real, 4> w4{0.7, 1, 0.5, 2};
    checkProjection<4>(pt.x, pt.coefficients(), w4, rest, unit,
                       pointTriangleDistancePbd(pt.x, w4, rest, unit));
    const EdgeEdgeCase ee;
    checkProjection<4>(ee.x, ee.coefficients(), w4, rest, unit,
                       edgeEdgeDistancePbd(ee.x, w4, rest, unit));
  }
}

TEST(ProximityDistance, StaticParticlesDoNotMove) {
  const ProximityStiffness unit{1, 1};
  const Real rest = Real(0.3);
  const PointEdgeCase pe;
  const std::array<Real, 3> edgeStatic{1, 0, 0};  // only the point moves
  checkProjection<3>(pe.x, pe.coefficients(), edgeStatic, rest, unit,
                     pointEdgeDistancePbd(pe.x, edgeStatic, rest, unit));
  const PointTriangleCase pt;
  const std::array<Real, 4> pointStatic{0, 1, 0, 2};
  checkProjection<4>(pt.x, pt.coefficients(), pointStatic, rest, unit,
                     pointTriangleDistancePbd(pt.x, pointStatic, rest, unit));
  const EdgeEdgeCase ee;
  const std::array<Real, 4> firstEdgeStatic{0, 0, 1, 1};
  checkProjection<4>(ee.x, ee.coefficients(), firstEdgeStatic, rest, unit,
                     edgeEdgeDistancePbd(ee.x, firstEdgeStatic, rest, unit));
  // Everything static: no correction.
  const ProximityCorrection<4> none = edgeEdgeDistancePbd(ee.x, {0, 0, 0, 0}, rest, unit);
  EXPECT_FALSE(none.applied);
  for (const Vector3& d : none.delta)
    EXPECT_EQ(d, Vector3::Zero());
}

TEST(ProximityDistance, CompressionAndStretchStiffnessOnTheirSides) {
  // Distinct stiffnesses: the remaining error (1 − k) C names the one used.
  const ProximityStiffness stiffness{Real(0.25), Real(0.75)};
  const std::array<Real, 4> w4{0.7, 1, 0.5, 2};
  const PointTriangleCase pt;
  const Real distance = difference<4>(pt.x, pt.coefficients()).norm();
  const ProximityCorrection<4> stretched =
      pointTriangleDistancePbd(pt.x, w4, distance / 2, stiffness);  // C > 0
  ASSERT_GT(stretched.value, 0);
  checkProjection<4>(pt.x, pt.coefficients(), w4, distance / 2, stiffness, stretched);
  const ProximityCorrection<4> compressed =
      pointTriangleDistancePbd(pt.x, w4, 2 * distance, stiffness);  // C < 0
  ASSERT_LT(compressed.value, 0);
  checkProjection<4>(pt.x, pt.coefficients(), w4, 2 * distance, stiffness, compressed);
  // And directly: the remaining errors are 1/4 (stretch k = 3/4) and 3/4 (compression k = 1/4)
  // of the initial ones, whose sizes are distance/2 and distance.
  const Real afterStretch = difference<4>(corrected<4>(pt.x, stretched), pt.coefficients()).norm();
  EXPECT_NEAR(afterStretch - distance / 2, distance / 8, 16 * kEpsilon);
  const Real afterCompress =
      difference<4>(corrected<4>(pt.x, compressed), pt.coefficients()).norm();
  EXPECT_NEAR(afterCompress - 2 * distance, -Real(0.75) * distance, 16 * kEpsilon);
}

TEST(ProximityDistance, ZeroDistanceHasNoDirectionAndNoCorrection) {
  const ProximityStiffness unit{1, 1};
  // The point on the edge's interior, on the triangle's face; crossing edges.
  const ProximityCorrection<3> pe = pointEdgeDistancePbd(
      {Vector3(0.5, 0, 0), Vector3(0, 0, 0), Vector3(1, 0, 0)}, {1, 1, 1}, Real(0.1), unit);
  const ProximityCorrection<4> pt = pointTriangleDistancePbd(
      {Vector3(0.25, 0.25, 0), Vector3(0, 0, 0), Vector3(1, 0, 0), Vector3(0, 1, 0)}, {1, 1, 1, 1},
      Real(0.1), unit);
  const ProximityCorrection<4> ee = edgeEdgeDistancePbd(
      {Vector3(-1, 0, 0), Vector3(1, 0, 0), Vector3(0, -1, 0), Vector3(0, 1, 0)}, {1, 1, 1, 1},
      Real(0.1), unit);
  EXPECT_FALSE(pe.applied);
  EXPECT_FALSE(pt.applied);
  EXPECT_FALSE(ee.applied);
  EXPECT_EQ(pe.value, Real(-0.1));
  for (const Vector3& d : pe.delta)
    EXPECT_EQ(d, Vector3::Zero());
  for (const Vector3& d : pt.delta)
    EXPECT_EQ(d, Vector3::Zero());
  for (const Vector3& d : ee.delta)
    EXPECT_EQ(d, Vector3::Zero());
}

TEST(ProximityDistance, DegenerateFeaturesGiveFiniteCorrections) {
  const ProximityStiffness unit{1, 1};
  // A zero-length edge is the point at its midpoint: the point–point distance, 1, to d = 0.5.
  const std::array<Vector3, 3> x{Vector3(0, 1, 0), Vector3(0, 0, 0), Vector3(0, 0, 0)};
  const ProximityCorrection<3> c = pointEdgeDistancePbd(x, {1, 1, 1}, Real(0.5), unit);
  ASSERT_TRUE(c.applied);
  EXPECT_NEAR(c.value, 0.5, kClosedFormTolerance);
  const Vector3 after =
      (x[0] + c.delta[0]) - Real(0.5) * ((x[1] + c.delta[1]) + (x[2] + c.delta[2]));
  EXPECT_NEAR(after.norm(), 0.5, kClosedFormTolerance);
  // A collinear triangle.
  const ProximityCorrection<4> t = pointTriangleDistancePbd(
      {Vector3(1.5, 1, 0), Vector3(0, 0, 0), Vector3(1, 0, 0), Vector3(2, 0, 0)}, {1, 1, 1, 1},
      Real(0.5), unit);
  ASSERT_TRUE(t.applied);
  EXPECT_NEAR(t.value, 0.5, kClosedFormTolerance);  // distance 1 to the line y = 0
  for (const Vector3& d : t.delta)
    EXPECT_TRUE(d.allFinite());
}

}  // namespace
}  // namespace pbd
