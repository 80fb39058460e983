// Box contacts in closed form (primitive_contacts.h).
//
// Box–box: separating axes, then a clipped face or an edge pair (the scheme of Gottschalk's
// OBB test and of the box–box manifolds of ODE's dBoxBox and Box2D; written here anew).
// Boxes A, B with centres c_A, c_B, axes A_i, B_j (columns of their rotations), half extents
// a, b; d = c_B − c_A. For a unit axis L the boxes' projections are separated by
//   σ(L) = |L·d| − Σ_i a_i |L·A_i| − Σ_j b_j |L·B_j|,
// and the boxes are disjoint iff σ(L) > 0 for one of the 15 axes A_i, B_j, A_i × B_j
// (normalised; parallel edge pairs, |A_i × B_j|² < 10⁻¹², are skipped: a face axis already
// covers them). The largest σ over the 15 axes is the signed distance when it is positive
// along a face axis, and minus the penetration depth otherwise (the shortest separating
// translation is along one of these axes for two boxes). No axis above maxSeparation: no
// contact. Else the axis of the largest σ decides, with a bias towards faces (the face axis
// of the box whose σ is larger by more than 10⁻³ of the smallest half extent, and within that
// band the larger face: a box on the ground has the ground as its reference, its own corners
// as the contacts; an edge axis only when it beats both by 10⁻² of the smallest half extent),
// so that a box resting on another keeps one reference face from step to step:
//   - face axis: the reference face is that face of its box, n_ref = ±R_i towards the other
//     box's centre; the incident face is the other box's face most opposed to n_ref. The
//     incident face's 4 corners are clipped (Sutherland–Hodgman) to the 4 side planes of the
//     reference face, (p − c_ref)·R_u ≤ h_u and ≥ −h_u for the two other axes u; each clipped
//     point p with s = n_ref·(p − c_ref) − h_i ≤ maxSeparation is a contact, p on the incident
//     box and p − s n_ref on the reference face. More than 4 are reduced to 4 (the deepest,
//     the farthest from it, then the two spanning the largest triangles on either side). When
//     nothing is left (boxes apart sideways), or the boxes are apart and every clipped point
//     is farther than the incident box's support corner along −n_ref (the closest corner lies
//     beyond the rim), that corner is a contact too, with s = σ (a lower bound of the
//     distance: a speculative contact is never late). The contacts come in
//     the order of the incident box's corner numbering (x fastest, its surface samples'), so
//     that equally deep corners are solved in the order the samples were.
//   - edge axis A_i × B_j, oriented from A to B: the supporting edges are A's edge along A_i
//     through c_A + Σ_{k≠i} a_k sgn(L·A_k) A_k and B's along B_j through
//     c_B − Σ_{k≠j} b_k sgn(L·B_k) B_k; their closest points q_A, q_B (the lines' common
//     perpendicular, clamped to the edges) are one contact with n = −L and s = L·(q_B − q_A).
//
// Box inside a hollow box's cavity (half extents h = b − t; sphere_contacts.cpp): each corner
// v of the box (in the hollow box's frame) against each inner wall k± (σ = ±1) is a contact
// when s = h_k − σ v_k ≤ maxSeparation, with n = −σ e_k, p_B = v + (σ h_k − v_k) e_k, p_A = v.
// Exact for a convex polytope against a plane: the deepest points are corners. Used while the
// box's centre is inside the cavity; otherwise the pair keeps its samples.
#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "pbd/collision/primitive_contacts.h"

