// Closed-form contacts of primitive pairs (collision/primitive_contacts.h) in configurations
// whose contacts are known by hand, and their selection (Simulation.contactGeometry). The
// random configurations against FCL are in tests/validation/test_primitive_contacts_oracle.cpp.
#include <gtest/gtest.h>

#include <cmath>

#include "common/scene_fixtures.h"
#include "pbd/collision/primitive_contacts.h"
#include "pbd/io/scene_loader.h"
#include "pbd/model/world.h"

namespace pbd {
namespace {

// Every value below is a sum or product of a few exactly representable numbers and round-off
// of one or two ulps of 1 m: 1e-12 m.
constexpr Real kRoundOff = Real(1e-12);

PlacedPrimitive primitive(CollisionObjectType type, const Vector3& size, const Vector3& center,
                          const Matrix3& rotation = Matrix3::Identity(), Real thickness = 0) {
  PlacedPrimitive p;
  p.type = type;
  p.size = size;
  p.center = center;
  p.rotation = rotation;
  p.thickness = thickness;
  return p;
}

TEST(PrimitiveContacts, SphereInAHollowBoxCornerTouchesThreeWalls) {
  // Cavity half extents 0.5 − 0.05 = 0.45; the sphere (r = 0.1) sits 0.005 deep in the floor
  // and the x+ wall and 0.02 from the z− wall, farther than 0.03 from the others.
  const PlacedPrimitive box =
      primitive(CollisionObjectType::HollowBox, Vector3::Constant(Real(0.5)), Vector3::Zero(),
                Matrix3::Identity(), Real(0.05));
  const PlacedPrimitive sphere =
      primitive(CollisionObjectType::Sphere, Vector3::Constant(0.1), Vector3(0.355, -0.355, -0.33));
  PrimitiveManifold m;
  ASSERT_TRUE(primitiveContacts(sphere, box, Real(0.03), m));
  ASSERT_EQ(m.count, 3);
  // Order: walls x+, x−, y+, y−, z+, z− (those in reach).
  EXPECT_NEAR(m.contacts[0].separation, -0.005, kRoundOff);
  EXPECT_TRUE(m.contacts[0].normal.isApprox(-Vector3::UnitX()));
  EXPECT_NEAR(m.contacts[1].separation, -0.005, kRoundOff);
  EXPECT_TRUE(m.contacts[1].normal.isApprox(Vector3::UnitY()));
  EXPECT_NEAR(m.contacts[2].separation, 0.02, kRoundOff);
  EXPECT_TRUE(m.contacts[2].normal.isApprox(Vector3::UnitZ()));
  EXPECT_NEAR(m.contacts[1].pointOnB.y(), -0.45, kRoundOff);  // on the floor
}

TEST(PrimitiveContacts, BoxRestingFlatOnABoxHasItsFourBottomCorners) {
  // A 0.2 m cube 0.001 m into a 4 × 1 × 4 slab whose top is y = 0.
  const PlacedPrimitive slab =
      primitive(CollisionObjectType::Box, Vector3(2, 0.5, 2), Vector3(0, -0.5, 0));
  const PlacedPrimitive cube =
      primitive(CollisionObjectType::Box, Vector3::Constant(Real(0.1)), Vector3(0.3, 0.099, -0.2));
  for (const bool cubeFirst : {true, false}) {
    PrimitiveManifold m;
    ASSERT_TRUE(cubeFirst ? primitiveContacts(cube, slab, Real(0.01), m)
                          : primitiveContacts(slab, cube, Real(0.01), m));
    ASSERT_EQ(m.count, 4);
    for (int i = 0; i < 4; ++i) {
      const PrimitiveContact& c = m.contacts[std::size_t(i)];
      EXPECT_NEAR(c.separation, -0.001, kRoundOff);
      const Vector3& onCube = cubeFirst ? c.pointOnA : c.pointOnB;
      EXPECT_NEAR(onCube.y(), -0.001, kRoundOff);
      EXPECT_NEAR(std::abs(onCube.x() - 0.3), 0.1, kRoundOff);  // a corner
      EXPECT_NEAR(std::abs(onCube.z() + 0.2), 0.1, kRoundOff);
      EXPECT_TRUE(c.normal.isApprox(cubeFirst ? Vector3::UnitY() : Vector3(-Vector3::UnitY())));
    }
    // The slab's face (the larger of two equally deep faces) carries the normal: the SDF side
    // either way, and the contacts are the cube's own corners.
    EXPECT_EQ(m.normalFixedInA, !cubeFirst);
  }
}

TEST(PrimitiveContacts, CrossedEdgesGiveOneContactOnTheirCommonPerpendicular) {
  // Two unit cubes turned 45° about z and about x: their edges cross, A's lowest edge (along
  // z, at y = −√2/2 from A's centre) over B's highest edge (along x, at y = +√2/2), 0.01 apart.
  const Real s = std::sqrt(Real(0.5));
  const Matrix3 aboutZ =
      Eigen::AngleAxis<Real>(std::atan(Real(1)), Vector3::UnitZ()).toRotationMatrix();
  const Matrix3 aboutX =
      Eigen::AngleAxis<Real>(std::atan(Real(1)), Vector3::UnitX()).toRotationMatrix();
  const PlacedPrimitive a = primitive(CollisionObjectType::Box, Vector3::Constant(Real(0.5)),
                                      Vector3(0, 2 * s + Real(0.01), 0), aboutZ);
  const PlacedPrimitive b =
      primitive(CollisionObjectType::Box, Vector3::Constant(Real(0.5)), Vector3::Zero(), aboutX);
  PrimitiveManifold m;
  ASSERT_TRUE(primitiveContacts(a, b, Real(0.05), m));
  ASSERT_EQ(m.count, 1);
  EXPECT_NEAR(m.contacts[0].separation, 0.01, kRoundOff);
  EXPECT_TRUE(m.contacts[0].normal.isApprox(Vector3::UnitY()));
  EXPECT_TRUE(m.contacts[0].pointOnB.isApprox(Vector3(0, s, 0)));
}

TEST(PrimitiveContacts, BoxInsideAHollowBoxPutsItsCornersOnTheFloor) {
  const PlacedPrimitive container =
      primitive(CollisionObjectType::HollowBox, Vector3::Constant(Real(0.5)), Vector3::Zero(),
                Matrix3::Identity(), Real(0.05));
  const PlacedPrimitive cube = primitive(CollisionObjectType::Box, Vector3::Constant(Real(0.1)),
                                         Vector3(0, -0.352, 0));  // 0.002 deep into the floor
  PrimitiveManifold m;
  ASSERT_TRUE(primitiveContacts(cube, container, Real(0.01), m));
  ASSERT_EQ(m.count, 4);
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(m.contacts[std::size_t(i)].separation, -0.002, kRoundOff);
    EXPECT_TRUE(m.contacts[std::size_t(i)].normal.isApprox(Vector3::UnitY()));
  }
}

TEST(PrimitiveContacts, PairsWithoutAClosedFormAreLeftToTheSamples) {
  const PlacedPrimitive cylinder =
      primitive(CollisionObjectType::Cylinder, Vector3(0.1, 0.2, 0), Vector3::Zero());
  const PlacedPrimitive box =
      primitive(CollisionObjectType::Box, Vector3::Constant(Real(0.1)), Vector3(0, 0.25, 0));
  PrimitiveManifold m;
  EXPECT_FALSE(primitiveContacts(cylinder, box, Real(0.1), m));
  EXPECT_EQ(m.count, 0);
  EXPECT_FALSE(hasPrimitiveContacts(CollisionObjectType::Cylinder, CollisionObjectType::Box));
  EXPECT_TRUE(hasPrimitiveContacts(CollisionObjectType::Cylinder, CollisionObjectType::Sphere));
  // A box overlapping a hollow box's wall from outside: no closed form here.
  const PlacedPrimitive container =
      primitive(CollisionObjectType::HollowBox, Vector3::Constant(Real(0.5)), Vector3::Zero(),
                Matrix3::Identity(), Real(0.05));
  const PlacedPrimitive outside =
      primitive(CollisionObjectType::Box, Vector3::Constant(Real(0.1)), Vector3(0, 0.6, 0));
  EXPECT_FALSE(primitiveContacts(outside, container, Real(0.1), m));
  // invertSDF: never.
  PlacedPrimitive inverted = box;
  inverted.inverted = true;
  EXPECT_FALSE(primitiveContacts(
      primitive(CollisionObjectType::Sphere, Vector3::Constant(0.1), Vector3::Zero()), inverted,
      Real(0.1), m));
}

// The selection: `pbd` keeps the seed's samples, `pbd.xpbd` takes the closed forms, unless the
// scene says (docs/contacts.md#primitive-contacts).
TEST(PrimitiveContacts, ContactGeometryIsTheMethodsOwnUnlessTheSceneGivesIt) {
  SimulationSettings settings;
  EXPECT_EQ(contactGeometryFor(settings), ContactGeometry::Samples);
  settings.contactGeometry = ContactGeometry::Primitives;
  EXPECT_EQ(contactGeometryFor(settings), ContactGeometry::Primitives);
  settings.contactGeometry.reset();
  settings.stepMethod = StepMethod::Xpbd;
  EXPECT_EQ(contactGeometryFor(settings), ContactGeometry::Primitives);
  settings.contactGeometry = ContactGeometry::Samples;
  EXPECT_EQ(contactGeometryFor(settings), ContactGeometry::Samples);
  settings.contactGeometry = ContactGeometry::Primitives;
  EXPECT_EQ(contactGeometryFor(settings), ContactGeometry::Primitives);
  const Scene scene =
      parseScene(R"({"Simulation": {"contactGeometry": "primitives"}})", "inline.json").scene;
  ASSERT_TRUE(scene.simulation.contactGeometry.has_value());
  EXPECT_EQ(*scene.simulation.contactGeometry, ContactGeometry::Primitives);
  try {
    parseScene(R"({"Simulation": {"contactGeometry": "exact"}})", "inline.json");
    FAIL() << "an unknown contactGeometry was accepted";
  } catch (const SceneError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("Simulation.contactGeometry"), std::string::npos) << message;
    EXPECT_NE(message.find("\"samples\", \"primitives\""), std::string::npos) << message;
  }
}

