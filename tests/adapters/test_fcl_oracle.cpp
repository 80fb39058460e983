// The FCL distance oracle (validation/measure/oracle/distance_oracle.h) against closed forms:
// signed distances, penetration depths and witness points of primitive and mesh pairs, placement of
// bodies from their states, and the whole-state penetration query behind the validation metrics
// penetration_max / penetration_mean.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "common/scene_fixtures.h"
#include "pbd/io/mesh_loader.h"
#include "pbd/model/mass_properties.h"
#include "validation/measure/oracle/distance_oracle.h"
#include "validation/measure/oracle/mesh_geometry.h"

namespace pbdval::test {
namespace {

using pbd::AngleAxis;
using pbd::CollisionObjectType;
using pbd::RigidBodyDesc;
using pbd::Scene;
using pbd::TriangleMesh;
using pbd::test::boxBody;
using pbd::test::sphereBody;

// --- Tolerances, each from its source ------------------------------------------------------
/// FCL's closed-form sphere–sphere / sphere–box / sphere–cylinder routines and triangle
/// distances: exact up to the rounding of O(1) lengths (a few hundred ε).
constexpr double kClosedForm = 1e-12;
/// GJK (the oracle's distanceTolerance 1e-9) and EPA (epaTolerance 1e-6, the smallest FCL 0.7
/// survives): distance errors below 1e-6 m (measured ≤ 1.3e-6 at contact, docs/fcl-oracle.md).
constexpr double kGjk = 1e-6;
/// EPA on two polytopes ends on an exact facet of their Minkowski difference: rounding only
/// (measured ≤ 1.5e-15 over 13 605 random box–box overlaps, docs/fcl-oracle.md).
constexpr double kPolytope = 1e-9;
/// GJK/EPA witness points: only ≈ √1e-6 = 1e-3 (FCL's GJK signed-distance tests;
/// validation.md §1.5).
constexpr double kWitness = 1e-3;
/// FCL's libccd MPR contact depth of a mesh triangle against a primitive's face, along the face
/// normal: exact for these vertex–face contacts (measured ≤ 1e-15); margin for rounding.
constexpr double kMeshContact = 1e-9;

// --- Meshes built in code -----------------------------------------------------------------

/// An L-shaped prism (non-convex): the polygon (0,0) (2,0) (2,1) (1,1) (1,2) (0,2) in x–y,
/// extruded over z ∈ [0, 1]; closed and outward.
TriangleMesh lPrism() {
  const double polygon[6][2] = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
  TriangleMesh mesh;
  for (int level = 0; level < 2; ++level) {
    for (const auto& p : polygon)
      mesh.vertices.emplace_back(p[0], p[1], level);
  }
  const auto bottom = [](int i) { return i; };
  const auto top = [](int i) { return 6 + i; };
  for (const auto& fan : {std::array<int, 3>{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 5}}) {
    mesh.triangles.push_back({top(fan[0]), top(fan[1]), top(fan[2])});
    mesh.triangles.push_back({bottom(fan[0]), bottom(fan[2]), bottom(fan[1])});
  }
  for (int i = 0; i < 6; ++i) {
    const int next = (i + 1) % 6;
    mesh.triangles.push_back({bottom(i), bottom(next), top(next)});
    mesh.triangles.push_back({bottom(i), top(next), top(i)});
  }
  return mesh;
}

/// A torus around the y axis (the seed's convention); its vertex rings include the lowest and
/// highest circles y = ∓r when `minorSegments` is a multiple of 4.
TriangleMesh torus(double majorRadius, double minorRadius, int majorSegments, int minorSegments) {
  TriangleMesh mesh;
  for (int i = 0; i < majorSegments; ++i) {
    for (int j = 0; j < minorSegments; ++j) {
      const double u = 2 * M_PI * i / majorSegments, w = 2 * M_PI * j / minorSegments;
      const double radial = majorRadius + minorRadius * std::cos(w);
      mesh.vertices.emplace_back(radial * std::cos(u), minorRadius * std::sin(w),
                                 radial * std::sin(u));
    }
  }
  const auto index = [&](int i, int j) {
    return (i % majorSegments) * minorSegments + (j % minorSegments);
  };
  for (int i = 0; i < majorSegments; ++i) {
    for (int j = 0; j < minorSegments; ++j) {
      mesh.triangles.push_back({index(i, j), index(i + 1, j + 1), index(i + 1, j)});
      mesh.triangles.push_back({index(i, j), index(i, j + 1), index(i + 1, j + 1)});
    }
  }
  return mesh;
}

/// The corner tetrahedron (0,0,0) (1,0,0) (0,1,0) (0,0,1): centre of mass (¼, ¼, ¼).
TriangleMesh cornerTetrahedron() {
  TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  mesh.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return mesh;
}

/// cases/models/cube.obj scaled by `extents`, as the loader scales geometry files.
TriangleMesh cubeModel(const Vector3& extents) {
  TriangleMesh mesh = pbd::loadObj(std::string(PBDVAL_SOURCE_DIR) + "/cases/models/cube.obj");
  for (Vector3& v : mesh.vertices)
    v = v.cwiseProduct(extents);
  return mesh;
}

// --- Bodies and states --------------------------------------------------------------------

std::string jsonPath(int index) {
  return "RigidBodies[" + std::to_string(index) + "]";
}

RigidBodyDesc cylinderBody(int id, double radius, double height) {
  RigidBodyDesc b;
  b.id = id;
  b.jsonPath = jsonPath(id);
  b.collision.type = CollisionObjectType::Cylinder;
  b.collision.scale = Vector3(radius, height, 1);
  b.massProperties = pbd::toPrincipal(pbd::cylinderMoments(radius, height, 1));
  return b;
}

/// A body whose collision object is represented by its mesh (torus or SDF), with mass
/// properties integrated from the mesh as the loader does.
RigidBodyDesc meshBody(int id, CollisionObjectType type, const TriangleMesh& mesh,
                       const Vector3& collisionScale = Vector3::Ones()) {
  RigidBodyDesc b;
  b.id = id;
  b.jsonPath = jsonPath(id);
  b.geometryFile = "built in the test";
  b.mesh = std::make_shared<const TriangleMesh>(mesh);
  b.collision.type = type;
  b.collision.scale = collisionScale;
  b.massProperties = pbd::toPrincipal(pbd::integrateSolid(mesh, 1));
  return b;
}

RigidBodyDesc staticBox(int id, const Vector3& extents) {
  return boxBody(id, extents, Vector3::Zero(), 1, false);
}

/// The state of a body whose scene frame is at `origin` with `rotation`: by the BodyState
/// convention the centre of mass is at origin + rotation · centerOfMass.
BodyState place(const RigidBodyDesc& body, const Vector3& origin,
                const Quaternion& rotation = Quaternion::Identity()) {
  BodyState state;
  state.id = body.id;
  state.rotation = rotation;
  state.position = origin + rotation * body.massProperties.centerOfMass;
  return state;
}

Quaternion rotationAbout(const Vector3& axis, double angle) {
  return Quaternion(AngleAxis(angle, axis.normalized()));
}

Scene sceneOf(std::vector<RigidBodyDesc> bodies) {
  Scene scene;
  scene.rigidBodies = std::move(bodies);
  return scene;
}

/// Two-body scene: distance of body 0 at `stateA` and body 1 at `stateB`.
struct Pair {
  DistanceOracle oracle;
  explicit Pair(const RigidBodyDesc& a, const RigidBodyDesc& b) : oracle(sceneOf({a, b})) {}
  PairDistance operator()(const BodyState& a, const BodyState& b) const {
    return oracle.distance(0, a, 1, b);
  }
};

void expectNear(const Vector3& actual, const Vector3& expected, double tolerance) {
  EXPECT_LE((actual - expected).norm(), tolerance)
      << "actual " << actual.transpose() << ", expected " << expected.transpose();
}

/// Witness points must be |distance| apart whatever the method.
void expectConsistentWitnesses(const PairDistance& d, double tolerance) {
  EXPECT_NEAR((d.pointOnA - d.pointOnB).norm(), std::abs(d.distance), tolerance)
      << distanceMethodName(d.method);
}

// --- Sphere pairs (FCL's closed forms) ------------------------------------------------------

TEST(FclOracle, SphereSphereSeparatedTouchingAndPenetrating) {
  const RigidBodyDesc a = sphereBody(0, 0.5, Vector3::Zero());
  const RigidBodyDesc b = sphereBody(1, 0.3, Vector3::Zero());
  const Pair pair(a, b);
  const Vector3 c1(0.2, -0.1, 0.3);
  const Vector3 direction = Vector3(1, 0.1, -0.2).normalized();
  for (const double centreDistance : {1.0, 0.8, 0.7, 0.5}) {
    SCOPED_TRACE("centre distance " + std::to_string(centreDistance));
    const Vector3 c2 = c1 + centreDistance * direction;
    const PairDistance d = pair(place(a, c1), place(b, c2));
    EXPECT_EQ(d.method, DistanceMethod::ClosedForm);
    EXPECT_NEAR(d.distance, centreDistance - 0.8, kClosedForm);  // d − r1 − r2
    // Both witness points on the centre line: A's surface towards B, B's surface towards A.
    expectNear(d.pointOnA, c1 + 0.5 * direction, kClosedForm);
    expectNear(d.pointOnB, c2 - 0.3 * direction, kClosedForm);
  }
}

TEST(FclOracle, SphereBoxFaceEdgeAndCornerRegions) {
  const Vector3 halfExtents(1, 0.5, 0.3);
  const RigidBodyDesc box = boxBody(0, 2 * halfExtents, Vector3::Zero());
  const RigidBodyDesc sphere = sphereBody(1, 0.2, Vector3::Zero());
  const Pair pair(box, sphere);
  const Vector3 origin(0.4, 1.2, -0.7);
  const Quaternion rotation = rotationAbout(Vector3(1, 2, 3), 0.8);
  struct Case {
    const char* region;
    Vector3 centreOutsideBy;  ///< sphere centre − nearest box point, box frame
    Vector3 nearestOnBox;     ///< box frame
  };
  const Vector3 face(1, 0.1, -0.1), edge(1, 0.5, 0.1), corner(1, 0.5, 0.3);
  const std::vector<Case> cases = {
      {"face", {0.5, 0, 0}, face},         {"face, penetrating", {0.15, 0, 0}, face},
      {"edge", {0.3, 0.4, 0}, edge},       {"edge, penetrating", {0.06, 0.08, 0}, edge},
      {"corner", {0.2, 0.2, 0.1}, corner}, {"corner, penetrating", {0.1, 0.1, 0.05}, corner},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.region);
    const Vector3 centreLocal = c.nearestOnBox + c.centreOutsideBy;
    const PairDistance d =
        pair(place(box, origin, rotation), place(sphere, origin + rotation * centreLocal));
    EXPECT_EQ(d.method, DistanceMethod::ClosedForm);
    // Outside the box, the signed distance is |c − nearest point| − r, penetrating or not.
    EXPECT_NEAR(d.distance, c.centreOutsideBy.norm() - 0.2, kClosedForm);
    expectNear(d.pointOnA, origin + rotation * c.nearestOnBox, kClosedForm);
    expectConsistentWitnesses(d, kClosedForm);
  }
}

// --- Box pairs (GJK when separated; separating axes when overlapping)
// -----------------------------------------------------

TEST(FclOracle, BoxBoxFaceToFaceSeparatedAndPenetrating) {
  const RigidBodyDesc a = boxBody(0, Vector3(1, 1, 1), Vector3::Zero());
  const RigidBodyDesc b = boxBody(1, Vector3(0.5, 0.5, 0.5), Vector3::Zero());
  const Pair pair(a, b);
  // B turned about x keeps its half-extent 0.25 along x: the x-gap is the distance.
  const Quaternion turnB = rotationAbout(Vector3::UnitX(), 0.5);
  for (const double gap : {0.05, 1e-4, -1e-4, -0.02}) {
    SCOPED_TRACE("gap " + std::to_string(gap));
    const PairDistance d =
        pair(place(a, Vector3::Zero()), place(b, Vector3(0.5 + 0.25 + gap, 0.1, -0.2), turnB));
    // Separated: GJK; overlapping: the separating-axis depth (EPA aborts on flat box contacts).
    EXPECT_EQ(d.method, gap > 0 ? DistanceMethod::GjkEpa : DistanceMethod::BoxBoxSat);
    EXPECT_NEAR(d.distance, gap, gap > 0 ? kGjk : kPolytope);
    EXPECT_NEAR(d.pointOnA.x(), 0.5, kWitness);  // on A's face x = ½
    expectConsistentWitnesses(d, kGjk);
  }
}

// A box resting on a box with a tiny overlap is what engines produce every step; FCL 0.7's EPA
// aborted the process on exactly this (a failed assertion in libfcl). The separating-axis depth
// must answer it exactly: for a face-down box tilted by θ about x, the lowest edge sits
// h/2·cos θ + w/2·sin θ below the centre, so the overlap is that minus the centre's height.
TEST(FclOracle, BoxRestingOnBoxWithTinyOverlapsIsExactAndDoesNotAbort) {
  const RigidBodyDesc ground = boxBody(0, Vector3(4, 1, 4), Vector3::Zero());
  const RigidBodyDesc box = boxBody(1, Vector3(0.6, 0.4, 0.5), Vector3::Zero());
  const Pair pair(ground, box);
  for (const double tilt : {0.0, 1e-9, 1e-6, 1e-3})
    for (const double overlap : {1e-9, 1e-7, 1e-5, 1e-3}) {
      const double reach = 0.2 * std::cos(tilt) + 0.25 * std::sin(tilt);
      const PairDistance d =
          pair(place(ground, Vector3::Zero()), place(box, Vector3(0.1, 0.5 + reach - overlap, -0.2),
                                                     rotationAbout(Vector3::UnitX(), tilt)));
      EXPECT_EQ(d.method, DistanceMethod::BoxBoxSat) << tilt << " " << overlap;
      EXPECT_NEAR(d.distance, -overlap, kPolytope) << tilt << " " << overlap;
      EXPECT_NEAR(d.pointOnA.y(), 0.5, kWitness);  // on the ground's top face
    }
}

TEST(FclOracle, BoxBoxCrossedEdgesSeparatedAndPenetrating) {
  // A unit cube turned 45° about x has a top edge along x at height √½; one turned 45° about z
  // has a bottom edge along z at −√½. Stacked at centre distance √2 + gap the edges cross, and
  // every face axis overlaps by ≈ 0.35, so the signed distance is the gap along y.
  const RigidBodyDesc a = boxBody(0, Vector3::Ones(), Vector3::Zero());
  const RigidBodyDesc b = boxBody(1, Vector3::Ones(), Vector3::Zero());
  const Pair pair(a, b);
  const Quaternion turnA = rotationAbout(Vector3::UnitX(), M_PI / 4);
  const Quaternion turnB = rotationAbout(Vector3::UnitZ(), M_PI / 4);
  for (const double gap : {0.02, -0.01}) {
    SCOPED_TRACE("gap " + std::to_string(gap));
    const PairDistance d = pair(place(a, Vector3::Zero(), turnA),
                                place(b, Vector3(0, std::sqrt(2.0) + gap, 0), turnB));
    EXPECT_NEAR(d.distance, gap, gap > 0 ? kGjk : kPolytope);
    expectNear(d.pointOnA, Vector3(0, std::sqrt(0.5), 0), kWitness);
    expectNear(d.pointOnB, Vector3(0, std::sqrt(0.5) + gap, 0), kWitness);
  }
}

// --- Invariance under a common rigid motion, and symmetry ------------------------------------

TEST(FclOracle, DistancesAreInvariantUnderACommonRigidMotionAndSymmetric) {
  const RigidBodyDesc ground = boxBody(0, Vector3(4, 1, 4), Vector3::Zero());
  const RigidBodyDesc box = boxBody(1, Vector3(0.6, 0.4, 0.5), Vector3::Zero());
  const RigidBodyDesc cylinder = cylinderBody(2, 0.3, 0.9);
  const RigidBodyDesc sphere = sphereBody(3, 0.25, Vector3::Zero());
  const RigidBodyDesc ell = meshBody(4, CollisionObjectType::SignedDistanceField, lPrism());
  const std::vector<RigidBodyDesc> bodies = {ground, box, cylinder, sphere, ell};
  const DistanceOracle oracle(sceneOf(bodies));
  const Quaternion tilt = rotationAbout(Vector3(1, 0, 1), 0.3);
  const std::vector<BodyState> states = {
      place(ground, Vector3::Zero()),
      place(box, Vector3(0.2, 0.68, 0.1), tilt),      // a corner into the ground
      place(cylinder, Vector3(-1, 0.93, 0.3), tilt),  // the rim into the ground
      place(sphere, Vector3(1.3, 0.6, -0.8)),         // into the ground's face
      place(ell, Vector3(-0.5, 0.495, -1.5), tilt),   // an edge into the ground
  };
  const Quaternion motionRotation = rotationAbout(Vector3(-2, 1, 0.5), 2.1);
  const Vector3 motionTranslation(3, -7, 11);
  const auto moved = [&](int body) {
    const SceneFramePose pose = sceneFramePose(bodies[body], states[body]);
    return place(bodies[body], motionRotation * pose.origin + motionTranslation,
                 motionRotation * pose.rotation);
  };
  for (int body = 1; body < 5; ++body) {
    SCOPED_TRACE(oracle.description(body));
    const PairDistance before = oracle.distance(0, states[0], body, states[body]);
    const PairDistance after = oracle.distance(0, moved(0), body, moved(body));
    const PairDistance swapped = oracle.distance(body, states[body], 0, states[0]);
    EXPECT_LT(before.distance, 0);  // every configuration above penetrates
    EXPECT_NEAR(after.distance, before.distance, 2 * kGjk);
    EXPECT_NEAR(swapped.distance, before.distance, 2 * kGjk);
    // A mesh contact's point is one of several equally deep triangle contacts: not unique.
    if (!isExact(before.method, before.distance)) continue;
    expectNear(after.pointOnA, motionRotation * before.pointOnA + motionTranslation, kWitness);
    expectNear(after.pointOnB, motionRotation * before.pointOnB + motionTranslation, kWitness);
    expectNear(swapped.pointOnA, before.pointOnB, kWitness);
    expectNear(swapped.pointOnB, before.pointOnA, kWitness);
  }
}

// --- Cylinders: the seed's axis is y -------------------------------------------------------

TEST(FclOracle, CylinderAxisIsYSphereBesideVersusAbove) {
  // r = 0.5, h = 2: the cylinder spans |y| ≤ 1, radius 0.5 around y. Were its axis z, the
  // first two distances would be 0.7 and −0.4.
  const RigidBodyDesc cylinder = cylinderBody(0, 0.5, 2);
  const RigidBodyDesc sphere = sphereBody(1, 0.3, Vector3::Zero());
  const Pair pair(cylinder, sphere);
  struct Case {
    const char* where;
    Vector3 centre;
    double distance;
  };
  const std::vector<Case> cases = {
      {"above the top cap", {0, 1.5, 0}, 1.5 - 1 - 0.3},
      {"beside, along z", {0, 0, 0.9}, 0.9 - 0.5 - 0.3},
      {"beside, along x", {1.0, 0.2, 0}, 1.0 - 0.5 - 0.3},
      {"into the top cap", {0.1, 1.25, 0}, 0.25 - 0.3},
  };
  const Vector3 origin(2, -1, 0.5);
  for (const Case& c : cases) {
    SCOPED_TRACE(c.where);
    const PairDistance d = pair(place(cylinder, origin), place(sphere, origin + c.centre));
    EXPECT_EQ(d.method, DistanceMethod::ClosedForm);
    EXPECT_NEAR(d.distance, c.distance, kClosedForm);
    expectConsistentWitnesses(d, kClosedForm);
  }
}

TEST(FclOracle, CylinderStandingAndLyingOnABox) {
  const RigidBodyDesc ground = boxBody(0, Vector3(4, 1, 4), Vector3::Zero());  // top y = ½
  const RigidBodyDesc cylinder = cylinderBody(1, 0.4, 1);
  const Pair pair(ground, cylinder);
  const Quaternion lying = rotationAbout(Vector3::UnitZ(), M_PI / 2);  // axis along x
  for (const double gap : {0.01, 1e-3, -1e-3, -0.01}) {
    SCOPED_TRACE("gap " + std::to_string(gap));
    // Standing: the bottom cap (h/2 = 0.5 below the centre) at y = ½ + gap. Lying: the lowest
    // line (r = 0.4 below the centre) at y = ½ + gap.
    const PairDistance standing =
        pair(place(ground, Vector3::Zero()), place(cylinder, Vector3(0.3, 1 + gap, 0.1)));
    const PairDistance onItsSide =
        pair(place(ground, Vector3::Zero()), place(cylinder, Vector3(0.3, 0.9 + gap, 0.1), lying));
    EXPECT_EQ(standing.method, DistanceMethod::GjkEpa);
    EXPECT_NEAR(standing.distance, gap, kGjk);
    EXPECT_NEAR(onItsSide.distance, gap, kGjk);
    EXPECT_NEAR(onItsSide.pointOnB.y(), 0.5 + gap, kWitness);
  }
}

// --- Meshes -------------------------------------------------------------------------------

TEST(FclOracle, MeshCubeAgreesWithTheBoxPrimitive) {
  const Vector3 extents(0.6, 0.4, 1.0);
  const RigidBodyDesc meshCube =
      meshBody(0, CollisionObjectType::SignedDistanceField, cubeModel(extents));
  const RigidBodyDesc primitive = boxBody(1, extents, Vector3::Zero());
  const RigidBodyDesc probeBox = boxBody(2, Vector3(0.5, 0.5, 0.5), Vector3::Zero());
  const RigidBodyDesc probeSphere = sphereBody(3, 0.2, Vector3::Zero());
  const DistanceOracle oracle(sceneOf({meshCube, primitive, probeBox, probeSphere}));
  ASSERT_EQ(oracle.shape(0), OracleShape::ConvexMesh) << oracle.description(0);

  const Vector3 origin(1, 2, 3);
  const Quaternion rotation = rotationAbout(Vector3(0.3, 1, -0.2), 0.7);
  const Quaternion probeRotation = rotationAbout(Vector3(1, 1, 0), 0.4);
  for (const Vector3& offset : {Vector3(0.75, 0.1, 0), Vector3(0.5, 0.05, 0.1),
                                Vector3(0, 0.4, 0.2), Vector3(0.1, 0.1, 0.68)}) {
    SCOPED_TRACE("probe offset " + std::to_string(offset.x()) + ", " + std::to_string(offset.y()) +
                 ", " + std::to_string(offset.z()));
    const Vector3 probeOrigin = origin + rotation * offset;
    for (const int probe : {2, 3}) {
      const RigidBodyDesc& probeBody = probe == 2 ? probeBox : probeSphere;
      const BodyState probeState = place(probeBody, probeOrigin, probeRotation);
      const PairDistance fromMesh =
          oracle.distance(0, place(meshCube, origin, rotation), probe, probeState);
      const PairDistance fromBox =
          oracle.distance(1, place(primitive, origin, rotation), probe, probeState);
      EXPECT_NEAR(fromMesh.distance, fromBox.distance, kGjk) << oracle.description(probe);
    }
  }
}

TEST(FclOracle, MeshHelpersClassifyPointsAndConvexity) {
  const TriangleMesh cube = cubeModel(Vector3::Ones());
  // The winding number of a closed outward mesh is exactly 1 inside and 0 outside; the sum of
  // solid angles is exact up to rounding.
  EXPECT_NEAR(windingNumber(cube, Vector3(0.1, -0.2, 0.3)), 1, kClosedForm);
  EXPECT_NEAR(windingNumber(cube, Vector3(2, 0, 0)), 0, kClosedForm);
  EXPECT_NEAR(windingNumber(lPrism(), Vector3(1.5, 1.5, 0.5)), 0, kClosedForm);  // the notch
  EXPECT_NEAR(windingNumber(lPrism(), Vector3(0.5, 1.5, 0.5)), 1, kClosedForm);
  EXPECT_TRUE(isConvex(cube));
  EXPECT_TRUE(isConvex(cornerTetrahedron()));
  EXPECT_FALSE(isConvex(lPrism()));
  EXPECT_FALSE(isConvex(torus(1, 0.25, 48, 24)));
  // The test meshes are outward: positive volume (the L has area 3, height 1).
  EXPECT_NEAR(pbd::integrateSolid(lPrism(), 1).volume, 3, kClosedForm);
  EXPECT_GT(pbd::integrateSolid(torus(1, 0.25, 48, 24), 1).volume, 0);
}

TEST(FclOracle, TorusMeshOnABox) {
  // The 48 × 24 torus has vertex rings on its lowest circle y = −r: against a box face below,
  // the mesh's distance is the gap to that ring.
  const double majorRadius = 1, minorRadius = 0.25;
  const RigidBodyDesc ring =
      meshBody(0, CollisionObjectType::Torus, torus(majorRadius, minorRadius, 48, 24),
               Vector3(majorRadius, minorRadius, 1));
  const RigidBodyDesc ground = boxBody(1, Vector3(4, 1, 4), Vector3::Zero(), 1, false);
  const DistanceOracle oracle(sceneOf({ring, ground}));
  ASSERT_EQ(oracle.shape(0), OracleShape::TriangleMesh) << oracle.description(0);
  for (const double gap : {0.02, 1e-3, -1e-4, -1e-3, -0.01}) {
    SCOPED_TRACE("gap " + std::to_string(gap));
    const BodyState groundState = place(ground, Vector3(0.1, -minorRadius - 0.5 - gap, 0.05));
    const PairDistance d = oracle.distance(0, place(ring, Vector3::Zero()), 1, groundState);
    EXPECT_EQ(d.method, gap > 0 ? DistanceMethod::MeshDistance : DistanceMethod::MeshContact);
    EXPECT_NEAR(d.distance, gap, gap > 0 ? kGjk : kMeshContact);
    if (gap > 0) {
      EXPECT_NEAR(d.pointOnA.y(), -minorRadius, kWitness);
      expectConsistentWitnesses(d, kGjk);
    }
  }
  ASSERT_FALSE(oracle.notes().empty());
  EXPECT_NE(oracle.notes().front().find("torus (R = 1, r = 0.25) represented by its mesh"),
            std::string::npos)
      << oracle.notes().front();
}

TEST(FclOracle, TorusMeshAndSphereWitnessPointsAreInTheWorld) {
  // A sphere outside the outer equator at u = 0, where the mesh has the vertex (R + r, 0, 0).
  const RigidBodyDesc ring =
      meshBody(0, CollisionObjectType::Torus, torus(1, 0.25, 48, 24), Vector3(1, 0.25, 1));
  const RigidBodyDesc ball = sphereBody(1, 0.3, Vector3::Zero());
  const Pair pair(ring, ball);
  const Vector3 origin(5, -2, 1);
  const Quaternion rotation = rotationAbout(Vector3(0, 1, 1), 0.9);
  const Vector3 vertex = origin + rotation * Vector3(1.25, 0, 0);
  const Vector3 outward = rotation * Vector3::UnitX();
  for (const double gap : {0.05, -0.01}) {
    SCOPED_TRACE("gap " + std::to_string(gap));
    const Vector3 centre = vertex + (0.3 + gap) * outward;
    const PairDistance d = pair(place(ring, origin, rotation), place(ball, centre));
    EXPECT_EQ(d.method, gap > 0 ? DistanceMethod::MeshDistance : DistanceMethod::MeshContact);
    EXPECT_NEAR(d.distance, gap, gap > 0 ? kGjk : kMeshContact);
    if (gap > 0) {
      expectNear(d.pointOnA, vertex, kWitness);
      expectNear(d.pointOnB, centre - 0.3 * outward, kWitness);
    }
  }
}

TEST(FclOracle, NonConvexMeshesStackedByTheirVertices) {
  // Two L prisms, the upper shifted by (0.1, 0.1) and lowered into the lower by `overlap`: the
  // lower's top vertices lie `overlap` below the upper's bottom face and ≥ 0.1 from its sides,
  // so for overlap < 0.1 the penetration depth is the overlap.
  const RigidBodyDesc lower = meshBody(0, CollisionObjectType::SignedDistanceField, lPrism());
  const RigidBodyDesc upper = meshBody(1, CollisionObjectType::SignedDistanceField, lPrism());
  const Pair pair(lower, upper);
  ASSERT_EQ(pair.oracle.shape(0), OracleShape::TriangleMesh);
  const Vector3 origin(-1, 3, 2);
  const Quaternion rotation = rotationAbout(Vector3(2, -1, 1), 1.1);
  for (const double overlap : {-0.05, -1e-3, 1e-3, 0.01, 0.05}) {
    SCOPED_TRACE("overlap " + std::to_string(overlap));
    const PairDistance d =
        pair(place(lower, origin, rotation),
             place(upper, origin + rotation * Vector3(0.1, 0.1, 1 - overlap), rotation));
    EXPECT_EQ(d.method,
              overlap > 0 ? DistanceMethod::MeshVertexDepth : DistanceMethod::MeshDistance);
    EXPECT_NEAR(d.distance, -overlap, kClosedForm);
    expectConsistentWitnesses(d, kClosedForm);
  }
}

TEST(FclOracle, NonConvexMeshOnABox) {
  const RigidBodyDesc ell = meshBody(0, CollisionObjectType::SignedDistanceField, lPrism());
  const RigidBodyDesc ground = staticBox(1, Vector3(10, 10, 1));
  const Pair pair(ell, ground);
  for (const double gap : {0.01, -1e-3, -0.02}) {
    SCOPED_TRACE("gap " + std::to_string(gap));
    // The ground's top face at z = −gap, under the L's bottom face z = 0.
    const PairDistance d =
        pair(place(ell, Vector3::Zero()), place(ground, Vector3(1, 1, -gap - 0.5)));
    EXPECT_EQ(d.method, gap > 0 ? DistanceMethod::MeshDistance : DistanceMethod::MeshContact);
    EXPECT_NEAR(d.distance, gap, gap > 0 ? kGjk : kMeshContact);
  }
}

// --- Placement from BodyState ---------------------------------------------------------------

TEST(FclOracle, CentreOfMassOffsetFromTheSceneFrameIsPlacedRight) {
  // The tetrahedron's centre of mass is (¼, ¼, ¼) in its scene frame. A sphere half a unit
  // outside the middle of its face x = 0 is at distance 0.5 − r; placing the geometry at the
  // centre of mass instead would shift it by ¼ along the face normal.
  const RigidBodyDesc tetrahedron =
      meshBody(0, CollisionObjectType::SignedDistanceField, cornerTetrahedron());
  ASSERT_LE((tetrahedron.massProperties.centerOfMass - Vector3(0.25, 0.25, 0.25)).norm(), 1e-12);
  const RigidBodyDesc ball = sphereBody(1, 0.1, Vector3::Zero());
  const Pair pair(tetrahedron, ball);
  EXPECT_EQ(pair.oracle.shape(0), OracleShape::ConvexMesh);
  const Vector3 origin(2, 0, 0);
  const Quaternion rotation = rotationAbout(Vector3::UnitZ(), M_PI / 2);
  const Vector3 facePoint(0, 0.2, 0.2), faceNormal(-1, 0, 0);  // scene frame
  const Vector3 centre = origin + rotation * (facePoint + 0.5 * faceNormal);
  const PairDistance d = pair(place(tetrahedron, origin, rotation), place(ball, centre));
  EXPECT_NEAR(d.distance, 0.5 - 0.1, kGjk);
  expectNear(d.pointOnA, origin + rotation * facePoint, kWitness);
}

TEST(FclOracle, CentreOfMassSetByHandDoesNotMoveThePrimitive) {
  // A box whose mass properties put the centre of mass 0.3 along x: the box stays centred on
  // the scene-frame origin (the scene frame is where collision shapes live).
  RigidBodyDesc box = boxBody(0, Vector3::Ones(), Vector3::Zero());
  box.massProperties.centerOfMass = Vector3(0.3, 0, 0);
  const RigidBodyDesc ball = sphereBody(1, 0.2, Vector3::Zero());
  const Pair pair(box, ball);
  const Vector3 origin(-1, 4, 2);
  const PairDistance d = pair(place(box, origin), place(ball, origin + Vector3(0.5 + 0.25, 0, 0)));
  EXPECT_NEAR(d.distance, 0.25 - 0.2, kClosedForm);
  ASSERT_EQ(pair.oracle.notes().size(), 1u);
  EXPECT_NE(pair.oracle.notes()[0].find("RigidBodies[0]: the box is placed in the scene frame"),
            std::string::npos)
      << pair.oracle.notes()[0];
}

TEST(FclOracle, SceneFramePoseInvertsStateFromSceneFrame) {
  const RigidBodyDesc tetrahedron =
      meshBody(0, CollisionObjectType::SignedDistanceField, cornerTetrahedron());
  const Vector3 origin(1, -2, 3);
  const Quaternion rotation = rotationAbout(Vector3(1, 1, 1), 0.6);
  const BodyState state = stateFromSceneFrame(tetrahedron, origin, rotation);
  expectNear(state.position, place(tetrahedron, origin, rotation).position, kClosedForm);
  const SceneFramePose pose = sceneFramePose(tetrahedron, state);
  expectNear(pose.origin, origin, kClosedForm);
  EXPECT_LE(pose.rotation.angularDistance(rotation), kClosedForm);
}

// --- The whole-state query -------------------------------------------------------------------

/// Ground (static, top y = 0), a static wall overlapping it, spheres A, B, C (r = ½) and a
/// dynamic box D (0.4³): A sinks 1 mm into the ground, B hovers 10 mm above it, C sinks 2 mm
/// into A, D sinks 3 mm into the ground.
struct Pile {
  Scene scene = sceneOf({
      boxBody(0, Vector3(10, 1, 10), Vector3(0, -0.5, 0), 1, false),    // ground
      boxBody(1, Vector3(1, 2, 10), Vector3(5, 0.5, 0), 1, false),      // wall, into the ground
      sphereBody(2, 0.5, Vector3(0, 0.499, 0)),                         // A
      sphereBody(3, 0.5, Vector3(3, 0.51, 0)),                          // B
      sphereBody(4, 0.5, Vector3(0, 0.499 + 0.998, 0)),                 // C
      boxBody(5, Vector3(0.4, 0.4, 0.4), Vector3(-3, 0.2 - 0.003, 0)),  // D
  });
  State state;
  Pile() {
    for (const RigidBodyDesc& body : scene.rigidBodies) {
      state.bodies.push_back(place(body, body.translation, body.rotation));
    }
  }
};

void expectContact(const PairPenetration& contact, int bodyA, int bodyB, double depth,
                   double margin = 0) {
  EXPECT_EQ(contact.bodyA, bodyA);
  EXPECT_EQ(contact.bodyB, bodyB);
  EXPECT_NEAR(contact.depth, depth, kPolytope) << "pair " << bodyA << "–" << bodyB;
  EXPECT_EQ(contact.margin, margin);
}

TEST(FclOracle, PenetrationsOfASmallPile) {
  const Pile pile;
  const DistanceOracle oracle(pile.scene);
  const PenetrationReport report = oracle.penetrations(pile.state);
  ASSERT_EQ(report.contacts.size(), 3u);  // the static ground–wall overlap is skipped
  expectContact(report.contacts[0], 0, 2, 0.001);
  expectContact(report.contacts[1], 0, 5, 0.003);
  expectContact(report.contacts[2], 2, 4, 0.002);
  EXPECT_NEAR(report.maxDepth(), 0.003, kPolytope);
  EXPECT_NEAR(report.meanDepth(), 0.002, kPolytope);
  // δ(Σ d²) = Σ 2 d δd ≤ 2 · 0.006 · kPolytope.
  EXPECT_NEAR(report.sumSquaredDepth(), 1e-6 + 9e-6 + 4e-6, 0.012 * kPolytope);
  EXPECT_EQ(report.inexactContacts(), 0);
  EXPECT_TRUE(report.failures.empty());
  EXPECT_GE(report.pairsTested, 3);
}

TEST(FclOracle, MarginsAreSubtractedGloballyAndPerPair) {
  const Pile pile;
  const DistanceOracle oracle(pile.scene);
  PenetrationOptions options;
  options.margins.global = 0.0015;  // A's 1 mm into the ground is within the margin
  PenetrationReport report = oracle.penetrations(pile.state, options);
  ASSERT_EQ(report.contacts.size(), 2u);
  expectContact(report.contacts[0], 0, 5, 0.0015, 0.0015);
  expectContact(report.contacts[1], 2, 4, 0.0005, 0.0015);
  EXPECT_NEAR(report.maxDepth(), 0.0015, kPolytope);
  EXPECT_NEAR(report.meanDepth(), 0.001, kPolytope);

  options.margins.perPair[{2, 4}] = 0;
  report = oracle.penetrations(pile.state, options);
  ASSERT_EQ(report.contacts.size(), 2u);
  expectContact(report.contacts[1], 2, 4, 0.002, 0);
  EXPECT_NEAR(report.maxDepth(), 0.002, kPolytope);
}

TEST(FclOracle, ActiveDistanceCountsNearbyPairsAsContactsOfDepthZero) {
  const Pile pile;
  const DistanceOracle oracle(pile.scene);
  PenetrationOptions options;
  options.activeDistance = 0.02;  // B hovers 10 mm above the ground
  const PenetrationReport report = oracle.penetrations(pile.state, options);
  ASSERT_EQ(report.contacts.size(), 4u);
  expectContact(report.contacts[1], 0, 3, 0);
  EXPECT_NEAR(report.contacts[1].distance, 0.01, kClosedForm);
  EXPECT_NEAR(report.meanDepth(), (0.001 + 0.003 + 0.002) / 4, kPolytope);
}

TEST(FclOracle, JointedPairsAreSkippedUnlessAsked) {
  Scene scene = sceneOf({boxBody(0, Vector3::Ones(), Vector3::Zero()),
                         boxBody(1, Vector3::Ones(), Vector3(0.9, 0, 0))});
  scene.joints.push_back(pbd::test::makeJointDesc(pbd::JointType::Ball, 0, 1));
  State state;
  for (const RigidBodyDesc& body : scene.rigidBodies) {
    state.bodies.push_back(place(body, body.translation));
  }
  const DistanceOracle oracle(scene);
  EXPECT_TRUE(oracle.penetrations(state).contacts.empty());
  PenetrationOptions options;
  options.skipJointedPairs = false;
  const PenetrationReport report = oracle.penetrations(state, options);
  ASSERT_EQ(report.contacts.size(), 1u);
  expectContact(report.contacts[0], 0, 1, 0.1);
}

TEST(FclOracle, StateOfTheWrongSizeIsRejected) {
  const Pile pile;
  const DistanceOracle oracle(pile.scene);
  State state = pile.state;
  state.bodies.pop_back();
  EXPECT_THROW(oracle.penetrations(state), std::invalid_argument);
}

// --- Accuracy over random configurations, against closed forms ------------------------------

/// Random rotations (normalised Gaussian quaternions) and offsets.
struct RandomPoses {
  std::mt19937 engine{20261121};
  Quaternion rotation() {
    std::normal_distribution<double> gauss;
    return Quaternion(gauss(engine), gauss(engine), gauss(engine), gauss(engine)).normalized();
  }
  double uniform(double low, double high) {
    return std::uniform_real_distribution<double>(low, high)(engine);
  }
  double logUniform(double low, double high) {
    return std::exp(uniform(std::log(low), std::log(high)));
  }
  Vector3 offset(double size) {
    return Vector3(uniform(-size, size), uniform(-size, size), uniform(-size, size));
  }
};

/// The penetration depth of two boxes: the smallest overlap over the 15 separating axes (face
/// normals, edge–edge cross products). Exact for polytopes: the Minkowski difference's facet
/// normals are among these axes.
double separatingAxisDepth(const Vector3& halfA, const Quaternion& rotationA, const Vector3& halfB,
                           const Quaternion& rotationB, const Vector3& centreOffset) {
  const pbd::Matrix3 a = rotationA.toRotationMatrix(), b = rotationB.toRotationMatrix();
  std::vector<Vector3> axes;
  for (int i = 0; i < 3; ++i) {
    axes.push_back(a.col(i));
    axes.push_back(b.col(i));
    for (int j = 0; j < 3; ++j) {
      const Vector3 cross = a.col(i).cross(b.col(j));
      if (cross.norm() > 1e-9) axes.push_back(cross.normalized());
    }
  }
  double depth = std::numeric_limits<double>::infinity();
  for (const Vector3& axis : axes) {
    double reach = 0;
    for (int i = 0; i < 3; ++i) {
      reach += halfA[i] * std::abs(a.col(i).dot(axis)) + halfB[i] * std::abs(b.col(i).dot(axis));
    }
    depth = std::min(depth, reach - std::abs(centreOffset.dot(axis)));
  }
  return depth;
}

void reportAccuracy(const char* what, int samples, double maxError) {
  std::printf("[ measured ] %s: %d samples, max |error| %.3g m\n", what, samples, maxError);
  ::testing::Test::RecordProperty(what, std::to_string(maxError));
}

TEST(FclOracle, RandomBoxOverlapsMatchTheSeparatingAxisDepth) {
  const Vector3 extentsA(1, 0.6, 0.8), extentsB(0.7, 0.5, 0.9);
  const RigidBodyDesc a = boxBody(0, extentsA, Vector3::Zero());
  const RigidBodyDesc b = boxBody(1, extentsB, Vector3::Zero());
  const Pair pair(a, b);
  RandomPoses random;
  int samples = 0;
  double maxError = 0;
  while (samples < 1000) {
    const Quaternion rotationA = random.rotation(), rotationB = random.rotation();
    const Vector3 offset = random.offset(0.8);
    const double depth =
        separatingAxisDepth(extentsA / 2, rotationA, extentsB / 2, rotationB, offset);
    if (depth <= 1e-6 || depth > 0.05) continue;  // shallow overlaps, as in resting contact
    ++samples;
    const Vector3 origin = random.offset(5);
    const PairDistance d = pair(place(a, origin, rotationA), place(b, origin + offset, rotationB));
    maxError = std::max(maxError, std::abs(d.distance + depth));
  }
  reportAccuracy("box-box penetration vs separating axes", samples, maxError);
  EXPECT_LE(maxError, kPolytope);
}

TEST(FclOracle, RandomCrossedCylindersAndCylindersOnABox) {
  // Two lying cylinders crossing at an angle, one on top of the other: near the crossing they
  // are infinite cylinders (a line ⊕ a disc), whose penetration depth is r₁ + r₂ − the distance
  // between the axes. A lying cylinder on a box face sinks by the gap below its lowest line.
  const RigidBodyDesc lower = cylinderBody(0, 0.3, 2);
  const RigidBodyDesc upper = cylinderBody(1, 0.2, 1.5);
  const RigidBodyDesc ground = boxBody(2, Vector3(4, 1, 4), Vector3::Zero());
  const DistanceOracle oracle(sceneOf({lower, upper, ground}));
  RandomPoses random;
  const Quaternion axisAlongX = rotationAbout(Vector3::UnitZ(), M_PI / 2);
  double crossedError = 0, lyingError = 0;
  const int samples = 300;
  for (int i = 0; i < samples; ++i) {
    const double depth = random.logUniform(1e-6, 1e-2);
    const Quaternion motion = random.rotation();
    const Vector3 shift = random.offset(5);
    const auto moved = [&](const RigidBodyDesc& body, const Vector3& origin,
                           const Quaternion& rotation) {
      return place(body, motion * origin + shift, motion * rotation);
    };
    const double heading = random.uniform(0, 2 * M_PI);
    const double crossing = random.uniform(0.3, M_PI / 2);
    const Quaternion lowerTurn = rotationAbout(Vector3::UnitY(), heading) * axisAlongX;
    const Quaternion upperTurn = rotationAbout(Vector3::UnitY(), heading + crossing) * axisAlongX;
    const PairDistance crossed =
        oracle.distance(0, moved(lower, Vector3::Zero(), lowerTurn), 1,
                        moved(upper, Vector3(0, 0.5 - depth, 0), upperTurn));
    crossedError = std::max(crossedError, std::abs(crossed.distance + depth));
    const PairDistance lying =
        oracle.distance(2, moved(ground, Vector3::Zero(), Quaternion::Identity()), 0,
                        moved(lower, Vector3(0.2, 0.5 + 0.3 - depth, -0.1), lowerTurn));
    lyingError = std::max(lyingError, std::abs(lying.distance + depth));
  }
  reportAccuracy("crossed cylinders (EPA)", samples, crossedError);
  reportAccuracy("cylinder lying on a box (EPA)", samples, lyingError);
  EXPECT_LE(crossedError, kGjk);
  EXPECT_LE(lyingError, kGjk);
}

TEST(FclOracle, SphereNearAConvexMeshMatchesTheClosedForm) {
  // libccd's GJK reports overlaps of up to 7e-5 m between a sphere and a polytope as gaps; the
  // oracle decides overlap with MPR. Reference: FCL's closed-form sphere–box routine for the
  // box primitive the cube mesh stands for, near contact (within ±1 mm).
  const Vector3 extents(0.7, 0.4, 0.5);
  const RigidBodyDesc sphere = sphereBody(0, 0.4, Vector3::Zero());
  const RigidBodyDesc box = boxBody(1, extents, Vector3::Zero());
  const RigidBodyDesc cube =
      meshBody(2, CollisionObjectType::SignedDistanceField, cubeModel(extents));
  const DistanceOracle oracle(sceneOf({sphere, box, cube}));
  RandomPoses random;
  double maxError = 0;
  int beyondTolerance = 0;
  const int samples = 2000;
  for (int i = 0; i < samples; ++i) {
    const Quaternion rotation = random.rotation();
    const Vector3 direction = random.offset(1).normalized();
    const auto sphereAt = [&](double s) { return place(sphere, s * direction); };
    const BodyState boxState = place(box, Vector3::Zero(), rotation);
    double inside = 0, outside = 2;  // bisection on the closed form for the contact distance
    for (int step = 0; step < 50; ++step) {
      const double middle = (inside + outside) / 2;
      (oracle.distance(0, sphereAt(middle), 1, boxState).distance > 0 ? outside : inside) = middle;
    }
    const double offset = random.logUniform(1e-9, 1e-3) * (random.uniform(-1, 1) < 0 ? -1 : 1);
    const BodyState sphereState = sphereAt(outside + offset);
    const double reference = oracle.distance(0, sphereState, 1, boxState).distance;
    const double fromMesh =
        oracle.distance(0, sphereState, 2, place(cube, Vector3::Zero(), rotation)).distance;
    maxError = std::max(maxError, std::abs(fromMesh - reference));
    if (std::abs(fromMesh - reference) > kGjk) ++beyondTolerance;
  }
  reportAccuracy("sphere near a convex mesh", samples, maxError);
  std::printf("[ measured ] sphere near a convex mesh: %d samples beyond 1e-6 m\n",
              beyondTolerance);
  // Measured over 20 000 such samples: 99.965 % within 1e-6, the rest ≤ 8.7e-6 (EPA overestimates
  // a few near-touching depths where MPR's depth just exceeds the EPA tolerance). Deciding overlap
  // by GJK instead puts 0.64 % beyond 1e-6, up to 7.9e-5.
  EXPECT_LE(maxError, 1e-5);
  EXPECT_LE(beyondTolerance, samples / 500);
}

// --- What cannot be represented -------------------------------------------------------------

TEST(FclOracle, UnsupportedTypesAreReportedByBodyAndReason) {
  std::vector<RigidBodyDesc> bodies;
  const auto add = [&](CollisionObjectType type) {
    RigidBodyDesc b = sphereBody(static_cast<int>(bodies.size()), 0.5, Vector3::Zero());
    b.collision.type = type;
    bodies.push_back(b);
    return &bodies.back();
  };
  add(CollisionObjectType::HollowSphere);
  add(CollisionObjectType::HollowBox);
  add(CollisionObjectType::Box)->collision.invertSDF = true;
  add(CollisionObjectType::Torus);  // no mesh
  RigidBodyDesc* sdf = add(CollisionObjectType::SignedDistanceField);
  sdf->collision.fileName = "/models/bunny.csdf";
  sdf->mesh = std::make_shared<const TriangleMesh>(cubeModel(Vector3::Ones()));
  add(CollisionObjectType::None);
  add(CollisionObjectType::Sphere);
  add(CollisionObjectType::Sphere);

  const DistanceOracle oracle(sceneOf(bodies));
  const std::vector<std::string> reasons = {"hollow sphere", "hollow box", "invertSDF", "torus",
                                            "SDF read from /models/bunny.csdf"};
  ASSERT_EQ(oracle.unsupported().size(), reasons.size());
  for (std::size_t i = 0; i < reasons.size(); ++i) {
    const UnsupportedBody& u = oracle.unsupported()[i];
    EXPECT_EQ(u.body, static_cast<int>(i));
    EXPECT_EQ(u.jsonPath, jsonPath(static_cast<int>(i)));
    EXPECT_NE(u.message().find(reasons[i]), std::string::npos) << u.message();
    EXPECT_EQ(oracle.shape(u.body), OracleShape::Unsupported);
    EXPECT_FALSE(oracle.hasGeometry(u.body));
  }
  EXPECT_EQ(oracle.shape(5), OracleShape::None);
  EXPECT_TRUE(oracle.hasGeometry(6));

  // Everything sits at the origin: only the two supported spheres count.
  State state;
  for (const RigidBodyDesc& body : bodies)
    state.bodies.push_back(place(body, Vector3::Zero()));
  const PenetrationReport report = oracle.penetrations(state);
  ASSERT_EQ(report.contacts.size(), 1u);
  expectContact(report.contacts[0], 6, 7, 1.0);
  try {
    oracle.distance(1, state.bodies[1], 6, state.bodies[6]);
    ADD_FAILURE() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("RigidBodies[1] has no geometry"), std::string::npos)
        << error.what();
  }
}

}  // namespace
}  // namespace pbdval::test
