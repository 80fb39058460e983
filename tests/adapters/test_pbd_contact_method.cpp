// The pbd method's solver settings are the scene's Simulation settings, with one route and one
// set of bounds: `--set contactModel=corrected` goes through the scene loader's own key table,
// is reported with the effective settings, and a bad value is an error naming the setting and
// what it accepts.
#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "adapters/pbd/pbd_engine.h"
#include "common/scene_fixtures.h"
#include "engines/selftest_engine.h"
#include "pbd/io/scene_loader.h"
#include "validation/run/overrides.h"

namespace pbdval::test {
namespace {

TEST(PbdContactMethod, ContactModelIsASceneSettingSetWithSet) {
  pbd::Scene scene;
  scene.simulation.contactModel = pbd::ContactModel::Corrected;
  const MethodInfo& pbdMethod = testRegistry().method("pbd");
  EXPECT_TRUE(applyAssignments({}, pbdMethod, scene).empty());
  EXPECT_EQ(scene.simulation.contactModel, pbd::ContactModel::Corrected);
  EXPECT_TRUE(applyAssignments({"contactModel=seed"}, pbdMethod, scene).empty());
  EXPECT_EQ(scene.simulation.contactModel, pbd::ContactModel::Seed);
  try {
    applyAssignments({"contactModel=exact"}, pbdMethod, scene);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()),
              "--set contactModel=exact: Simulation.contactModel: expected one of \"seed\", "
              "\"corrected\", got \"exact\"");
  }
}

TEST(PbdContactMethod, SetAcceptsExactlyWhatTheSceneFileAccepts) {
  // One declaration: the loader's bounds [1, kMaxSubSteps] hold for --set as for the file.
  pbd::Scene scene;
  const MethodInfo& pbdMethod = testRegistry().method("pbd");
  EXPECT_THROW(applyAssignments({"subSteps=0"}, pbdMethod, scene), std::invalid_argument);
  EXPECT_THROW(applyAssignments({"subSteps=1000000000"}, pbdMethod, scene), std::invalid_argument);
  EXPECT_THROW(pbd::parseScene(R"({"Simulation": {"subSteps": 1000000000}})", "s.json"),
               pbd::SceneError);
  applyAssignments({"subSteps=" + std::to_string(pbd::kMaxSubSteps)}, pbdMethod, scene);
  EXPECT_EQ(scene.simulation.subSteps, pbd::kMaxSubSteps);
  applyAssignments({"gravitation=0,-1.5,0"}, pbdMethod, scene);
  EXPECT_EQ(scene.simulation.gravitation, pbd::Vector3(0, -1.5, 0));
  EXPECT_THROW(applyAssignments({"noSuchKey=1"}, pbdMethod, scene), std::invalid_argument);
}

TEST(PbdContactMethod, EffectiveSettingsNameTheContactModelAndRule) {
  pbd::Scene scene;
  scene.simulation.contactModel = pbd::ContactModel::Corrected;
  scene.rigidBodies.push_back(pbd::test::boxBody(0, Vector3::Ones(), Vector3::Zero(), 1, false));
  PbdEngine engine;
  engine.load(scene, testRegistry().resolve("pbd"));
  const auto settings = engine.effectiveSettings();
  EXPECT_EQ(settings.at("contactModel"), "corrected");
  EXPECT_EQ(settings.at("contactCombineRule"), "seed");
  EXPECT_EQ(engine.runFacts().integratorStepsPerSceneStep, scene.simulation.subSteps);
}

}  // namespace
}  // namespace pbdval::test