// In the detector: a sphere resting on a box reports one contact with primitives where the
// samples report the cap of its 642 points inside the tolerance shell; distance and shell point
// follow the samples' convention (separation − tolerance, shell point = surface + tolerance n).
TEST(PrimitiveContacts, DetectorReportsOneContactForASphereOnABox) {
  Scene scene;
  scene.rigidBodies.push_back(
      test::boxBody(0, Vector3(2, 1, 2), Vector3(0, Real(-0.5), 0), 1, false));
  scene.rigidBodies.push_back(test::sphereBody(1, Real(0.1), Vector3(0, Real(0.098), 0), 500));
  for (const ContactGeometry geometry : {ContactGeometry::Samples, ContactGeometry::Primitives}) {
    scene.simulation.contactGeometry = geometry;
    World world = buildWorld(scene);
    ContactGeometryBuffer found;
    world.collision.reserve(found);
    const Real tolerance = Real(0.01);
    world.collision.detect(world.bodies, tolerance, found);
    if (geometry == ContactGeometry::Samples) {
      EXPECT_GT(found.rigid.size(), 5u);
      continue;
    }
    ASSERT_EQ(found.rigid.size(), 1u);
    const ContactPointGeometry& c = found.rigid[0];
    EXPECT_EQ(c.vertexSide, 1);
    EXPECT_EQ(c.sdfBody, 0);
    EXPECT_NEAR(c.distance, Real(-0.002) - tolerance, kRoundOff);
    EXPECT_TRUE(c.normal.isApprox(Vector3::UnitY()));
    EXPECT_NEAR(c.vertexPoint.y(), -0.002, kRoundOff);
    EXPECT_NEAR(c.surfacePoint.y(), tolerance, kRoundOff);
  }
}

