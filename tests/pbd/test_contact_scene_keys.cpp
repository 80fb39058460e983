// The scene keys of contacts and collision shapes: the `contactModel` extension, and clear
// errors (file, JSON path, expectation) for collision parameters that describe no shape.
#include <gtest/gtest.h>

#include <string>

#include "pbd/io/scene_loader.h"

namespace pbd {
namespace {

const std::string kDataDir = PBDVAL_TEST_DATA_DIR;
// Inline scenes resolve relative paths from tests/data/scenes.
const std::string kInline = kDataDir + "/scenes/inline.json";

std::string errorOf(const std::string& json) {
  try {
    parseScene(json, kInline);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "no error";
}

TEST(ContactSceneKeys, ContactModelIsReadAndChecked) {
  EXPECT_EQ(parseScene("{}", kInline).scene.simulation.contactModel, ContactModel::Seed);
  EXPECT_EQ(parseScene(R"({"Simulation": {"contactModel": "corrected"}})", kInline)
                .scene.simulation.contactModel,
            ContactModel::Corrected);
  EXPECT_EQ(errorOf(R"({"Simulation": {"contactModel": "exact"}})"),
            kInline +
                ": Simulation.contactModel: expected one of \"seed\", \"corrected\", got "
                "\"exact\"");
}

// Unset, the grid is the method's (the seed's for `pbd`, Catmull-Rom for XPBD); given, it wins.
TEST(ContactSceneKeys, DistanceGridIsReadCheckedAndDefaultsPerMethod) {
  SimulationSettings settings = parseScene("{}", kInline).scene.simulation;
  EXPECT_FALSE(settings.distanceGrid.has_value());
  EXPECT_EQ(distanceGridFor(settings), GridInterpolation::CubicLagrange);
  settings.stepMethod = StepMethod::Xpbd;
  EXPECT_EQ(distanceGridFor(settings), GridInterpolation::CatmullRom);
  settings =
      parseScene(R"({"Simulation": {"distanceGrid": "cubicLagrange"}})", kInline).scene.simulation;
  settings.stepMethod = StepMethod::Xpbd;
  EXPECT_EQ(distanceGridFor(settings), GridInterpolation::CubicLagrange);
  settings =
      parseScene(R"({"Simulation": {"distanceGrid": "catmullRom"}})", kInline).scene.simulation;
  EXPECT_EQ(distanceGridFor(settings), GridInterpolation::CatmullRom);
  EXPECT_EQ(errorOf(R"({"Simulation": {"distanceGrid": "trilinear"}})"),
            kInline +
                ": Simulation.distanceGrid: expected one of \"cubicLagrange\", \"catmullRom\", "
                "got \"trilinear\"");
}

TEST(ContactSceneKeys, SignedDistanceFieldWithoutMeshIsAnError) {
  EXPECT_EQ(errorOf(R"({"RigidBodies": [{"collisionObjectType": 5, "mass": 1,
                        "inertia": [1, 1, 1]}]})"),
            kInline +
                ": RigidBodies[0].collisionObjectType: collisionObjectType 5 (signed "
                "distance field) needs a mesh: give \"geometryFile\" or "
                "\"collisionObjectFileName\"");
}

TEST(ContactSceneKeys, ACsdfFileThatIsNoDiscregridGridIsAnError) {
  // placeholder.csdf is text: its would-be header has no valid resolution. The grid reader's
  // own errors are tested in test_discregrid_file.cpp.
  const std::string message =
      errorOf(R"({"RigidBodies": [{"geometryFile": "../meshes/tet_surface.obj",
      "collisionObjectType": 5, "collisionObjectFileName": "../meshes/placeholder.csdf"}]})");
  EXPECT_EQ(message.rfind(kInline + ": RigidBodies[0].collisionObjectFileName: ", 0), 0u)
      << message;
  EXPECT_NE(message.find("placeholder.csdf: Discregrid grid (.csdf): resolution 1852795251: "
                         "expected 1 to 512 cells per axis (at byte 52 of 86)"),
            std::string::npos)
      << message;
}

TEST(ContactSceneKeys, SignedDistanceFieldOfAnOpenMeshIsAnError) {
  const std::string message =
      errorOf(R"({"RigidBodies": [{"geometryFile": "../meshes/tet_surface.obj",
      "collisionObjectType": 5, "collisionObjectFileName": "../meshes/open_box.obj"}]})");
  EXPECT_NE(message.find("RigidBodies[0].collisionObjectFileName: the mesh must be closed"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("open_box.obj has an open surface"), std::string::npos) << message;
}

TEST(ContactSceneKeys, OversizedGridIsAnError) {
  // One axis beyond 512 cells: the key's range (checked for every collision type).
  EXPECT_EQ(
      errorOf(R"({"RigidBodies": [{"geometryFile": "../meshes/tet_surface.obj",
      "collisionObjectType": 5, "resolutionSDF": [1000, 10, 10]}]})"),
      kInline + ": RigidBodies[0].resolutionSDF[0]: expected an integer in [1, 512], got 1000");
  // Every axis within 512 but 300³ = 2.7e7 cells beyond 256³: the grid's total.
  EXPECT_EQ(errorOf(R"({"RigidBodies": [{"geometryFile": "../meshes/tet_surface.obj",
      "collisionObjectType": 5, "resolutionSDF": [300, 300, 300]}]})"),
            kInline +
                ": RigidBodies[0].resolutionSDF: expected at most 512 cells per axis and "
                "256^3 cells in total, got [300,300,300]");
}

TEST(ContactSceneKeys, SignedDistanceFieldMeshIsLoadedUnscaled) {
  const LoadedScene loaded =
      parseScene(R"({"RigidBodies": [{"geometryFile": "../meshes/tet_surface.obj",
      "scale": [2, 2, 2], "collisionObjectType": 5,
      "collisionObjectFileName": "../meshes/tet_surface.obj"}]})",
                 kInline);
  const RigidBodyDesc& body = loaded.scene.rigidBodies[0];
  ASSERT_TRUE(body.collision.mesh);
  ASSERT_TRUE(body.mesh);
  EXPECT_EQ(body.collision.mesh->vertices[1] * 2, body.mesh->vertices[1]);
}

}  // namespace
}  // namespace pbd
