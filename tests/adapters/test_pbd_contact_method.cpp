// The pbd engine's methods: the pbd method's `contactModel` parameter (it overrides the scene's
// Simulation.contactModel) and pbd.xpbd's parameters; both are reported with the effective
// settings, and bad values are errors naming the parameter.
#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "adapters/pbd/pbd_engine.h"
#include "common/scene_fixtures.h"

namespace pbdval::test {
namespace {

TEST(PbdContactMethod, ContactModelParameterOverridesTheScene) {
  pbd::Scene scene;
  scene.simulation.contactModel = pbd::ContactModel::Corrected;
  EXPECT_EQ(pbdSettingsFor(scene, resolveMethod("pbd", {})).contactModel,
            pbd::ContactModel::Corrected);  // default "scene": the scene's value
  EXPECT_EQ(pbdSettingsFor(scene, resolveMethod("pbd", {{"contactModel", "seed"}})).contactModel,
            pbd::ContactModel::Seed);
  scene.simulation.contactModel = pbd::ContactModel::Seed;
  EXPECT_EQ(
      pbdSettingsFor(scene, resolveMethod("pbd", {{"contactModel", "corrected"}})).contactModel,
      pbd::ContactModel::Corrected);
  try {
    pbdSettingsFor(scene, resolveMethod("pbd", {{"contactModel", "exact"}}));
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()),
              "method pbd: contactModel must be 'seed', 'corrected' or 'scene', got 'exact'");
  }
}

TEST(PbdContactMethod, EffectiveSettingsNameTheContactModelAndRule) {
  pbd::Scene scene;
  scene.rigidBodies.push_back(pbd::test::boxBody(0, Vector3::Ones(), Vector3::Zero(), 1, false));
  PbdEngine engine;
  engine.load(scene, resolveMethod("pbd", {{"contactModel", "corrected"}}));
  const auto settings = engine.effectiveSettings();
  EXPECT_EQ(settings.at("contactModel"), "corrected");
  EXPECT_EQ(settings.at("contactCombineRule"), "seed");
}

}  // namespace
}  // namespace pbdval::test

namespace pbdval::test {
namespace {

// pbd.xpbd: its parameters land in settings.xpbd with the step method, the defaults are the
// library's, and bad values are errors naming the parameter.
TEST(PbdXpbdMethod, ParametersSelectTheXpbdStep) {
  pbd::Scene scene;
  const pbd::SimulationSettings seed = pbdSettingsFor(scene, resolveMethod("pbd", {}));
  EXPECT_EQ(seed.stepMethod, pbd::StepMethod::Seed);
  const pbd::SimulationSettings defaults = pbdSettingsFor(scene, resolveMethod("pbd.xpbd", {}));
  EXPECT_EQ(defaults.stepMethod, pbd::StepMethod::Xpbd);
  EXPECT_EQ(defaults.xpbd.substeps, pbd::XpbdSettings{}.substeps);
  EXPECT_EQ(defaults.xpbd.speculativeMargin, pbd::XpbdSettings{}.speculativeMargin);
  const pbd::SimulationSettings set = pbdSettingsFor(
      scene, resolveMethod("pbd.xpbd", {{"substeps", "7"}, {"contactCompliance", "1e-6"}}));
  EXPECT_EQ(set.xpbd.substeps, 7);
  EXPECT_DOUBLE_EQ(double(set.xpbd.contactCompliance), 1e-6);
  for (const auto& [name, value] :
       std::vector<std::pair<std::string, std::string>>{{"substeps", "0"},
                                                        {"substeps", "2.5"},
                                                        {"jointLinearCompliance", "-1"}}) {
    try {
      pbdSettingsFor(scene, resolveMethod("pbd.xpbd", {{name, value}}));
      ADD_FAILURE() << name << " = " << value << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("method pbd.xpbd: " + name), std::string::npos)
          << e.what();
    }
  }
}

TEST(PbdXpbdMethod, EffectiveSettingsNameTheStepAndItsSubsteps) {
  pbd::Scene scene;
  scene.rigidBodies.push_back(pbd::test::boxBody(0, Vector3::Ones(), Vector3::Zero(), 1, false));
  PbdEngine engine;
  engine.load(scene, resolveMethod("pbd.xpbd", {{"substeps", "12"}}));
  const auto settings = engine.effectiveSettings();
  EXPECT_EQ(settings.at("stepMethod"), "xpbd");
  EXPECT_EQ(settings.at("subSteps"), "12");  // the substeps taken: the runner's integration step
}

}  // namespace
}  // namespace pbdval::test
