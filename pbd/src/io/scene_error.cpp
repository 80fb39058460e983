#include "pbd/io/scene_loader.h"

namespace pbd {

std::string SceneDiagnostic::text() const {
  std::string result;
  if (!file.empty()) result += file + ": ";
  if (!jsonPath.empty()) result += jsonPath + ": ";
  return result + message;
}

SceneError::SceneError(SceneDiagnostic diagnostic)
    : std::runtime_error(diagnostic.text()), diagnostic_(std::move(diagnostic)) {}

}  // namespace pbd