namespace pbd {
namespace {

/// Up to 8 points of a convex polygon (4 corners clipped by 4 planes).
struct Polygon {
  std::array<Vector3, 8> points;
  int count = 0;
};

/// Keeps the part of `in` with (p − origin)·axis ≤ limit.
void clip(const Polygon& in, const Vector3& origin, const Vector3& axis, Real limit, Polygon& out) {
  out.count = 0;
  for (int i = 0; i < in.count; ++i) {
    const Vector3& p = in.points[std::size_t(i)];
    const Vector3& q = in.points[std::size_t((i + 1) % in.count)];
    const Real dp = (p - origin).dot(axis) - limit, dq = (q - origin).dot(axis) - limit;
    if (dp <= 0 && out.count < 8) out.points[std::size_t(out.count++)] = p;
    if ((dp < 0 && dq > 0) || (dp > 0 && dq < 0)) {
      if (out.count < 8) out.points[std::size_t(out.count++)] = p + (dp / (dp - dq)) * (q - p);
    }
  }
}

struct FaceCandidate {
  Vector3 incident;  ///< point on the incident box
  Real separation;   ///< s
  int rank;          ///< a corner of the incident box: its index (x fastest); else 8 + position
};

/// A face contact: reference box (c, R, h) with face axis i, the other box (c, R, h).
void faceContacts(const PlacedPrimitive& reference, int axis, const PlacedPrimitive& incident,
                  Real maxSeparation, bool referenceIsA, PrimitiveManifold& out) {
  const Vector3 toIncident = incident.center - reference.center;
  const Vector3 referenceAxis = reference.rotation.col(axis);
  const Vector3 normal =
      referenceAxis.dot(toIncident) < 0 ? Vector3(-referenceAxis) : referenceAxis;  // n_ref
  // The incident face: the other box's face most opposed to n_ref.
  int k = 0;
  Real best = -1;
  for (int j = 0; j < 3; ++j) {
    const Real alignment = std::abs(incident.rotation.col(j).dot(normal));
    if (alignment > best) {
      best = alignment;
      k = j;
    }
  }
  const Vector3 kAxis = incident.rotation.col(k);
  const Real faceSign = kAxis.dot(normal) > 0 ? Real(-1) : Real(1);
  const int u = (k + 1) % 3, v = (k + 2) % 3;
  const Vector3 faceCenter = incident.center + faceSign * incident.size[k] * kAxis;
  const Vector3 eu = incident.size[u] * incident.rotation.col(u);
  const Vector3 ev = incident.size[v] * incident.rotation.col(v);
  Polygon polygon, clipped;
  polygon.points = {faceCenter + eu + ev, faceCenter - eu + ev, faceCenter - eu - ev,
                    faceCenter + eu - ev};
  polygon.count = 4;
  // The corners' indices in the box (x fastest, as its surface samples are numbered), so that
  // equally deep corners come in the samples' order.
  std::array<int, 4> cornerIndex{};
  const Real cornerSigns[4][2] = {{1, 1}, {-1, 1}, {-1, -1}, {1, -1}};
  for (int c = 0; c < 4; ++c) {
    Vector3 signs;
    signs[k] = faceSign;
    signs[u] = cornerSigns[c][0];
    signs[v] = cornerSigns[c][1];
    cornerIndex[std::size_t(c)] =
        (signs.x() > 0 ? 1 : 0) + (signs.y() > 0 ? 2 : 0) + (signs.z() > 0 ? 4 : 0);
  }
  const std::array<Vector3, 8> corners = polygon.points;
  // Clip to the reference face's four side planes.
  const int ru = (axis + 1) % 3, rv = (axis + 2) % 3;
  for (const int side : {ru, rv})
    for (const Real sign : {Real(1), Real(-1)}) {
      clip(polygon, reference.center, sign * reference.rotation.col(side), reference.size[side],
           clipped);
      polygon = clipped;
    }
  std::array<FaceCandidate, 8> kept;
  int count = 0;
  for (int i = 0; i < polygon.count; ++i) {
    const Vector3& p = polygon.points[std::size_t(i)];
    const Real separation = normal.dot(p - reference.center) - reference.size[axis];
    if (!(separation <= maxSeparation)) continue;
    int rank = 8 + i;
    for (int c = 0; c < 4; ++c)
      if (p == corners[std::size_t(c)]) rank = cornerIndex[std::size_t(c)];
    kept[std::size_t(count++)] = {p, separation, rank};
  }
  // In rank order (insertion sort of at most 8).
  for (int i = 1; i < count; ++i)
    for (int j = i; j > 0 && kept[std::size_t(j)].rank < kept[std::size_t(j - 1)].rank; --j)
      std::swap(kept[std::size_t(j)], kept[std::size_t(j - 1)]);
  // The incident box's support corner along −n_ref: its separation is the axis' σ, a lower
  // bound of the distance. It becomes a contact when nothing of the incident face lies over
  // the reference face (boxes apart sideways), and when the boxes are apart and every clipped
  // point is farther than it (the closest corner lies beyond the reference face's rim): the
  // reference face is then taken as its plane, a speculative contact that is never late. (A
  // nanometre of slack: the clipped corner and the support corner are the same point computed
  // twice.)
  Vector3 support = incident.center;
  for (int j = 0; j < 3; ++j) {
    const Vector3 axisJ = incident.rotation.col(j);
    support -= (axisJ.dot(normal) < 0 ? Real(-1) : Real(1)) * incident.size[j] * axisJ;
  }
  const Real supportSeparation = normal.dot(support - reference.center) - reference.size[axis];
  Real closestKept = std::numeric_limits<Real>::infinity();
  for (int i = 0; i < count; ++i)
    closestKept = std::min(closestKept, kept[std::size_t(i)].separation);
  const bool supportIsCloser =
      supportSeparation > 0 && closestKept > supportSeparation + Real(1e-9);
  if (supportSeparation <= maxSeparation && (count == 0 || supportIsCloser) && count < 8)
    kept[std::size_t(count++)] = {support, supportSeparation, 16};
  // Reduce to 4: the deepest, the farthest from it, then the largest triangles on either side
  // of the line through them (signed area along n_ref).
  std::array<int, 4> chosen{};
  int chosenCount = count;
  if (count > 4) {
    int first = 0;
    for (int i = 1; i < count; ++i)
      if (kept[std::size_t(i)].separation < kept[std::size_t(first)].separation) first = i;
    int second = first == 0 ? 1 : 0;
    for (int i = 0; i < count; ++i)
      if (i != first &&
          (kept[std::size_t(i)].incident - kept[std::size_t(first)].incident).squaredNorm() >
              (kept[std::size_t(second)].incident - kept[std::size_t(first)].incident)
                  .squaredNorm())
        second = i;
    const Vector3 p0 = kept[std::size_t(first)].incident, p1 = kept[std::size_t(second)].incident;
    int third = -1, fourth = -1;
    Real most = 0, least = 0;
    for (int i = 0; i < count; ++i) {
      if (i == first || i == second) continue;
      const Real area = normal.dot((p1 - p0).cross(kept[std::size_t(i)].incident - p0));
      if (third < 0 || area > most) {
        most = area;
        third = i;
      }
      if (fourth < 0 || area < least) {
        least = area;
        fourth = i;
      }
    }
    chosen = {first, second, third, fourth};
    chosenCount = third == fourth ? 3 : 4;
  } else {
    for (int i = 0; i < count; ++i)
      chosen[std::size_t(i)] = i;
  }
  out.normalFixedInA = referenceIsA;
  for (int c = 0; c < chosenCount; ++c) {
    const FaceCandidate& candidate = kept[std::size_t(chosen[std::size_t(c)])];
    const Vector3 onReference = candidate.incident - candidate.separation * normal;
    if (referenceIsA)  // n_ref points from A to B; the manifold's normal from B to A
      out.add({onReference, candidate.incident, -normal, candidate.separation});
    else
      out.add({candidate.incident, onReference, normal, candidate.separation});
  }
}

Real clampTo(Real value, Real limit) {
  return std::max(-limit, std::min(limit, value));
}

}  // namespace

void boxBoxContacts(const PlacedPrimitive& a, const PlacedPrimitive& b, Real maxSeparation,
                    PrimitiveManifold& out) {
  const Matrix3& ra = a.rotation;
  const Matrix3& rb = b.rotation;
  const Vector3& ha = a.size;
  const Vector3& hb = b.size;
  const Vector3 d = b.center - a.center;
  const Matrix3 c = ra.transpose() * rb;  // B's axes in A's frame
  const Matrix3 absC = c.cwiseAbs();
  const Vector3 dA = ra.transpose() * d;

  // Face axes of A and of B.
  Real faceA = -std::numeric_limits<Real>::infinity(), faceB = faceA;
  int axisA = 0, axisB = 0;
  for (int i = 0; i < 3; ++i) {
    const Real s = std::abs(dA[i]) - (ha[i] + hb.dot(absC.row(i)));
    if (s > maxSeparation) return;
    if (s > faceA) {
      faceA = s;
      axisA = i;
    }
  }
  for (int j = 0; j < 3; ++j) {
    const Real s = std::abs(dA.dot(c.col(j))) - (hb[j] + ha.dot(absC.col(j)));
    if (s > maxSeparation) return;
    if (s > faceB) {
      faceB = s;
      axisB = j;
    }
  }
  // Edge axes A_i × B_j (in A's frame: e_i × c.col(j)).
  Real edge = -std::numeric_limits<Real>::infinity();
  int edgeI = -1, edgeJ = -1;
  Vector3 edgeAxis = Vector3::Zero();  // in A's frame, unit
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const Vector3 axis = Vector3::Unit(i).cross(c.col(j));
      const Real squared = axis.squaredNorm();
      if (squared < Real(1e-12)) continue;  // parallel edges: a face axis covers them
      const Vector3 l = axis / std::sqrt(squared);
      const Real s =
          std::abs(l.dot(dA)) - (ha.dot(l.cwiseAbs()) + hb.dot((c.transpose() * l).cwiseAbs()));
      if (s > maxSeparation) return;
      if (s > edge) {
        edge = s;
        edgeI = i;
        edgeJ = j;
        edgeAxis = l;
      }
    }

