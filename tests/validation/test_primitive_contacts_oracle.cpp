// The PBD library's closed-form contacts (pbd/collision/primitive_contacts.h) against the FCL
// oracle (validation/oracle): signed distance, normal and witness points of random
// configurations.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "pbd/collision/primitive_contacts.h"
#include "pbd/io/scene_loader.h"
#include "validation/measure/oracle/distance_oracle.h"

namespace pbdval {
namespace {

using pbd::CollisionObjectType;

/// A scene of two primitives without meshes (closed-form mass properties; the scene frame is
/// the shape's frame and its origin the centre of mass).
pbd::Scene twoBodies(int typeA, const Vector3& scaleA, int typeB, const Vector3& scaleB) {
  auto body = [](int id, int type, const Vector3& s) {
    return "{\"id\": " + std::to_string(id) + ", \"collisionObjectType\": " + std::to_string(type) +
           ", \"collisionObjectScale\": [" + std::to_string(s.x()) + ", " + std::to_string(s.y()) +
           ", " + std::to_string(s.z()) + "]}";
  };
  const std::string json =
      "{\"RigidBodies\": [" + body(0, typeA, scaleA) + ", " + body(1, typeB, scaleB) + "]}";
  return pbd::parseScene(json, "primitive_pair.json").scene;
}

struct Placement {
  Quaternion rotation;
  Vector3 origin;
};

Quaternion randomRotation(std::mt19937_64& random) {
  std::normal_distribution<double> n(0, 1);
  return Quaternion(n(random), n(random), n(random), n(random)).normalized();
}

pbd::PlacedPrimitive place(const pbd::Scene& scene, int body, const Placement& p) {
  const pbd::CollisionShape shape = pbd::makeCollisionShape(scene.rigidBodies[std::size_t(body)]);
  return pbd::placePrimitive(shape, p.rotation.toRotationMatrix(), p.origin);
}

PairDistance oracleDistance(const pbd::Scene& scene, const Placement& a, const Placement& b) {
  const DistanceOracle oracle(scene);
  return oracle.distance(0, stateFromSceneFrame(scene.rigidBodies[0], a.origin, a.rotation), 1,
                         stateFromSceneFrame(scene.rigidBodies[1], b.origin, b.rotation));
}

/// The deepest contact of a manifold (lowest separation).
const pbd::PrimitiveContact& deepest(const pbd::PrimitiveManifold& m) {
  int best = 0;
  for (int i = 1; i < m.count; ++i)
    if (m.contacts[std::size_t(i)].separation < m.contacts[std::size_t(best)].separation) best = i;
  return m.contacts[std::size_t(best)];
}

// A large maxSeparation: every configuration of the tests reports its contact.
constexpr double kReachEverything = 10;

// Sphere–sphere, sphere–box, sphere–cylinder (either order): one contact whose separation is
// the oracle's signed distance, and, when separated, whose points are the oracle's closest
// points and whose normal points from B's closest point to A's. Both sides are closed forms in
// double on values of order 1 m (FCL's sphereSphereDistance, sphereBoxDistance,
// sphereCylinderDistance, DistanceMethod::ClosedForm): they agree to round-off, a few 10⁻¹⁶ m
// per operation over some ten operations; 10⁻¹² m leaves room for the cylinder's hypot.
TEST(PrimitiveContactsOracle, SpherePairsMatchTheOraclesClosedFormsInDistanceNormalAndPoints) {
  constexpr double kRoundOff = 1e-12;
  std::mt19937_64 random(2026);
  std::uniform_real_distribution<double> size(0.05, 0.5), offset(-0.8, 0.8);
  struct PairType {
    int a, b;
  };
  int checked = 0, penetrating = 0;
  for (const PairType types :
       {PairType{1, 1}, PairType{1, 2}, PairType{2, 1}, PairType{1, 3}, PairType{3, 1}}) {
    for (int trial = 0; trial < 400; ++trial) {
      const Vector3 scaleA(size(random), size(random), size(random));
      const Vector3 scaleB(size(random), size(random), size(random));
      const pbd::Scene scene = twoBodies(types.a, scaleA, types.b, scaleB);
      const Placement a{randomRotation(random),
                        Vector3(offset(random), offset(random), offset(random))};
      const Placement b{randomRotation(random), Vector3::Zero()};
      pbd::PrimitiveManifold manifold;
      ASSERT_TRUE(pbd::primitiveContacts(place(scene, 0, a), place(scene, 1, b), kReachEverything,
                                         manifold));
      ASSERT_EQ(manifold.count, 1);
      const pbd::PrimitiveContact& c = manifold.contacts[0];
      const PairDistance exact = oracleDistance(scene, a, b);
      ASSERT_EQ(exact.method, DistanceMethod::ClosedForm);
      EXPECT_NEAR(c.separation, exact.distance, kRoundOff) << "types " << types.a << "-" << types.b;
      EXPECT_NEAR(c.normal.norm(), 1, kRoundOff);
      EXPECT_NEAR(c.normal.dot(c.pointOnA - c.pointOnB), c.separation, kRoundOff);
      ++checked;
      if (exact.distance < 0) {
        ++penetrating;
        continue;
      }
      EXPECT_LE((c.pointOnA - exact.pointOnA).norm(), kRoundOff * 10);
      EXPECT_LE((c.pointOnB - exact.pointOnB).norm(), kRoundOff * 10);
    }
  }
  EXPECT_EQ(checked, 2000);
  EXPECT_GT(penetrating, 100);  // both regimes are covered
  EXPECT_GT(checked - penetrating, 100);
}

// Box–box, random poses. Separated: the largest separating-axis gap is a lower bound of the
// distance, with equality when the closest features are two faces or two edges, so every
// contact's separation is ≤ the oracle's distance (GJK, within its 10⁻⁶ m: docs/fcl-oracle.md)
// and no contact is missed. Penetrating: the oracle's depth is its own separating-axis test
// over the same 15 axes (DistanceMethod::BoxBoxSat). Ours is a face axis unless an edge axis
// beats the faces by 10⁻² of the smallest half extent (box_contacts.cpp), so the face chosen
// is at most that much deeper than the oracle's axis, and every contact lies on the incident
// box, no deeper along n than its support corner: −(deepest separation) ≤ depth + 10⁻² b_min.
TEST(PrimitiveContactsOracle, BoxPairsNeverReportMoreGapOrMoreDepthThanTheOracleAllows) {
  constexpr double kGjk = 1e-6;        // FCL's GJK at distance_tolerance 1e-9 (fcl-oracle.md)
  constexpr double kRoundOff = 1e-12;  // both sides' separating-axis arithmetic in double
  std::mt19937_64 random(30);
  std::uniform_real_distribution<double> size(0.1, 0.8), offset(-0.7, 0.7);
  int separated = 0, penetrating = 0;
  for (int trial = 0; trial < 1500; ++trial) {
    const Vector3 sizeA(size(random), size(random), size(random));
    const Vector3 sizeB(size(random), size(random), size(random));
    const pbd::Scene scene = twoBodies(2, sizeA, 2, sizeB);
    const double faceBias = 1e-2 * std::min(sizeA.minCoeff(), sizeB.minCoeff()) / 2;
    const Placement a{randomRotation(random),
                      Vector3(offset(random), offset(random), offset(random))};
    const Placement b{randomRotation(random), Vector3::Zero()};
    pbd::PrimitiveManifold manifold;
    ASSERT_TRUE(
        pbd::primitiveContacts(place(scene, 0, a), place(scene, 1, b), kReachEverything, manifold));
    ASSERT_GE(manifold.count, 1);
    ASSERT_LE(manifold.count, 4);
    const PairDistance exact = oracleDistance(scene, a, b);
    const double ours = deepest(manifold).separation;
    if (exact.distance > 0) {
      ++separated;
      EXPECT_LE(ours, exact.distance + kGjk) << "trial " << trial;
    } else {
      ++penetrating;
      ASSERT_EQ(exact.method, DistanceMethod::BoxBoxSat);
      EXPECT_GE(ours, exact.distance - faceBias - kRoundOff) << "trial " << trial;
    }
    for (int i = 0; i < manifold.count; ++i) {
      const pbd::PrimitiveContact& c = manifold.contacts[std::size_t(i)];
      EXPECT_NEAR(c.normal.norm(), 1, kRoundOff);
      EXPECT_NEAR(c.normal.dot(c.pointOnA - c.pointOnB), c.separation, kRoundOff);
    }
  }
  EXPECT_GT(separated, 100);
  EXPECT_GT(penetrating, 100);
}

// Box B resting on box A's top face (the configurations of a stack or a pile): tilted by 1° to
// 15° (below 1° A's own face would compete with B's as the reference), its lowest corners over A's
// face. The deepest contact is then on the separating axis that gives the oracle's depth or
// distance: equal to it, with the normal along A's face normal (the oracle's witness points differ
// by the depth along it).
TEST(PrimitiveContactsOracle, StackedBoxesHaveTheOraclesDepthAndFaceNormal) {
  constexpr double kGjk = 1e-6;
  constexpr double kRoundOff = 1e-12;
  std::mt19937_64 random(31);
  std::uniform_real_distribution<double> unit(-1, 1), gap(-0.01, 0.01);
  const double pi = std::acos(-1.0);
  for (int trial = 0; trial < 500; ++trial) {
    const Vector3 lower(1.0, 0.2, 1.0), upper(0.3, 0.2, 0.25);  // full extents
    const pbd::Scene scene = twoBodies(2, upper, 2, lower);     // A: upper, B: lower
    const Vector3 axis = Vector3(unit(random), unit(random), unit(random)).normalized();
    const Quaternion tilt(Eigen::AngleAxisd((1 + 14 * std::abs(unit(random))) * pi / 180, axis));
    // Place the upper box's lowest corner `gap` above the lower box's top face (y = 0.1).
    const pbd::Matrix3 r = tilt.toRotationMatrix();
    const double lowest = (r.cwiseAbs() * (upper / 2)).y();
    const double clearance = gap(random);
    const Placement b{Quaternion::Identity(), Vector3::Zero()};
    const Placement a{tilt,
                      Vector3(0.2 * unit(random), 0.1 + lowest + clearance, 0.2 * unit(random))};
    pbd::PrimitiveManifold manifold;
    ASSERT_TRUE(
        pbd::primitiveContacts(place(scene, 0, a), place(scene, 1, b), kReachEverything, manifold));
    ASSERT_GE(manifold.count, 1);
    const PairDistance exact = oracleDistance(scene, a, b);
    const pbd::PrimitiveContact& c = deepest(manifold);
    EXPECT_NEAR(c.separation, clearance, kRoundOff) << "trial " << trial;
    EXPECT_NEAR(c.separation, exact.distance, exact.distance > 0 ? kGjk : kRoundOff);
    EXPECT_NEAR(c.normal.dot(Vector3::UnitY()), 1, kRoundOff);
  }
}

}  // namespace
}  // namespace pbdval
