#include "pbd/io/input_checks.h"
#include "pbd/io/scene_loader.h"

namespace pbd {
namespace {

/// File names, JSON keys and quoted tokens come from the input: a message must stay valid
/// UTF-8 (it is printed, and stored in results.json) whatever bytes they hold.
SceneDiagnostic printable(SceneDiagnostic diagnostic) {
  diagnostic.file = printableText(diagnostic.file);
  diagnostic.jsonPath = printableText(diagnostic.jsonPath);
  diagnostic.message = printableText(diagnostic.message);
  return diagnostic;
}

}  // namespace

std::string SceneDiagnostic::text() const {
  std::string result;
  if (!file.empty()) result += file + ": ";
  if (!jsonPath.empty()) result += jsonPath + ": ";
  return printableText(result + message);
}

SceneError::SceneError(SceneDiagnostic diagnostic)
    : std::runtime_error(printable(diagnostic).text()),
      diagnostic_(printable(std::move(diagnostic))) {}

}  // namespace pbd
