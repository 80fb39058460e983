// The pbd method's `contactModel` parameter: it overrides the scene's Simulation.contactModel,
// is reported with the effective settings, and bad values are errors naming the parameter.
#include <gtest/gtest.h>

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
