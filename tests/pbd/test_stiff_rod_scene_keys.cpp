// The seed's stiff-rods scene keys (CosseratJoints, TreeModels): what they become, the
// segment dimensions, the solver type, and located errors for bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "common/text_assertions.h"
#include "common/tolerances.h"
#include "pbd/io/scene_loader.h"
#include "pbd/io/scene_writer.h"
#include "pbd/model/world.h"

namespace pbd {
namespace {

const std::string kInline = std::string(PBDVAL_TEST_DATA_DIR) + "/scenes/inline.json";

LoadedScene parse(const std::string& json) {
  return parseScene(json, kInline, {});
}

std::string errorOf(const std::string& json) {
  try {
    parse(json);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "(no SceneError)";
}

using pbd::test::containsAll;

// Three cylinder segments along y (r = 1 cm, 0.2 m), the first static through staticSegments.
const std::string kSegments = R"("RigidBodies": [
  {"id": 1, "collisionObjectType": 3, "collisionObjectScale": [0.01, 0.2, 0.01], "translation": [0, 0.1, 0]},
  {"id": 2, "collisionObjectType": 3, "collisionObjectScale": [0.01, 0.2, 0.01], "translation": [0, 0.3, 0]},
  {"id": 3, "collisionObjectType": 2, "collisionObjectScale": [0.03, 0.4, 0.01], "translation": [0, 0.6, 0]}])";
const std::string kJoints = R"("CosseratJoints": [
  {"bodyID1": 1, "bodyID2": 2, "id": 10, "position": [0, 0.2, 0], "stiffnessModifier": [1, 2, 1]},
  {"bodyID1": 2, "bodyID2": 3, "id": 11, "position": [0, 0.4, 0]}])";

std::string scene(const std::string& tree, const std::string& joints = kJoints) {
  return "{" + kSegments + ", " + joints + ", \"TreeModels\": [" + tree + "]}";
}

const std::string kTree =
    R"({"id": 5, "rbIds": [1, 2, 3], "jIds": [10, 11], "staticSegments": [1],
        "youngsModulus": 2e9, "torsionModulus": 8e8})";

TEST(StiffRodSceneKeys, JointsTakeTheTreesMaterialAndTheSegmentsShape) {
  const LoadedScene loaded = parse(scene(kTree));
  const Scene& s = loaded.scene;
  EXPECT_TRUE(loaded.warnings.empty());
  ASSERT_EQ(s.joints.size(), 2u);
  ASSERT_EQ(s.stiffRodTrees.size(), 1u);
  const StiffRodTreeDesc& tree = s.stiffRodTrees[0];
  EXPECT_EQ(tree.solver, StiffRodSolver::Direct);  // the seed's default, 12
  EXPECT_EQ(tree.id, 5);
  EXPECT_EQ(tree.joints, (std::vector<int>{0, 1}));
  EXPECT_FALSE(s.rigidBodies[0].isDynamic);  // staticSegments
  EXPECT_TRUE(s.rigidBodies[1].isDynamic);
  const StiffRodJointParams& a = s.joints[0].stiffRod;
  EXPECT_EQ(s.joints[0].type, JointType::StiffRod);
  EXPECT_EQ(s.joints[0].jsonPath, "CosseratJoints[0]");
  EXPECT_EQ(a.id, 10);
  EXPECT_EQ(a.tree, 0);
  EXPECT_EQ(a.youngsModulus, Real(2e9));
  EXPECT_EQ(a.torsionModulus, Real(8e8));
  EXPECT_EQ(a.stiffnessModifier, Vector3(1, 2, 1));
  // Cylinders: radius 0.01, length 0.2 (exact in binary to a few ulps). Precision-aware: 1e-15
  // is ~5 ulps of 0.2 in double, kept as the same multiple of ε in float (the literals are
  // rounded to Real first, so both sides carry the same representation error).
  const Real fewUlps = test::roundOffBound(1e-15);
  EXPECT_NEAR(a.averageRadius, Real(0.01), fewUlps);
  EXPECT_NEAR(a.averageSegmentLength, Real(0.2), fewUlps);
  // Cylinder (2r = 0.02 wide) and box (0.03 × 0.01): r = (0.02 + 0.02 + 0.03 + 0.01)/8 = 0.01;
  // L = (0.2 + 0.4)/2 = 0.3.
  const StiffRodJointParams& b = s.joints[1].stiffRod;
  EXPECT_NEAR(b.averageRadius, Real(0.01), fewUlps);
  EXPECT_NEAR(b.averageSegmentLength, Real(0.3), fewUlps);
  EXPECT_EQ(b.stiffnessModifier, Vector3::Ones());
  // The world solves them with the tree solver.
  const World world = buildWorld(s);
  EXPECT_EQ(world.stiffRodTrees.size(), 1u);
  EXPECT_TRUE(world.joints.empty());
}

TEST(StiffRodSceneKeys, SolverTypeZeroIsIterative) {
  std::string tree = kTree;
  tree.insert(tree.size() - 1, R"(, "solverType": 0)");
  const Scene s = parse(scene(tree)).scene;
  EXPECT_EQ(s.stiffRodTrees[0].solver, StiffRodSolver::Iterative);
  const World world = buildWorld(s);
  EXPECT_TRUE(world.stiffRodTrees.empty());
  EXPECT_EQ(world.joints.size(), 2u);
}

