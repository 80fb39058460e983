#include "pbd/constraints/proximity_distance.h"

#include <algorithm>

namespace pbd {
namespace {

Real clampUnit(Real x) {
  return std::min(Real(1), std::max(Real(0), x));
}

/// The PBD projection of C = |Σᵢ bᵢ xᵢ| − d with the barycentric coefficients b held constant
/// (the formulas at the top of the header).
template <int N>
ProximityCorrection<N> projectDifference(const std::array<Vector3, N>& positions,
                                         const std::array<Real, N>& inverseMasses,
                                         const std::array<Real, N>& coefficients, Real restDistance,
                                         ProximityStiffness stiffness) {
  ProximityCorrection<N> correction;
  for (Vector3& d : correction.delta)
    d.setZero();
  Vector3 difference = Vector3::Zero();
  Real weightSum = 0;  // Σ wⱼ bⱼ²
  for (int i = 0; i < N; ++i) {
    difference += coefficients[std::size_t(i)] * positions[std::size_t(i)];
    weightSum +=
        inverseMasses[std::size_t(i)] * coefficients[std::size_t(i)] * coefficients[std::size_t(i)];
  }
  const Real distance = difference.norm();
  correction.value = distance - restDistance;
  if (!(distance > 0) || !(weightSum > 0)) return correction;
  const Vector3 direction = difference / distance;
  const Real k = correction.value < 0 ? stiffness.compression : stiffness.stretch;
  const Real scale = -k * correction.value / weightSum;
  for (int i = 0; i < N; ++i)
    correction.delta[std::size_t(i)] =
        scale * inverseMasses[std::size_t(i)] * coefficients[std::size_t(i)] * direction;
  correction.applied = true;
  return correction;
}

}  // namespace

Real closestPointOnSegment(const Vector3& p, const Vector3& a, const Vector3& b) {
  const Vector3 edge = b - a;
  const Real lengthSquared = edge.squaredNorm();
  if (!(lengthSquared > 0)) return Real(0.5);
  return clampUnit(edge.dot(p - a) / lengthSquared);
}

Vector3 closestPointOnTriangle(const Vector3& p, const Vector3& a, const Vector3& b,
                               const Vector3& c) {
  const Vector3 ab = b - a, ac = c - a;
  if (ab.cross(ac).squaredNorm() <= kEpsilon * ab.squaredNorm() * ac.squaredNorm()) {
    // Collinear to round-off: the closest of the three edges.
    const Real tab = closestPointOnSegment(p, a, b);
    const Real tbc = closestPointOnSegment(p, b, c);
    const Real tca = closestPointOnSegment(p, c, a);
    const Vector3 onAb(1 - tab, tab, 0), onBc(0, 1 - tbc, tbc), onCa(tca, 0, 1 - tca);
    Vector3 best = onAb;
    Real bestDistance = (p - ((1 - tab) * a + tab * b)).squaredNorm();
    const Real dBc = (p - ((1 - tbc) * b + tbc * c)).squaredNorm();
    if (dBc < bestDistance) best = onBc, bestDistance = dBc;
    const Real dCa = (p - ((1 - tca) * c + tca * a)).squaredNorm();
    if (dCa < bestDistance) best = onCa;
    return best;
  }
  // Voronoi regions of the vertices, then the edges, then the face.
  const Vector3 ap = p - a;
  const Real d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return Vector3(1, 0, 0);
  const Vector3 bp = p - b;
  const Real d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return Vector3(0, 1, 0);
  const Real regionC = d1 * d4 - d3 * d2;  // ∝ barycentric of c of the projection
  if (regionC <= 0 && d1 >= 0 && d3 <= 0) {
    const Real v = d1 / (d1 - d3);
    return Vector3(1 - v, v, 0);
  }
  const Vector3 cp = p - c;
  const Real d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return Vector3(0, 0, 1);
  const Real regionB = d5 * d2 - d1 * d6;  // ∝ barycentric of b
  if (regionB <= 0 && d2 >= 0 && d6 <= 0) {
    const Real w = d2 / (d2 - d6);
    return Vector3(1 - w, 0, w);
  }
  const Real regionA = d3 * d6 - d5 * d4;  // ∝ barycentric of a
  if (regionA <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
    const Real w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return Vector3(0, 1 - w, w);
  }
  const Real inverseSum = 1 / (regionA + regionB + regionC);
  const Real v = regionB * inverseSum, w = regionC * inverseSum;
  return Vector3(1 - v - w, v, w);
}

SegmentPairParameters closestPointsOfSegments(const Vector3& a0, const Vector3& a1,
                                              const Vector3& b0, const Vector3& b1) {
  SegmentPairParameters r;
  const Vector3 da = a1 - a0, db = b1 - b0, offset = a0 - b0;
  const Real aa = da.squaredNorm(), bb = db.squaredNorm(), fb = db.dot(offset);
  const bool pointA = !(aa > 0), pointB = !(bb > 0);
  if (pointA && pointB) {
    r.s = r.t = Real(0.5);
    return r;
  }
  if (pointA) {
    r.s = Real(0.5);
    r.t = closestPointOnSegment(a0, b0, b1);
    return r;
  }
  const Real ca = da.dot(offset);
  if (pointB) {
    r.t = Real(0.5);
    r.s = closestPointOnSegment(b0, a0, a1);
    return r;
  }
  // Minimise |offset + s da − t db|²: the normal equations' determinant is aa bb − ab².
  const Real ab = da.dot(db);
  const Real determinant = aa * bb - ab * ab;
  r.s = determinant > kEpsilon * aa * bb ? clampUnit((ab * fb - ca * bb) / determinant)
                                         : Real(0);  // parallel: any s; start at a₀
  // The best t for that s, then the best s for a clamped t.
  const Real t = (ab * r.s + fb) / bb;
  if (t < 0) {
    r.t = 0;
    r.s = clampUnit(-ca / aa);
  } else if (t > 1) {
    r.t = 1;
    r.s = clampUnit((ab - ca) / aa);
  } else {
    r.t = t;
  }
  return r;
}

ProximityCorrection<3> pointEdgeDistancePbd(const std::array<Vector3, 3>& positions,
                                            const std::array<Real, 3>& inverseMasses,
                                            Real restDistance, ProximityStiffness stiffness) {
  const Real t = closestPointOnSegment(positions[0], positions[1], positions[2]);
  return projectDifference<3>(positions, inverseMasses, {1, -(1 - t), -t}, restDistance, stiffness);
}

ProximityCorrection<4> pointTriangleDistancePbd(const std::array<Vector3, 4>& positions,
                                                const std::array<Real, 4>& inverseMasses,
                                                Real restDistance, ProximityStiffness stiffness) {
  const Vector3 b = closestPointOnTriangle(positions[0], positions[1], positions[2], positions[3]);
  return projectDifference<4>(positions, inverseMasses, {1, -b.x(), -b.y(), -b.z()}, restDistance,
                              stiffness);
}

ProximityCorrection<4> edgeEdgeDistancePbd(const std::array<Vector3, 4>& positions,
                                           const std::array<Real, 4>& inverseMasses,
                                           Real restDistance, ProximityStiffness stiffness) {
  const SegmentPairParameters st =
      closestPointsOfSegments(positions[0], positions[1], positions[2], positions[3]);
  return projectDifference<4>(positions, inverseMasses, {1 - st.s, st.s, -(1 - st.t), -st.t},
                              restDistance, stiffness);
}

}  // namespace pbd
