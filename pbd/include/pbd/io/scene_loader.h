// Loads the seed's scene JSON (PositionBasedDynamics 2.2.2 format, see docs/scene-format.md)
// into a Scene, with strict, located error messages.
//
// Errors (SceneError) name the file, the JSON path and what was expected:
//   scene.json: RigidBodies[3].collisionObjectScale: expected an array of 3 finite numbers, got
//   "abc"
// Warnings name unknown keys with their JSON path (the seed silently drops them); with
// LoadOptions::strict every warning becomes an error.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "pbd/model/scene.h"

namespace pbd {

/// A located problem in an input file.
struct SceneDiagnostic {
  std::string file;      ///< the scene (or mesh) file
  std::string jsonPath;  ///< "RigidBodies[3].collisionObjectScale"; empty for file-level issues
  std::string message;   ///< what was expected / what is wrong

  /// "file: path: message"
  std::string text() const;
};

class SceneError : public std::runtime_error {
 public:
  explicit SceneError(SceneDiagnostic diagnostic);
  const SceneDiagnostic& diagnostic() const { return diagnostic_; }

 private:
  SceneDiagnostic diagnostic_;
};

struct LoadOptions {
  bool strict = false;  ///< warnings (unknown keys, `gravity`) become errors
};

struct LoadedScene {
  Scene scene;
  std::vector<SceneDiagnostic> warnings;
};

/// Reads and validates a scene file. Relative file paths inside it are resolved against the
/// scene file's folder. Throws SceneError.
LoadedScene loadScene(const std::string& path, const LoadOptions& options = {});

/// Upper bounds of the Simulation block's solver counts (docs/scene-format.md).
inline constexpr int kMaxSubSteps = 10000;
inline constexpr int kMaxIterations = 10000;

/// The keys of the Simulation block.
std::vector<std::string> simulationSettingKeys();

/// Sets one key of the Simulation block from text with exactly the loader's checks (the same
/// key table, the same bounds), so `--set subSteps=10` and `"subSteps": 10` accept the same
/// values. The text is JSON ("10", "[0, -9.81, 0]"), a comma-separated list ("0,-9.81,0") or a
/// plain string ("corrected"). Throws SceneError "ORIGIN: Simulation.KEY: expected ..., got ...".
void applySimulationSetting(SimulationSettings& settings, const std::string& key,
                            const std::string& valueText, const std::string& origin);

/// Same, from JSON text; `sourcePath` is used for messages and to resolve relative paths.
LoadedScene parseScene(const std::string& jsonText, const std::string& sourcePath,
                       const LoadOptions& options = {});

}  // namespace pbd
