#include "validation/measure/oracle/narrow_phase.h"

#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>
#include <fcntl.h>
#include <setjmp.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <deque>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "validation/measure/oracle/mesh_geometry.h"

namespace pbdval::fcl_oracle {
namespace {

/// Contacts FCL may report for a pair: one per intersecting triangle pair for meshes, a few
/// (a box–box manifold) for primitives.
constexpr std::size_t kMaxMeshContacts = std::size_t(1) << 20;
constexpr std::size_t kMaxPrimitiveContacts = 16;

fcl::Transform3d identity() {
  return fcl::Transform3d::Identity();
}

bool isConvexShape(OracleShape shape) {
  return shape == OracleShape::Sphere || shape == OracleShape::Box ||
         shape == OracleShape::Cylinder || shape == OracleShape::ConvexMesh;
}

/// FCL 0.7 has closed-form distance and intersection routines for these pairs.
bool hasClosedForm(OracleShape a, OracleShape b) {
  const auto partner = [](OracleShape s) {
    return s == OracleShape::Sphere || s == OracleShape::Box || s == OracleShape::Cylinder;
  };
  return (a == OracleShape::Sphere && partner(b)) || (b == OracleShape::Sphere && partner(a));
}

Vector3 toVector(const fcl::Vector3d& v) {
  return v.cast<Real>();
}

fcl::DistanceResultd runDistance(const fcl::CollisionGeometryd& a, const fcl::Transform3d& poseA,
                                 const fcl::CollisionGeometryd& b, const fcl::Transform3d& poseB,
                                 double tolerance, bool signedDistance) {
  const fcl::DistanceRequestd request(/*enable_nearest_points=*/true, signedDistance,
                                      /*rel_err=*/0, /*abs_err=*/0, tolerance);
  fcl::DistanceResultd result;
  fcl::distance(&a, poseA, &b, poseB, request, result);
  return result;
}

fcl::CollisionResultd runCollide(const fcl::CollisionGeometryd& a, const fcl::Transform3d& poseA,
                                 const fcl::CollisionGeometryd& b, const fcl::Transform3d& poseB,
                                 bool enableContact, std::size_t maxContacts) {
  fcl::CollisionRequestd request(maxContacts, enableContact);
  request.gjk_solver_type = fcl::GST_LIBCCD;
  fcl::CollisionResultd result;
  fcl::collide(&a, poseA, &b, poseB, request, result);
  return result;
}

/// The contact with the largest |depth| (FCL's sphere–triangle contacts carry negative ones).
const fcl::Contactd& deepestContact(const fcl::CollisionResultd& result) {
  std::size_t best = 0;
  for (std::size_t i = 1; i < result.numContacts(); ++i) {
    if (std::abs(result.getContact(i).penetration_depth) >
        std::abs(result.getContact(best).penetration_depth)) {
      best = i;
    }
  }
  return result.getContact(best);
}

/// MPR's contact point lies midway between the two deepest points; FCL's normal points from A
/// to B.
PairDistance fromContact(const fcl::Contactd& contact, DistanceMethod method) {
  const double depth = std::abs(contact.penetration_depth);
  const fcl::Vector3d halfDepth = contact.normal.normalized() * (depth / 2);
  return {-depth, toVector(contact.pos + halfDepth), toVector(contact.pos - halfDepth), method};
}

PairDistance fromDistance(const fcl::DistanceResultd& result, DistanceMethod method) {
  return {result.min_distance, toVector(result.nearest_points[0]),
          toVector(result.nearest_points[1]), method};
}

/// Touching within the tolerances with no witness points from FCL: the midpoint of the shapes'
/// origins stands for the contact.
PairDistance touchingWithoutPoints(const PlacedBody& a, const PlacedBody& b,
                                   DistanceMethod method) {
  const Vector3 middle = toVector((a.pose.translation() + b.pose.translation()) / 2);
  return {0, middle, middle, method};
}

/// Witness points from the sphere of the pair (FCL's contact point is not the same point for
/// every closed form): its deepest point into the other shape is centre ± r·n.
PairDistance sphereContact(const PlacedBody& a, const PlacedBody& b, const fcl::Contactd& contact) {
  const double depth = std::abs(contact.penetration_depth);
  const fcl::Vector3d normal = contact.normal.normalized();  // from A to B
  fcl::Vector3d onA, onB;
  if (a.body.shape == OracleShape::Sphere) {
    onA = a.pose.translation() + a.body.sphereRadius * normal;
    onB = onA - depth * normal;
  } else {
    onB = b.pose.translation() - b.body.sphereRadius * normal;
    onA = onB + depth * normal;
  }
  return {-depth, toVector(onA), toVector(onB), DistanceMethod::ClosedForm};
}

PairDistance closedFormPair(const PlacedBody& a, const PlacedBody& b,
                            const DistanceOracleOptions& tolerances) {
  const fcl::DistanceResultd separation = runDistance(*a.body.geometry, a.pose, *b.body.geometry,
                                                      b.pose, tolerances.distanceTolerance, false);
  if (separation.min_distance > 0) return fromDistance(separation, DistanceMethod::ClosedForm);
  const fcl::CollisionResultd overlap =
      runCollide(*a.body.geometry, a.pose, *b.body.geometry, b.pose, true, kMaxPrimitiveContacts);
  if (!overlap.isCollision()) return touchingWithoutPoints(a, b, DistanceMethod::ClosedForm);
  return sphereContact(a, b, deepestContact(overlap));
}

/// The support feature of a box along direction n: its vertex, edge (2 points) or face (4 points,
/// in cyclic order) farthest along n. An axis counts as perpendicular to n within 1e-9.
std::vector<fcl::Vector3d> boxSupportFeature(const fcl::Transform3d& pose,
                                             const fcl::Vector3d& half, const fcl::Vector3d& n) {
  fcl::Vector3d base = pose.translation();
  std::vector<int> free;
  for (int i = 0; i < 3; ++i) {
    const double along = n.dot(pose.linear().col(i));
    if (std::abs(along) < 1e-9)
      free.push_back(i);
    else
      base += (along > 0 ? half(i) : -half(i)) * pose.linear().col(i);
  }
  if (free.empty()) return {base};
  const fcl::Vector3d u = half(free[0]) * pose.linear().col(free[0]);
  if (free.size() == 1) return {base - u, base + u};
  const fcl::Vector3d v = half(free[1]) * pose.linear().col(free[1]);
  return {base - u - v, base + u - v, base + u + v, base - u + v};  // cyclic
}

/// Closest points of segments [p0, p1] and [q0, q1] (Ericson §5.1.9).
std::pair<fcl::Vector3d, fcl::Vector3d> closestPointsOfSegments(const fcl::Vector3d& p0,
                                                                const fcl::Vector3d& p1,
                                                                const fcl::Vector3d& q0,
                                                                const fcl::Vector3d& q1) {
  const fcl::Vector3d d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r), c = d1.dot(r),
               b = d1.dot(d2);
  const double denominator = a * e - b * b;
  double s = denominator > 1e-18 ? std::clamp((b * f - c * e) / denominator, 0.0, 1.0) : 0.0;
  double t = (b * s + f) / e;
  if (t < 0 || t > 1) {
    t = std::clamp(t, 0.0, 1.0);
    s = std::clamp((b * t - c) / a, 0.0, 1.0);
  }
  return {p0 + s * d1, q0 + t * d2};
}

/// Centroid of the points of `feature` (projected onto the plane of `face`, normal n) clipped to
/// the convex polygon `face` (Sutherland–Hodgman); the projected centroid when nothing remains.
fcl::Vector3d clippedCentroid(const std::vector<fcl::Vector3d>& face,
                              std::vector<fcl::Vector3d> feature, const fcl::Vector3d& n) {
  for (fcl::Vector3d& p : feature)
    p -= n.dot(p - face[0]) * n;
  const fcl::Vector3d centre = (face[0] + face[1] + face[2] + face[3]) / 4;
  std::vector<fcl::Vector3d> points = feature;
  for (std::size_t e = 0; e < face.size() && !points.empty(); ++e) {
    const fcl::Vector3d edge = face[(e + 1) % face.size()] - face[e];
    fcl::Vector3d inward = n.cross(edge);
    if (inward.dot(centre - face[e]) < 0) inward = -inward;
    auto inside = [&](const fcl::Vector3d& p) { return inward.dot(p - face[e]); };
    std::vector<fcl::Vector3d> kept;
    for (std::size_t k = 0; k < points.size(); ++k) {
      const fcl::Vector3d& current = points[k];
      const fcl::Vector3d& next = points[(k + 1) % points.size()];
      const double dc = inside(current), dn = inside(next);
      if (dc >= 0) kept.push_back(current);
      if ((dc >= 0) != (dn >= 0)) kept.push_back(current + (dc / (dc - dn)) * (next - current));
    }
    points = kept;
  }
  const std::vector<fcl::Vector3d>& chosen = points.empty() ? feature : points;
  fcl::Vector3d sum = fcl::Vector3d::Zero();
  for (const fcl::Vector3d& p : chosen)
    sum += p;
  return sum / double(chosen.size());
}

/// Two overlapping boxes: the separating-axis test over the 15 candidate axes (3 face normals of
/// each box, 9 edge cross products) gives the exact penetration depth — the smallest overlap of
/// the boxes' projections, d = r_A + r_B − |L·(c_B − c_A)| — and its direction n (Gottschalk,
/// Lin, Manocha 1996; Ericson, "Real-Time Collision Detection", §4.4). The witness points come
/// from the contact features (A's support feature along n, B's along −n): a vertex, the closest
/// points of two crossing edges, or the centroid of a face's overlap with the other feature.
/// FCL 0.7's EPA, the general route, fails an assertion and aborts the process on nearly flat
/// box contacts.
PairDistance boxBoxPair(const PlacedBody& a, const PlacedBody& b) {
  const fcl::Vector3d halfA = static_cast<const fcl::Boxd&>(*a.body.geometry).side / 2;
  const fcl::Vector3d halfB = static_cast<const fcl::Boxd&>(*b.body.geometry).side / 2;
  const fcl::Matrix3d ra = a.pose.linear(), rb = b.pose.linear();
  const fcl::Vector3d centres = b.pose.translation() - a.pose.translation();
  auto radius = [](const fcl::Matrix3d& r, const fcl::Vector3d& half, const fcl::Vector3d& axis) {
    return half.x() * std::abs(axis.dot(r.col(0))) + half.y() * std::abs(axis.dot(r.col(1))) +
           half.z() * std::abs(axis.dot(r.col(2)));
  };
  double depth = std::numeric_limits<double>::infinity();
  fcl::Vector3d n = fcl::Vector3d::UnitX();
  auto consider = [&](fcl::Vector3d axis) {
    const double length = axis.norm();
    if (length < 1e-9) return;  // parallel edges: the face axes cover this direction
    axis /= length;
    const double overlap =
        radius(ra, halfA, axis) + radius(rb, halfB, axis) - std::abs(axis.dot(centres));
    if (overlap < depth) {
      depth = overlap;
      n = axis.dot(centres) >= 0 ? axis : fcl::Vector3d(-axis);  // from A towards B
    }
  };
  for (int i = 0; i < 3; ++i)
    consider(ra.col(i));
  for (int i = 0; i < 3; ++i)
    consider(rb.col(i));
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      consider(ra.col(i).cross(rb.col(j)));

  const std::vector<fcl::Vector3d> featureA = boxSupportFeature(a.pose, halfA, n);
  const std::vector<fcl::Vector3d> featureB = boxSupportFeature(b.pose, halfB, -n);
  fcl::Vector3d onA, onB;
  if (featureB.size() == 1) {
    onB = featureB[0];
    onA = onB + depth * n;
  } else if (featureA.size() == 1) {
    onA = featureA[0];
    onB = onA - depth * n;
  } else if (featureA.size() == 2 && featureB.size() == 2) {
    std::tie(onA, onB) =
        closestPointsOfSegments(featureA[0], featureA[1], featureB[0], featureB[1]);
  } else if (featureA.size() == 4) {
    onA = clippedCentroid(featureA, featureB, n);
    onB = onA - depth * n;
  } else {
    onB = clippedCentroid(featureB, featureA, n);
    onA = onB + depth * n;
  }
  return {-depth, toVector(onA), toVector(onB), DistanceMethod::BoxBoxSat};
}

// --- Surviving FCL's EPA ------------------------------------------------------------------------
// Debian's libfcl 0.7 is built with assertions, and its EPA fails one
// (ComputeVisiblePatch: isOutsidePolytopeFace) on nearly flat contacts — a cylinder cap or a box
// face resting on a box — and then calls abort(). No tolerance avoids it, and nothing can be
// caught in C++. The call is therefore guarded: a SIGABRT handler installed for its duration
// jumps back (siglongjmp) to the caller, which falls back to MPR's depth. What EPA had allocated
// is leaked (a few kB per failure); libc's assertion message is silenced meanwhile. The
// handler and the stderr redirection are process-wide, so guarded calls are serialised by a
// mutex; an abort on another thread in that window finds no jump target and is re-raised.

thread_local sigjmp_buf* tAbortJump = nullptr;

extern "C" void returnFromAbort(int signal) {
  if (tAbortJump) siglongjmp(*tAbortJump, 1);
  std::signal(signal, SIG_DFL);
  std::raise(signal);
}

/// Runs `call`; false when it aborted.
template <class Call>
bool survivesAbort(Call&& call) {
  static std::mutex guard;
  const std::lock_guard<std::mutex> lock(guard);
  struct sigaction handler {
  }, previous{};
  handler.sa_handler = returnFromAbort;
  sigemptyset(&handler.sa_mask);
  ::sigaction(SIGABRT, &handler, &previous);
  std::fflush(stderr);
  const int savedStderr = ::dup(STDERR_FILENO);
  const int devNull = ::open("/dev/null", O_WRONLY);
  if (devNull >= 0) ::dup2(devNull, STDERR_FILENO);
  sigjmp_buf jump;
  // volatile: written between sigsetjmp and a possible siglongjmp (C11 7.13.2.1).
  volatile bool completed = false;
  tAbortJump = &jump;
  if (sigsetjmp(jump, 1) == 0) {
    call();
    completed = true;
  }
  tAbortJump = nullptr;
  if (savedStderr >= 0) ::dup2(savedStderr, STDERR_FILENO);
  if (savedStderr >= 0) ::close(savedStderr);
  if (devNull >= 0) ::close(devNull);
  ::sigaction(SIGABRT, &previous, nullptr);
  return completed;
}

/// EPA's witness points are |distance| apart unless it failed (it then returns −1 and no
/// points instead of throwing).
bool witnessesAgree(const fcl::DistanceResultd& result, double tolerance) {
  const double gap = (result.nearest_points[0] - result.nearest_points[1]).norm();
  return std::abs(gap - std::abs(result.min_distance)) <= 10 * tolerance;
}

/// Convex pairs without a closed form. libccd's GJK misjudges overlap near contact on curved
/// shapes (it reports overlaps of up to 7e-5 m as gaps), so MPR's intersection test, wrong
/// only within 1e-6 m of contact, decides first (docs/fcl-oracle.md, "Algorithms").
/// Separated: GJK's distance. Overlapping: MPR's depth, an upper bound of the penetration depth
/// (distance to a face of the Minkowski difference), is the answer below the EPA tolerance,
/// where FCL 0.7's EPA aborts the process (a failed assert in libfcl) on nearly touching
/// polytopes. Deeper, EPA gives the exact depth; if it throws, fails or finds no overlap,
/// MPR's depth stands. Two boxes never reach EPA: boxBoxPair's separating-axis depth is exact
/// (and EPA aborted on a box resting on a box at any depth).
PairDistance gjkEpaPair(const PlacedBody& a, const PlacedBody& b,
                        const DistanceOracleOptions& tolerances) {
  const fcl::CollisionResultd overlap =
      runCollide(*a.body.geometry, a.pose, *b.body.geometry, b.pose, true, kMaxPrimitiveContacts);
  if (!overlap.isCollision()) {
    const fcl::DistanceResultd separation = runDistance(
        *a.body.geometry, a.pose, *b.body.geometry, b.pose, tolerances.distanceTolerance, false);
    if (separation.min_distance > 0) return fromDistance(separation, DistanceMethod::GjkEpa);
    return touchingWithoutPoints(a, b, DistanceMethod::GjkEpa);
  }
  if (a.body.shape == OracleShape::Box && b.body.shape == OracleShape::Box) return boxBoxPair(a, b);
  const PairDistance mpr = fromContact(deepestContact(overlap), DistanceMethod::ShallowMpr);
  if (mpr.depth() <= tolerances.epaTolerance) return mpr;
  const PairDistance fallback{mpr.distance, mpr.pointOnA, mpr.pointOnB,
                              DistanceMethod::MprFallback};
  fcl::DistanceResultd epa;
  bool threw = false;
  const bool completed = survivesAbort([&] {
    try {
      epa = runDistance(*a.body.geometry, a.pose, *b.body.geometry, b.pose, tolerances.epaTolerance,
                        true);
    } catch (const std::exception&) {
      threw = true;
    }
  });
  if (!completed || threw) return fallback;
  if (epa.min_distance >= 0 || !witnessesAgree(epa, tolerances.epaTolerance)) return fallback;
  return fromDistance(epa, DistanceMethod::GjkEpa);
}

/// Closest point of a sphere (centre, radius) to an outside point.
fcl::Vector3d sphereSurfaceToward(const fcl::Vector3d& centre, double radius,
                                  const fcl::Vector3d& target) {
  const fcl::Vector3d direction = target - centre;
  const double length = direction.norm();
  return length > 0 ? centre + direction * (radius / length) : centre;
}

/// FCL 0.7's mesh–shape distance is not defined when a triangle intersects the shape (the
/// sphere–triangle routine then leaves it unset), so the intersection test comes first.
/// The mesh goes first, at the identity: FCL then reports the mesh's point in the mesh frame, and
/// the shape's point in the same frame except for spheres (reported in the sphere's own frame),
/// whose point is recomputed.
PairDistance meshConvexPair(const PlacedBody& mesh, const PlacedBody& convex,
                            const DistanceOracleOptions& tolerances, bool meshIsA) {
  const fcl::Transform3d convexInMesh = mesh.pose.inverse(Eigen::Isometry) * convex.pose;
  const fcl::CollisionResultd overlap = runCollide(
      *mesh.body.geometry, identity(), *convex.body.geometry, convexInMesh, true, kMaxMeshContacts);
  double distance = 0;
  fcl::Vector3d onMesh, onConvex;
  DistanceMethod method = DistanceMethod::MeshContact;
  if (overlap.isCollision()) {
    const fcl::Contactd& contact = deepestContact(overlap);
    distance = -std::abs(contact.penetration_depth);
    onMesh = onConvex = contact.pos;
  } else {
    const fcl::DistanceResultd separation =
        runDistance(*mesh.body.geometry, identity(), *convex.body.geometry, convexInMesh,
                    tolerances.distanceTolerance, false);
    distance = std::max(0.0, separation.min_distance);
    method = DistanceMethod::MeshDistance;
    onMesh = separation.nearest_points[0];
    onConvex =
        convex.body.shape == OracleShape::Sphere
            ? sphereSurfaceToward(convexInMesh.translation(), convex.body.sphereRadius, onMesh)
            : separation.nearest_points[1];
  }
  const Vector3 worldOnMesh = toVector(mesh.pose * onMesh);
  const Vector3 worldOnConvex = toVector(mesh.pose * onConvex);
  return meshIsA ? PairDistance{distance, worldOnMesh, worldOnConvex, method}
                 : PairDistance{distance, worldOnConvex, worldOnMesh, method};
}

bool isInside(const MeshData& mesh, const fcl::Vector3d& point) {
  return windingNumber(mesh.mesh, point.cast<Real>()) > 0.5;
}

/// A vertex of one mesh inside the other, with its nearest surface point there.
struct InsideVertex {
  double depth = 0;
  fcl::Vector3d vertex = fcl::Vector3d::Zero();        ///< in the target's frame
  fcl::Vector3d surfacePoint = fcl::Vector3d::Zero();  ///< in the target's frame
  bool found = false;
};

/// The distance from `point` (target frame) to the target mesh's surface, and the nearest point:
/// a zero-radius sphere against the BVH uses FCL's closed-form sphere–triangle distance.
std::pair<double, fcl::Vector3d> distanceToSurface(const BodyGeometry& target,
                                                   const fcl::Vector3d& point) {
  const fcl::Sphered probe(0);
  fcl::Transform3d probePose = identity();
  probePose.translation() = point;
  const fcl::DistanceResultd result =
      runDistance(*target.geometry, identity(), probe, probePose, 1e-12, false);
  return {result.min_distance, result.nearest_points[0]};
}

/// The deepest vertex of `moving` inside `target`, searched from `seeds` and flooding through
/// vertices that are inside (a penetrating region is connected to a crossing triangle).
InsideVertex deepestVertexInside(const MeshData& moving, const fcl::Transform3d& movingToTarget,
                                 const BodyGeometry& target, const std::vector<int>& seeds) {
  InsideVertex deepest;
  std::vector<bool> queued(moving.mesh.vertices.size(), false);
  std::deque<int> queue;
  for (const int seed : seeds) {
    if (!queued[seed]) queue.push_back(seed);
    queued[seed] = true;
  }
  while (!queue.empty()) {
    const int index = queue.front();
    queue.pop_front();
    const fcl::Vector3d point = movingToTarget * moving.mesh.vertices[index].cast<double>();
    if (!isInside(*target.mesh, point)) continue;
    const auto [depth, surfacePoint] = distanceToSurface(target, point);
    if (!deepest.found || depth > deepest.depth) deepest = {depth, point, surfacePoint, true};
    for (const int neighbour : moving.neighbours[index]) {
      if (!queued[neighbour]) queue.push_back(neighbour);
      queued[neighbour] = true;
    }
  }
  return deepest;
}

std::vector<int> allVertices(const MeshData& mesh) {
  std::vector<int> indices(mesh.mesh.vertices.size());
  for (std::size_t i = 0; i < indices.size(); ++i) {
    indices[i] = static_cast<int>(i);
  }
  return indices;
}

/// Vertices of the triangles FCL finds intersecting, per mesh.
std::pair<std::vector<int>, std::vector<int>> crossingVertices(const PlacedBody& a,
                                                               const PlacedBody& b,
                                                               const fcl::Transform3d& bInA) {
  const fcl::CollisionResultd overlap =
      runCollide(*a.body.geometry, identity(), *b.body.geometry, bInA, false, kMaxMeshContacts);
  std::vector<int> seedsA, seedsB;
  for (std::size_t i = 0; i < overlap.numContacts(); ++i) {
    const fcl::Contactd& contact = overlap.getContact(i);
    const auto& triangleA = a.body.mesh->mesh.triangles[contact.b1];
    const auto& triangleB = b.body.mesh->mesh.triangles[contact.b2];
    seedsA.insert(seedsA.end(), triangleA.begin(), triangleA.end());
    seedsB.insert(seedsB.end(), triangleB.begin(), triangleB.end());
  }
  return {seedsA, seedsB};
}

/// FCL 0.7's triangle–triangle contact depths are far off for meshes (docs/fcl-oracle.md), so the
/// depth is the deepest vertex of either mesh inside the other: exact for vertex–face contact,
/// a lower bound when edges cross with no vertex inside (then 0).
PairDistance vertexDepthPair(const PlacedBody& a, const PlacedBody& b, const fcl::Transform3d& bInA,
                             const std::vector<int>& seedsA, const std::vector<int>& seedsB) {
  const fcl::Transform3d aInB = bInA.inverse(Eigen::Isometry);
  const InsideVertex aVertex = deepestVertexInside(*a.body.mesh, aInB, b.body, seedsA);
  const InsideVertex bVertex = deepestVertexInside(*b.body.mesh, bInA, a.body, seedsB);
  if (aVertex.found && (!bVertex.found || aVertex.depth >= bVertex.depth)) {
    return {-aVertex.depth, toVector(b.pose * aVertex.vertex),
            toVector(b.pose * aVertex.surfacePoint), DistanceMethod::MeshVertexDepth};
  }
  if (bVertex.found) {
    return {-bVertex.depth, toVector(a.pose * bVertex.surfacePoint),
            toVector(a.pose * bVertex.vertex), DistanceMethod::MeshVertexDepth};
  }
  // Surfaces cross with no vertex inside: a vertex of a crossing triangle stands for the contact.
  const Vector3 crossing =
      toVector(a.pose * a.body.mesh->mesh.vertices[seedsA.front()].cast<double>());
  return {0, crossing, crossing, DistanceMethod::MeshVertexDepth};
}

/// Surfaces that do not meet can still overlap: one mesh inside the other.
bool oneContainsTheOther(const PlacedBody& a, const PlacedBody& b, const fcl::Transform3d& bInA) {
  const MeshData& meshA = *a.body.mesh;
  const MeshData& meshB = *b.body.mesh;
  return isInside(meshB, bInA.inverse(Eigen::Isometry) * meshA.mesh.vertices[0].cast<double>()) ||
         isInside(meshA, bInA * meshB.mesh.vertices[0].cast<double>());
}

PairDistance meshMeshPair(const PlacedBody& a, const PlacedBody& b,
                          const DistanceOracleOptions& tolerances) {
  const fcl::Transform3d bInA = a.pose.inverse(Eigen::Isometry) * b.pose;
  auto [seedsA, seedsB] = crossingVertices(a, b, bInA);
  if (seedsA.empty()) {
    if (!oneContainsTheOther(a, b, bInA)) {
      const fcl::DistanceResultd separation =
          runDistance(*a.body.geometry, identity(), *b.body.geometry, bInA,
                      tolerances.distanceTolerance, false);
      return {separation.min_distance, toVector(a.pose * separation.nearest_points[0]),
              toVector(a.pose * separation.nearest_points[1]), DistanceMethod::MeshDistance};
    }
    seedsA = allVertices(*a.body.mesh);
    seedsB = allVertices(*b.body.mesh);
  }
  return vertexDepthPair(a, b, bInA, seedsA, seedsB);
}

}  // namespace

PairDistance pairDistance(const PlacedBody& a, const PlacedBody& b,
                          const DistanceOracleOptions& tolerances) {
  const OracleShape shapeA = a.body.shape, shapeB = b.body.shape;
  if (hasClosedForm(shapeA, shapeB)) return closedFormPair(a, b, tolerances);
  if (isConvexShape(shapeA) && isConvexShape(shapeB)) return gjkEpaPair(a, b, tolerances);
  if (shapeA == OracleShape::TriangleMesh && shapeB == OracleShape::TriangleMesh) {
    return meshMeshPair(a, b, tolerances);
  }
  if (shapeA == OracleShape::TriangleMesh) return meshConvexPair(a, b, tolerances, true);
  return meshConvexPair(b, a, tolerances, false);
}

}  // namespace pbdval::fcl_oracle