// Jointed bodies keep their samples. A link whose end lies inside the static box around its
// pivot (double_pendulum_boxes: a 0.5 × 0.05 × 0.05 m link, its end 2.5 cm deep in a 0.1 m box):
// as a free pair the clipped manifold pushes the whole overlap out along its separating axis,
// x (overlap 0.05 m against 0.075 m in y and z), along the link; jointed, the link's corners
// inside the box are pushed out of the box's nearest faces, y or z (2.5 cm away), not along x.
TEST(PrimitiveContacts, JointedPairsKeepTheirSamples) {
  Scene scene;
  scene.rigidBodies.push_back(
      test::boxBody(0, Vector3::Constant(Real(0.1)), Vector3::Zero(), 1, false));
  scene.rigidBodies.push_back(
      test::boxBody(1, Vector3(0.5, 0.05, 0.05), Vector3(Real(0.25), 0, 0), 1000));
  scene.simulation.contactGeometry = ContactGeometry::Primitives;
  for (const bool jointed : {false, true}) {
    if (jointed) {
      JointDesc hinge = test::makeJointDesc(JointType::Hinge, 0, 1);
      hinge.axis = Vector3::UnitZ();
      scene.joints.push_back(hinge);
    }
    World world = buildWorld(scene);
    ContactGeometryBuffer found;
    world.collision.reserve(found);
    world.collision.detect(world.bodies, Real(0.01), found);
    ASSERT_FALSE(found.rigid.empty()) << "jointed " << jointed;
    for (const ContactPointGeometry& c : found.rigid) {
      if (jointed)
        EXPECT_LT(std::abs(c.normal.x()), kRoundOff) << "a sample pushed along the link";
      else
        EXPECT_NEAR(std::abs(c.normal.x()), 1, kRoundOff) << "the manifold's axis is x";
    }
  }
}

}  // namespace
}  // namespace pbd