  const Real scale = std::min(ha.minCoeff(), hb.minCoeff());
  const Real faceBias = Real(1e-3) * scale;
  const auto faceArea = [](const Vector3& half, int axis) {
    return half[(axis + 1) % 3] * half[(axis + 2) % 3];
  };
  const bool useB = faceB > faceA + faceBias ||
                    (!(faceA > faceB + faceBias) && faceArea(hb, axisB) > faceArea(ha, axisA));
  const Real face = useB ? faceB : faceA;
  if (edgeI >= 0 && edge > face + Real(1e-2) * scale) {
    Vector3 l = ra * edgeAxis;
    if (l.dot(d) < 0) l = -l;  // from A to B
    Vector3 pointA = a.center, pointB = b.center;
    for (int k = 0; k < 3; ++k) {
      if (k != edgeI) pointA += ha[k] * (l.dot(ra.col(k)) < 0 ? Real(-1) : Real(1)) * ra.col(k);
      if (k != edgeJ) pointB -= hb[k] * (l.dot(rb.col(k)) < 0 ? Real(-1) : Real(1)) * rb.col(k);
    }
    const Vector3 u = ra.col(edgeI), v = rb.col(edgeJ);
    const Vector3 r = pointA - pointB;
    const Real uv = u.dot(v), ur = u.dot(r), vr = v.dot(r);
    const Real denominator = 1 - uv * uv;  // > 10⁻¹² (the axis was not skipped)
    const Real s = clampTo((uv * vr - ur) / denominator, ha[edgeI]);
    const Real t = clampTo(vr + s * uv, hb[edgeJ]);
    const Vector3 qa = pointA + s * u, qb = pointB + t * v;
    out.normalFixedInA = false;
    out.add({qa, qb, -l, l.dot(qb - qa)});
    return;
  }
  if (useB)
    faceContacts(b, axisB, a, maxSeparation, /*referenceIsA=*/false, out);
  else
    faceContacts(a, axisA, b, maxSeparation, /*referenceIsA=*/true, out);
}

