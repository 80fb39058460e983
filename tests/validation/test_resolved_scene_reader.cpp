// The rigid part of a resolved scene read back (validation/external/resolved_scene_reader.h): for
// every case of the library, the MuJoCo adapter writes the same MJCF text from the scene read back
// as from the loaded scene (every number the writer prints, in the shortest form that reads back
// exactly, so equal text means bitwise equal inputs). That is what lets mujoco-python compile
// the built-in engine's model from the document it is given (docs/external-engines.md).
#include <gtest/gtest.h>

#include <filesystem>
#include <stdexcept>
#include <string>

#include "adapters/mujoco/kinematic_tree.h"
#include "adapters/mujoco/mjcf_writer.h"
#include "adapters/mujoco/mujoco_engine.h"
#include "adapters/mujoco/mujoco_settings.h"
#include "pbd/io/scene_loader.h"
#include "validation/external/resolved_scene.h"
#include "validation/external/resolved_scene_reader.h"

namespace pbdval {
namespace {

std::string mjcfOf(const pbd::Scene& scene) {
  mujoco::MujocoSettings settings;
  settings.stepSize = double(scene.simulation.timeStepSize);
  settings.contactTimeConstant = 4 * settings.stepSize;
  settings.equalitySolref = {2 * settings.stepSize, 1};
  settings.servoTimeConstant = 4 * settings.stepSize;
  return mujoco::writeMjcf(scene, settings, mujoco::planKinematicTree(scene)).xml;
}

TEST(ResolvedSceneReader, EveryCaseReadBackGivesTheMujocoAdapterTheSameModelText) {
  int written = 0;
  for (const auto& entry :
       std::filesystem::directory_iterator(std::string(PBDVAL_SOURCE_DIR) + "/cases")) {
    if (entry.path().extension() != ".json") continue;
    SCOPED_TRACE(entry.path().string());
    const pbd::Scene scene = pbd::loadScene(entry.path().string()).scene;
    const pbd::Scene readBack =
        rigidSceneFromResolvedJson(resolvedSceneJson(scene, "m", nlohmann::json::object(), {}));
    const std::vector<std::string> unsupported = mujoco::unsupportedRigidFeatures(scene);
    EXPECT_EQ(mujoco::unsupportedRigidFeatures(readBack), unsupported);
    if (!unsupported.empty()) continue;
    EXPECT_EQ(mjcfOf(readBack), mjcfOf(scene));
    ++written;
  }
  // Every rigid case but the four the writer refuses (hollow shapes, stiff rods, the particle
  // joint): at least the 45 of the library when this test was written.
  EXPECT_GE(written, 45);
}

TEST(ResolvedSceneReader, AMissingValueIsNamedByItsJsonPath) {
  const pbd::Scene scene =
      pbd::loadScene(std::string(PBDVAL_SOURCE_DIR) + "/cases/joint_hinge.json").scene;
  nlohmann::json document = resolvedSceneJson(scene, "m", nlohmann::json::object(), {});
  document["bodies"][1]["pose"].erase("rotation");
  try {
    rigidSceneFromResolvedJson(document);
    FAIL() << "accepted a body without a rotation";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("/bodies/1/pose/rotation"), std::string::npos) << e.what();
  }
  document = resolvedSceneJson(scene, "m", nlohmann::json::object(), {});
  document["joints"][0]["body1"] = 12345;
  EXPECT_THROW(rigidSceneFromResolvedJson(document), std::invalid_argument);
}

}  // namespace
}  // namespace pbdval