namespace pbdval::test {
namespace {

// pbd.xpbd: its typed parameters land in settings.xpbd with the step method, the defaults are
// the library's, and bad values are errors naming the parameter and its range.
TEST(PbdXpbdMethod, ParametersSelectTheXpbdStep) {
  pbd::Scene scene;
  const pbd::SimulationSettings seed = pbdSettingsFor(scene, testRegistry().resolve("pbd"));
  EXPECT_EQ(seed.stepMethod, pbd::StepMethod::Seed);
  const pbd::SimulationSettings defaults =
      pbdSettingsFor(scene, testRegistry().resolve("pbd.xpbd"));
  EXPECT_EQ(defaults.stepMethod, pbd::StepMethod::Xpbd);
  EXPECT_EQ(defaults.xpbd.substeps, pbd::XpbdSettings{}.substeps);
  EXPECT_EQ(defaults.xpbd.speculativeMargin, pbd::XpbdSettings{}.speculativeMargin);
  const pbd::SimulationSettings set = pbdSettingsFor(
      scene,
      testRegistry().resolve("pbd.xpbd", {{"substeps", "7"}, {"contactCompliance", "1e-6"}}));
  EXPECT_EQ(set.xpbd.substeps, 7);
  EXPECT_DOUBLE_EQ(double(set.xpbd.contactCompliance), 1e-6);
  for (const auto& [name, value] : std::vector<std::pair<std::string, std::string>>{
           {"substeps", "0"}, {"substeps", "2.5"}, {"jointLinearCompliance", "-1"}}) {
    try {
      testRegistry().resolve("pbd.xpbd", {{name, value}});
      ADD_FAILURE() << name << " = " << value << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("method pbd.xpbd: " + name), std::string::npos)
          << e.what();
    }
  }
}

TEST(PbdXpbdMethod, RunFactsAndSettingsNameTheStepAndItsSubsteps) {
  pbd::Scene scene;
  scene.rigidBodies.push_back(pbd::test::boxBody(0, Vector3::Ones(), Vector3::Zero(), 1, false));
  PbdEngine engine;
  engine.load(scene, testRegistry().resolve("pbd.xpbd", {{"substeps", "12"}}));
  const auto settings = engine.effectiveSettings();
  EXPECT_EQ(settings.at("stepMethod"), "xpbd");
  EXPECT_EQ(settings.at("xpbd.substeps"), "12");
  // The substeps taken: the analytic references' integration step is h / 12.
  EXPECT_EQ(engine.runFacts().integratorStepsPerSceneStep, 12);
}

TEST(PbdXpbdMethod, JointDirectionsReachTheStepAndTheRecordedSettings) {
  pbd::Scene scene;
  EXPECT_EQ(pbdSettingsFor(scene, testRegistry().resolve("pbd.xpbd")).xpbd.jointDirections,
            pbd::XpbdSettings{}.jointDirections);
  for (const auto& [text, directions] : std::vector<std::pair<std::string, pbd::JointDirections>>{
           {"start", pbd::JointDirections::Start},
           {"predicted", pbd::JointDirections::Predicted}}) {
    const Method method = testRegistry().resolve("pbd.xpbd", {{"jointDirections", text}});
    EXPECT_EQ(pbdSettingsFor(scene, method).xpbd.jointDirections, directions) << text;
    scene.rigidBodies.assign(1, pbd::test::boxBody(0, Vector3::Ones(), Vector3::Zero(), 1, false));
    PbdEngine engine;
    engine.load(scene, method);
    EXPECT_EQ(engine.effectiveSettings().at("xpbd.jointDirections"), text);
  }
  try {
    testRegistry().resolve("pbd.xpbd", {{"jointDirections", "sideways"}});
    ADD_FAILURE() << "jointDirections = sideways accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("method pbd.xpbd: jointDirections"), std::string::npos)
        << e.what();
  }
}

TEST(PbdXpbdMethod, JointIterationsReachTheStepAndTheRecordedSettings) {
  pbd::Scene scene;
  EXPECT_EQ(pbdSettingsFor(scene, testRegistry().resolve("pbd.xpbd")).xpbd.jointIterations,
            pbd::XpbdSettings{}.jointIterations);
  const Method method = testRegistry().resolve("pbd.xpbd", {{"jointIterations", "3"}});
  EXPECT_EQ(pbdSettingsFor(scene, method).xpbd.jointIterations, 3);
  scene.rigidBodies.assign(1, pbd::test::boxBody(0, Vector3::Ones(), Vector3::Zero(), 1, false));
  PbdEngine engine;
  engine.load(scene, method);
  EXPECT_EQ(engine.effectiveSettings().at("xpbd.jointIterations"), "3");
  try {
    testRegistry().resolve("pbd.xpbd", {{"jointIterations", "0"}});
    ADD_FAILURE() << "jointIterations = 0 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("method pbd.xpbd: jointIterations"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace pbdval::test