bool boxInHollowBoxContacts(const PlacedPrimitive& box, const PlacedPrimitive& hollowBox,
                            Real maxSeparation, PrimitiveManifold& out) {
  const Vector3 cavity = hollowBox.size - Vector3::Constant(hollowBox.thickness);  // h
  const Matrix3 toHollow = hollowBox.rotation.transpose();
  const Vector3 center = toHollow * (box.center - hollowBox.center);
  if (!(cavity.array() > 0).all() || !(center.cwiseAbs().array() < cavity.array()).all())
    return false;
  const Matrix3 axes = toHollow * box.rotation;  // the box's axes in the hollow box's frame
  for (int k = 0; k < 3; ++k)
    for (const Real sign : {Real(1), Real(-1)})
      for (int corner = 0; corner < 8; ++corner) {
        const Vector3 signs((corner & 1) ? -1 : 1, (corner & 2) ? -1 : 1, (corner & 4) ? -1 : 1);
        const Vector3 v = center + axes * signs.cwiseProduct(box.size);
        const Real separation = cavity[k] - sign * v[k];
        if (separation > maxSeparation) continue;
        const Vector3 onWall = v + (sign * cavity[k] - v[k]) * Vector3::Unit(k);
        out.add({hollowBox.rotation * v + hollowBox.center,
                 hollowBox.rotation * onWall + hollowBox.center, -sign * hollowBox.rotation.col(k),
                 separation});
      }
  return true;
}

}  // namespace pbd
