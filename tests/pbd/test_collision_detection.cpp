// Collision detection: surface samples, the point hierarchy, sweep and prune, and the contacts
// found between bodies (counts, normals, depths, directions, skipped pairs).
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

#include "common/scene_fixtures.h"
#include "pbd/collision/broad_phase.h"
#include "pbd/collision/point_bvh.h"
#include "pbd/collision/surface_samples.h"
#include "pbd/io/mesh_loader.h"
#include "pbd/model/world.h"

namespace pbd {
namespace {

const std::string kModels = std::string(PBDVAL_SOURCE_DIR) + "/cases/models/";

// --- Surface samples ---------------------------------------------------------------------------

// A primitive without geometry collides like the same body with the model mesh: its samples
// are the model's vertices, scaled. The generator repeats scripts/make-models in double
// precision, so in the double build they agree bit for bit; in float, to the rounding of one
// conversion.
TEST(SurfaceSamples, PrimitivesUseTheModelVerticesScaled) {
  struct Case {
    RigidBodyDesc body;
    const char* model;
    Vector3 scale;
  };
  RigidBodyDesc cylinder = test::boxBody(2, Vector3::Ones(), Vector3::Zero());
  cylinder.collision.type = CollisionObjectType::Cylinder;
  cylinder.collision.scale = Vector3(Real(0.3), 2, 9);
  const Case cases[] = {
      {test::boxBody(0, Vector3(Real(0.2), Real(0.4), 3), Vector3::Zero()), "cube.obj",
       Vector3(Real(0.2), Real(0.4), 3)},
      {test::sphereBody(1, Real(0.1), Vector3::Zero()), "sphere.obj", Vector3::Constant(Real(0.1))},
      {cylinder, "cylinder.obj", Vector3(Real(0.3), 2, Real(0.3))},
  };
  for (const Case& c : cases) {
    const std::vector<Vector3> samples = surfaceSamples(c.body);
    const TriangleMesh mesh = loadObj(kModels + c.model);
    ASSERT_EQ(samples.size(), mesh.vertices.size()) << c.model;
    for (std::size_t i = 0; i < samples.size(); ++i)
      EXPECT_LE((samples[i] - mesh.vertices[i].cwiseProduct(c.scale)).norm(),
                4 * kEpsilon * c.scale.maxCoeff())
          << c.model << " vertex " << i;
  }
  // A body with a geometry file uses its mesh vertices.
  RigidBodyDesc meshBody = test::boxBody(3, Vector3::Ones(), Vector3::Zero());
  meshBody.mesh = std::make_shared<const TriangleMesh>(loadObj(kModels + "cylinder.obj"));
  EXPECT_EQ(surfaceSamples(meshBody), meshBody.mesh->vertices);
}

// --- Point hierarchy ----------------------------------------------------------------------------

void expectContainsItsPoints(const PointBvh& bvh, const std::vector<Vector3>& points) {
  const Real slack = 8 * kEpsilon * 10;  // round-off of centre and radius for |p| ≤ 10
  for (const PointBvh::Node& node : bvh.nodes())
    for (int i = node.firstPoint; i < node.firstPoint + node.pointCount; ++i)
      EXPECT_LE((points[std::size_t(bvh.order()[std::size_t(i)])] - node.center).norm(),
                node.radius + slack);
}

TEST(PointBvh, EveryPointIsInOneLeafAndInsideEverySphereAboveIt) {
  std::mt19937 random(11);
  std::uniform_real_distribution<double> coordinate(-10, 10);
  std::vector<Vector3> points(1000);
  for (Vector3& p : points)
    p = Vector3(Real(coordinate(random)), Real(coordinate(random)), Real(coordinate(random)));
  PointBvh bvh(points);
  std::vector<int> visits(points.size(), 0);
  bvh.traverse([](const PointBvh::Node&) { return true; },
               [&](int point) { ++visits[std::size_t(point)]; });
  EXPECT_TRUE(std::all_of(visits.begin(), visits.end(), [](int v) { return v == 1; }));
  for (const PointBvh::Node& node : bvh.nodes())
    if (node.child < 0) {
      EXPECT_LE(node.pointCount, 10);
    }
  expectContainsItsPoints(bvh, points);
  // Refit after the points moved: still contains them, same topology.
  for (Vector3& p : points)
    p = Real(0.5) * p + Vector3(Real(coordinate(random)) / 10, 0, 0);
  const std::size_t nodes = bvh.nodes().size();
  bvh.refit(points.data());
  EXPECT_EQ(bvh.nodes().size(), nodes);
  expectContainsItsPoints(bvh, points);
  // A query that descends only into spheres reaching a ball visits exactly its points.
  const Vector3 centre(1, 2, 3);
  const Real radius = 4;
  std::set<int> found;
  bvh.traverse(
      [&](const PointBvh::Node& n) { return (n.center - centre).norm() <= n.radius + radius; },
      [&](int point) {
        if ((points[std::size_t(point)] - centre).norm() <= radius) found.insert(point);
      });
  std::set<int> expected;
  for (std::size_t i = 0; i < points.size(); ++i)
    if ((points[i] - centre).norm() <= radius) expected.insert(int(i));
  EXPECT_EQ(found, expected);
}

// --- Broad phase --------------------------------------------------------------------------------

TEST(SweepAndPrune, FindsExactlyTheOverlappingPairsSortedEveryStep) {
  std::mt19937 random(5);
  std::uniform_real_distribution<double> position(0, 20), size(0.1, 2);
  const std::size_t n = 300;
  std::vector<Aabb> boxes(n);
  SweepAndPrune sap(n, n * (n - 1) / 2);
  for (int step = 0; step < 5; ++step) {
    for (std::size_t i = 0; i < n; ++i) {
      const Vector3 low(Real(position(random)), Real(position(random)), Real(position(random)));
      boxes[i].min = low;
      boxes[i].max = low + Vector3(Real(size(random)), Real(size(random)), Real(size(random)));
      boxes[i].active = i % 17 != 0;
    }
    EXPECT_EQ(sap.findPairs(boxes), 0u);
    std::vector<ObjectPair> expected;
    for (std::size_t a = 0; a < n; ++a)
      for (std::size_t b = a + 1; b < n; ++b)
        if (boxes[a].active && boxes[b].active && boxes[a].overlaps(boxes[b]))
          expected.emplace_back(int(a), int(b));
    EXPECT_EQ(sap.pairs(), expected) << "step " << step;
  }
  // Beyond the capacity, pairs are dropped and counted.
  SweepAndPrune small(n, 3);
  const std::size_t all = [&] {
    SweepAndPrune full(n, n * n);
    full.findPairs(boxes);
    return full.pairs().size();
  }();
  EXPECT_EQ(small.findPairs(boxes), all - 3);
  EXPECT_EQ(small.pairs().size(), 3u);
}

// --- Contacts
// -------------------------------------------------------------------------------------

Scene groundScene() {
  Scene s;
  s.rigidBodies.push_back(test::boxBody(0, Vector3(4, 1, 4), Vector3(0, Real(-0.5), 0), 1, false));
  return s;
}

ContactGeometryBuffer detect(const Scene& scene) {
  CollisionDetector detector(scene, CollisionShapeOptions{"", 0});
  const World world = buildWorld(scene, CollisionShapeOptions{"", 0});
  ContactGeometryBuffer out;
  detector.reserve(out);
  detector.detect(world.bodies, scene.simulation.contactTolerance, out);
  return out;
}

// A 0.2 m cube whose bottom is 4 mm above the ground: its 4 bottom corners are inside the
// 10 mm shell at depth d = 4 mm − 10 mm, normal +y, surface point on the shell above the
// ground. The ground's corners are far away: no contact the other way.
TEST(CollisionDetection, BoxAboveGroundTouchesWithItsFourBottomCorners) {
  Scene s = groundScene();
  s.rigidBodies.push_back(test::boxBody(1, Vector3::Constant(Real(0.2)),
                                        Vector3(Real(0.3), Real(0.104), Real(-0.2)), 100));
  const ContactGeometryBuffer contacts = detect(s);
  ASSERT_EQ(contacts.rigid.size(), 4u);
  for (const ContactPointGeometry& c : contacts.rigid) {
    EXPECT_EQ(c.vertexSide, 1);
    EXPECT_EQ(c.sdfBody, 0);
    EXPECT_NEAR(c.distance, Real(0.004 - 0.01), 16 * kEpsilon);
    EXPECT_LE((c.normal - Vector3::UnitY()).norm(), 16 * kEpsilon);
    EXPECT_NEAR(c.vertexPoint.y(), Real(0.004), 16 * kEpsilon);
    EXPECT_NEAR(c.surfacePoint.y(), Real(0.01), 16 * kEpsilon);  // on the tolerance shell
    EXPECT_NEAR((c.surfacePoint - c.vertexPoint).x(), 0, 16 * kEpsilon);
  }
  EXPECT_TRUE(contacts.particle.empty());
}

// Two equal dynamic boxes stacked: both directions give contacts (the upper box's bottom
// corners against the lower box, the lower box's top corners against the upper one), the
// normals opposite; contacts are grouped by (vertex body, SDF body) in that order.
TEST(CollisionDetection, BothDirectionsOfAPairInTheSeedsOrder) {
  Scene s = groundScene();
  s.rigidBodies.push_back(test::boxBody(1, Vector3::Constant(Real(0.2)), Vector3(0, 1, 0), 100));
  s.rigidBodies.push_back(
      test::boxBody(2, Vector3::Constant(Real(0.2)), Vector3(0, Real(1.205), 0), 100));
  const ContactGeometryBuffer contacts = detect(s);
  ASSERT_EQ(contacts.rigid.size(), 8u);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(contacts.rigid[i].vertexSide, 1);
    EXPECT_EQ(contacts.rigid[i].sdfBody, 2);
    EXPECT_LE((contacts.rigid[i].normal + Vector3::UnitY()).norm(), 16 * kEpsilon);
    EXPECT_EQ(contacts.rigid[4 + i].vertexSide, 2);
    EXPECT_EQ(contacts.rigid[4 + i].sdfBody, 1);
    EXPECT_LE((contacts.rigid[4 + i].normal - Vector3::UnitY()).norm(), 16 * kEpsilon);
  }
}

TEST(CollisionDetection, SkipsStaticPairsUntestedMeshesAndBodiesWithoutShape) {
  Scene s = groundScene();
  s.rigidBodies.push_back(test::boxBody(1, Vector3::Constant(1), Vector3::Zero(), 1, false));
  EXPECT_TRUE(detect(s).rigid.empty()) << "static-static";
  s.rigidBodies[1].isDynamic = true;
  s.rigidBodies[1].massProperties = toPrincipal(boxMoments(Vector3::Ones(), 1));
  EXPECT_FALSE(detect(s).rigid.empty());
  s.rigidBodies[1].collision.testMesh = false;  // its corners are not tested ...
  for (const ContactPointGeometry& c : detect(s).rigid) {
    EXPECT_EQ(c.vertexSide, 0);
  }
  s.rigidBodies[1].collision.type = CollisionObjectType::None;  // ... and now it has no shape
  EXPECT_TRUE(detect(s).rigid.empty());
}

// Deepest first within a direction: a tilted box's lowest corner comes first.
TEST(CollisionDetection, ContactsOfADirectionAreOrderedDeepestFirst) {
  Scene s = groundScene();
  const Quaternion tilt(AngleAxis(Real(0.05), Vector3(1, 0, 1).normalized()));
  s.rigidBodies.push_back(
      test::boxBody(1, Vector3::Constant(Real(0.2)), Vector3(0, Real(0.1), 0), 100, true, tilt));
  const ContactGeometryBuffer contacts = detect(s);
  ASSERT_GE(contacts.rigid.size(), 2u);
  for (std::size_t i = 1; i < contacts.rigid.size(); ++i)
    EXPECT_LE(contacts.rigid[i - 1].distance, contacts.rigid[i].distance);
}

// Particles of a triangle model are the vertex side against rigid bodies; a static particle
// against a static body is skipped.
TEST(CollisionDetection, ParticlesAgainstRigidBodies) {
  Scene s = groundScene();
  TriangleModelDesc cloth;
  cloth.mesh.vertices = {Vector3(0, Real(0.005), 0), Vector3(1, Real(0.002), 0),
                         Vector3(0, Real(0.5), 0)};
  cloth.mesh.triangles = {{0, 1, 2}};
  s.triangleModels.push_back(cloth);
  for (const Vector3& v : cloth.mesh.vertices)
    s.particles.push_back({v, Vector3::Zero(), 1});
  s.particles[1].mass = 0;  // static
  const ContactGeometryBuffer contacts = detect(s);
  ASSERT_EQ(contacts.particle.size(), 1u);
  EXPECT_EQ(contacts.particle[0].vertexSide, 0);
  EXPECT_EQ(contacts.particle[0].sdfBody, 0);
  EXPECT_NEAR(contacts.particle[0].distance, Real(0.005 - 0.01), 16 * kEpsilon);
}

// A body with a grid SDF (type 5, the icosphere mesh, radius 0.3) above the ground, and a
// small box resting on top of it: the icosphere's vertices hit the ground box, and the small
// box's corners hit the grid.
TEST(CollisionDetection, GridShapesCollideLikeAnalyticOnes) {
  Scene s = groundScene();
  RigidBodyDesc ball = test::sphereBody(1, Real(0.3), Vector3(0, Real(0.302), 0), 100);
  auto mesh = loadObj(kModels + "sphere.obj");
  for (Vector3& v : mesh.vertices)
    v *= Real(0.3);
  ball.mesh = std::make_shared<const TriangleMesh>(mesh);
  ball.scale = Vector3::Constant(Real(0.3));
  ball.collision.type = CollisionObjectType::SignedDistanceField;
  ball.collision.scale = Vector3::Constant(Real(0.3));
  ball.collision.resolutionSDF = Vector3i::Constant(20);
  s.rigidBodies.push_back(ball);
  // The box's bottom at y = 0.6: its corners are √(2 · 0.05² + 0.298²) − 0.3 = 6.3 mm from
  // the ball, inside the 10 mm shell.
  s.rigidBodies.push_back(
      test::boxBody(2, Vector3::Constant(Real(0.1)), Vector3(0, Real(0.65), 0), 100));
  const ContactGeometryBuffer contacts = detect(s);
  std::vector<const ContactPointGeometry*> ballOnGround, boxOnBall;
  for (const ContactPointGeometry& c : contacts.rigid) {
    if (c.vertexSide == 1 && c.sdfBody == 0) ballOnGround.push_back(&c);
    if (c.vertexSide == 2 && c.sdfBody == 1) boxOnBall.push_back(&c);
  }
  ASSERT_FALSE(ballOnGround.empty());
  // Deepest first: the bottom pole, 2 mm above the ground.
  EXPECT_LE((ballOnGround[0]->vertexPoint - Vector3(0, Real(0.002), 0)).norm(), 8 * kEpsilon);
  EXPECT_NEAR(ballOnGround[0]->distance, Real(0.002 - 0.01), 8 * kEpsilon);
  ASSERT_EQ(boxOnBall.size(), 4u);
  for (const ContactPointGeometry* c : boxOnBall) {
    // The mesh lies up to its sag (0.3 × 1.5e-3 = 4.5e-4 m) inside the sphere; the grid adds
    // ~1e-4 m.
    EXPECT_NEAR(c->distance, Real(0.00627 - 0.01), Real(1e-3));
    // The normal points from the ball's centre through the corner, to within the angle of the
    // icosphere's facets (~0.06 rad: cos > 0.99).
    const Vector3 radial = (c->vertexPoint - Vector3(0, Real(0.302), 0)).normalized();
    EXPECT_GT(c->normal.dot(radial), Real(0.99));
  }
}

}  // namespace
}  // namespace pbd
