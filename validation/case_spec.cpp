#include "validation/case_spec.h"

#include <cmath>
#include <nlohmann/json.hpp>
#include <stdexcept>

namespace pbdval {
namespace {

double positiveNumber(const nlohmann::json& block, const char* key, const std::string& where) {
  const nlohmann::json& v = block.at(key);
  if (!v.is_number() || !std::isfinite(v.get<double>()) || !(v.get<double>() > 0))
    throw std::invalid_argument(where + ": Validation." + key + ": expected a positive number, got " +
                                v.dump());
  return v.get<double>();
}

}  // namespace

CaseSpec parseCaseSpec(const pbd::Scene& scene) {
  CaseSpec spec;
  if (scene.validationJson.empty()) return spec;
  const nlohmann::json block = nlohmann::json::parse(scene.validationJson);
  if (!block.is_object())
    throw std::invalid_argument(scene.sourceFile + ": Validation: expected an object");
  if (block.contains("duration")) spec.duration = positiveNumber(block, "duration", scene.sourceFile);
  if (block.contains("sampleInterval"))
    spec.sampleInterval = positiveNumber(block, "sampleInterval", scene.sourceFile);
  if (block.contains("description") && block["description"].is_string())
    spec.description = block["description"].get<std::string>();
  return spec;
}

double defaultDuration(const pbd::Scene& scene, const CaseSpec& spec) {
  if (spec.duration) return *spec.duration;
  if (scene.viewer.pauseAt > 0) return double(scene.viewer.pauseAt);
  return 5.0;
}

}  // namespace pbdval
