// The feature tables (adapters/features.h): every engine's table covers every feature for
// every method, the lookup picks the entry the declaration means, and the generic function
// names each unsupported use by its JSON path and the table's reason.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "adapters/built_in_engines.h"
#include "adapters/features.h"
#include "common/scene_fixtures.h"

namespace pbdval {
namespace {

using pbd::JointType;
using pbd::Vector3;

std::vector<std::string> methodNames(const EngineEntry& entry) {
  std::vector<std::string> names;
  for (const MethodInfo& m : entry.methods)
    names.push_back(m.name);
  return names;
}

TEST(FeatureTables, EveryBuiltInEngineDeclaresEveryFeatureForEveryMethod) {
  const EngineRegistry engines = builtInEngines();
  for (const EngineEntry& entry : engines.entries()) {
    const std::vector<std::string> problems = checkFeatureTable(entry.features, methodNames(entry));
    EXPECT_TRUE(problems.empty()) << entry.name << ": " << problems.front();
    EXPECT_FALSE(entry.features.entries.empty()) << entry.name;
  }
}

TEST(FeatureTables, TheVocabularyHasUniqueKeysAndEveryJointTypeAndShape) {
  std::vector<std::string> keys;
  for (const FeatureInfo& f : sceneFeatures())
    keys.push_back(f.key);
  std::vector<std::string> sorted = keys;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(std::adjacent_find(sorted.begin(), sorted.end()), sorted.end());
  // One scene per joint type: each is seen as a feature of its own.
  std::vector<std::string> jointKeys;
  for (int t = 0; t < pbd::kJointTypeCount; ++t) {
    pbd::Scene s;
    s.rigidBodies = {pbd::test::sphereBody(0, 1, Vector3::Zero()),
                     pbd::test::sphereBody(1, 1, Vector3(3, 0, 0))};
    s.joints = {pbd::test::makeJointDesc(JointType(t), 0, 1)};
    for (const FeatureUse& use : sceneFeatureUses(s))
      if (use.key.rfind("joint.", 0) == 0) jointKeys.push_back(use.key);
  }
  std::sort(jointKeys.begin(), jointKeys.end());
  EXPECT_EQ(std::unique(jointKeys.begin(), jointKeys.end()) - jointKeys.begin(),
            pbd::kJointTypeCount);
  for (const std::string& k : jointKeys)
    EXPECT_NE(findFeature(k), nullptr) << k;
}

TEST(FeatureTables, AnEntryForTheMethodWinsThenTheMostSpecificKey) {
  FeatureTable table{{
      {"cloth", Support::Unsupported, "not with this solver", {"e.b"}},
      {"cloth", Support::Unsupported, "no cloth"},
      {"cloth.method.xpbdDistance", Support::Approximated, "springs"},
  }};
  EXPECT_EQ(table.resolve("cloth.method.xpbdDistance", "e.a")->text, "springs");
  EXPECT_EQ(table.resolve("cloth.method.fem", "e.a")->text, "no cloth");
  EXPECT_EQ(table.resolve("cloth.method.xpbdDistance", "e.b")->text, "not with this solver");
  EXPECT_EQ(table.resolve("joint.ball", "e.a"), nullptr);
  // "cloth" is a group of "cloth.method.fem", never of a key that merely starts with its text.
  FeatureTable prefix{{{"shape.sdf", Support::Native, ""}}};
  EXPECT_EQ(prefix.resolve("shape.sdfx", "e.a"), nullptr);
}

TEST(FeatureTables, ATableThatMissesAFeatureOrNamesAnUnknownOneIsRefused) {
  FeatureTable table{{
      {"shape", Support::Native, ""},
      {"joint.ballz", Support::Native, ""},
      {"joint.hinge", Support::Unsupported, ""},
      {"joint.hinge", Support::Native, "", {"e.c"}},
  }};
  const std::vector<std::string> problems = checkFeatureTable(table, {"e.a", "e.b"});
  auto mentions = [&](const std::string& text) {
    return std::any_of(problems.begin(), problems.end(),
                       [&](const std::string& p) { return p.find(text) != std::string::npos; });
  };
  EXPECT_TRUE(mentions("features[1].feature: \"joint.ballz\" is neither"));
  EXPECT_TRUE(mentions("features[2].text"));  // unsupported without a reason
  EXPECT_TRUE(mentions("features[3].methods: \"e.c\" is not a method"));
  EXPECT_TRUE(mentions("no entry covers \"joint.ball\""));
}

TEST(FeatureTables, EachUnsupportedUseIsNamedOnceByItsPathWithTheTablesReason) {
  FeatureTable table{{
      {"shape", Support::Native, ""},
      {"shape.hollowSphere", Support::Unsupported, "no hollow shapes"},
      {"joint", Support::Native, ""},
      {"joint.distance", Support::Unsupported, "no distance rows"},
      {"body", Support::Native, ""},
      {"contact", Support::Native, ""},
      {"particle", Support::Unsupported, "no particles"},
      {"cloth", Support::Unsupported, "no particles"},
      {"solid", Support::Unsupported, "no particles"},
      {"rod", Support::Unsupported, "no particles"},
      {"fluid", Support::Unsupported, "no particles"},
  }};
  ASSERT_TRUE(checkFeatureTable(table, {"e.a"}).empty());
  pbd::Scene s;
  s.rigidBodies = {pbd::test::sphereBody(0, 1, Vector3::Zero()),
                   pbd::test::sphereBody(1, 1, Vector3(3, 0, 0))};
  s.rigidBodies[1].collision.type = pbd::CollisionObjectType::HollowSphere;
  s.rigidBodies[1].jsonPath = "RigidBodies[1]";
  s.joints = {pbd::test::makeJointDesc(JointType::Distance, 0, 1)};
  s.joints[0].jsonPath = "DistanceJoints[0]";
  s.triangleModels.emplace_back();
  s.triangleModels.back().jsonPath = "TriangleModels[0]";
  const std::vector<std::string> missing = unsupportedFeatures(table, s, "e.a");
  ASSERT_EQ(missing.size(), 3u);
  EXPECT_EQ(missing[0], "RigidBodies[1]: hollow sphere (collisionObjectType 6): no hollow shapes");
  EXPECT_EQ(missing[1], "DistanceJoints[0]: distance joint (DistanceJoints): no distance rows");
  // The cloth uses a method and a bending feature, both decided by "cloth": reported once.
  EXPECT_EQ(missing[2].rfind("TriangleModels[0]: cloth", 0), 0u) << missing[2];
  EXPECT_NE(missing[2].find(": no particles"), std::string::npos) << missing[2];
}

}  // namespace
}  // namespace pbdval