TEST(StiffRodSceneKeys, WrittenSceneLoadsToTheSameRod) {
  const Scene s = parse(scene(kTree)).scene;
  const Scene again = parse(writeSceneJson(s)).scene;
  ASSERT_EQ(again.joints.size(), 2u);
  ASSERT_EQ(again.stiffRodTrees.size(), 1u);
  for (std::size_t j = 0; j < 2; ++j) {
    EXPECT_EQ(again.joints[j].stiffRod.id, s.joints[j].stiffRod.id);
    EXPECT_EQ(again.joints[j].stiffRod.averageRadius, s.joints[j].stiffRod.averageRadius);
    EXPECT_EQ(again.joints[j].stiffRod.stiffnessModifier, s.joints[j].stiffRod.stiffnessModifier);
  }
  EXPECT_EQ(again.stiffRodTrees[0].staticSegments, s.stiffRodTrees[0].staticSegments);
  EXPECT_EQ(again.stiffRodTrees[0].youngsModulus, s.stiffRodTrees[0].youngsModulus);
}

TEST(StiffRodSceneKeys, BadInputNamesThePathAndTheExpectation) {
  std::string tree = kTree;
  tree.insert(tree.size() - 1, R"(, "solverType": 3)");
  EXPECT_TRUE(
      containsAll(errorOf(scene(tree)), {"inline.json", "TreeModels[0].solverType", "12", "0"}));
  EXPECT_TRUE(
      containsAll(errorOf(scene(R"({"rbIds": [1, 2, 3], "jIds": [10, 11], "torsionModulus": 1})")),
                  {"TreeModels[0]", "missing required key \"youngsModulus\""}));
  EXPECT_TRUE(containsAll(
      errorOf(scene(
          R"({"rbIds": [1, 2, 3], "jIds": [10, 11], "youngsModulus": -1, "torsionModulus": 1})")),
      {"TreeModels[0].youngsModulus"}));
  EXPECT_TRUE(containsAll(
      errorOf(scene(
          R"({"rbIds": [1, 2, 3], "jIds": [10, 12], "youngsModulus": 1, "torsionModulus": 1})")),
      {"TreeModels[0].jIds[1]", "CosseratJoint"}));
  EXPECT_TRUE(containsAll(
      errorOf(
          scene(R"({"rbIds": [1, 2], "jIds": [10, 11], "youngsModulus": 1, "torsionModulus": 1})")),
      {"TreeModels[0].jIds[1]", "CosseratJoints[1]", "rbIds"}));
  EXPECT_TRUE(containsAll(
      errorOf(
          scene(R"({"rbIds": [1, 2, 3], "jIds": [10], "youngsModulus": 1, "torsionModulus": 1})")),
      {"CosseratJoints[1]", "no TreeModel"}));
  EXPECT_TRUE(containsAll(errorOf(scene(kTree + ", " + kTree)),
                          {"TreeModels[1].jIds[0]", "already in TreeModels[0]"}));
  EXPECT_TRUE(containsAll(
      errorOf(scene(
          R"({"rbIds": [1, 2, 3], "jIds": [10, 11], "staticSegments": [4], "youngsModulus": 1, "torsionModulus": 1})")),
      {"TreeModels[0].staticSegments[0]"}));
  EXPECT_TRUE(containsAll(
      errorOf(scene(
          R"({"rbIds": [1, 2, 3], "jIds": [10, 11], "translation": [1, 0, 0], "youngsModulus": 1, "torsionModulus": 1})")),
      {"TreeModels[0].translation", "not supported"}));
  EXPECT_TRUE(containsAll(
      errorOf(scene(
          kTree, R"("CosseratJoints": [{"bodyID1": 1, "bodyID2": 2, "position": [0, 0.2, 0]}])")),
      {"CosseratJoints[0]", "missing required key \"id\""}));
  EXPECT_TRUE(containsAll(
      errorOf(scene(
          kTree,
          R"("CosseratJoints": [{"bodyID1": 1, "bodyID2": 9, "id": 10, "position": [0, 0.2, 0]}])")),
      {"CosseratJoints[0].bodyID2", "rigid body"}));
  EXPECT_TRUE(containsAll(
      errorOf(scene(
          kTree,
          R"("CosseratJoints": [{"bodyID1": 1, "bodyID2": 2, "id": 10, "position": [0, 0.2, 0]},
                                                 {"bodyID1": 2, "bodyID2": 3, "id": 10, "position": [0, 0.4, 0]}])")),
      {"CosseratJoints[1].id", "also the id of CosseratJoints[0]"}));
  EXPECT_TRUE(containsAll(
      errorOf(scene(
          kTree,
          R"("CosseratJoints": [{"bodyID1": 1, "bodyID2": 2, "id": 10, "position": [0, 0.2, 0], "stiffnessModifier": [1, 0, 1]}])")),
      {"CosseratJoints[0].stiffnessModifier"}));
  // A sphere segment has no rod cross-section.
  EXPECT_TRUE(containsAll(
      errorOf(
          R"({"RigidBodies": [{"id": 1, "collisionObjectType": 1}, {"id": 2, "collisionObjectType": 1, "translation": [0, 2, 0]}],
                  "CosseratJoints": [{"bodyID1": 1, "bodyID2": 2, "id": 0, "position": [0, 1, 0]}],
                  "TreeModels": [{"rbIds": [1, 2], "jIds": [0], "youngsModulus": 1, "torsionModulus": 1}]})"),
      {"TreeModels[0].jIds[0]", "box (type 2) or cylinder (type 3)"}));
}

TEST(StiffRodSceneKeys, UnsupportedStiffRodBlocksAreNamed) {
  for (const std::string key : {"CompactTreeModels", "SkinningMeshes", "RodAnimators"}) {
    EXPECT_TRUE(containsAll(errorOf("{\"" + key + "\": [{\"id\": 1}]}"), {key, "not supported"}));
    const LoadedScene empty = parse("{\"" + key + "\": []}");
    ASSERT_EQ(empty.warnings.size(), 1u) << key;
    EXPECT_TRUE(containsAll(empty.warnings[0].text(), {key, "not supported"}));
  }
}

}  // namespace
}  // namespace pbd
