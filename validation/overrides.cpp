#include "validation/overrides.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

namespace pbdval {
namespace {

double parseNumber(const std::string& key, const std::string& value) {
  char* end = nullptr;
  const double v = std::strtod(value.c_str(), &end);
  if (value.empty() || end != value.c_str() + value.size() || !std::isfinite(v))
    throw std::invalid_argument(key + ": expected a finite number, got '" + value + "'");
  return v;
}

int parseInteger(const std::string& key, const std::string& value, int minimum) {
  const double v = parseNumber(key, value);
  if (v != std::floor(v) || v < minimum || v > 1e9)
    throw std::invalid_argument(key + ": expected an integer ≥ " + std::to_string(minimum) +
                                ", got '" + value + "'");
  return static_cast<int>(v);
}

}  // namespace

const std::vector<std::string>& sceneOverrideKeys() {
  static const std::vector<std::string> keys = {"timeStepSize",
                                                "subSteps",
                                                "maxIterations",
                                                "maxIterationsV",
                                                "velocityUpdateMethod",
                                                "gravitation",
                                                "contactTolerance",
                                                "contactStiffnessRigidBody",
                                                "contactStiffnessParticleRigidBody"};
  return keys;
}

void applySceneOverride(pbd::Scene& scene, const std::string& key, const std::string& value) {
  pbd::SimulationSettings& s = scene.simulation;
  if (key == "timeStepSize") {
    const double h = parseNumber(key, value);
    if (!(h > 0)) throw std::invalid_argument("timeStepSize: must be > 0, got '" + value + "'");
    s.timeStepSize = pbd::Real(h);
  } else if (key == "subSteps") {
    s.subSteps = parseInteger(key, value, 1);
  } else if (key == "maxIterations") {
    s.maxIterations = parseInteger(key, value, 1);
  } else if (key == "maxIterationsV") {
    s.maxIterationsV = parseInteger(key, value, 0);
  } else if (key == "velocityUpdateMethod") {
    s.velocityUpdateMethod = parseInteger(key, value, 0);
    if (s.velocityUpdateMethod > 1)
      throw std::invalid_argument("velocityUpdateMethod: must be 0 or 1, got '" + value + "'");
  } else if (key == "gravitation") {
    std::stringstream in(value);
    std::string part;
    std::vector<double> parts;
    while (std::getline(in, part, ','))
      parts.push_back(parseNumber(key, part));
    if (parts.size() != 3)
      throw std::invalid_argument("gravitation: expected three comma-separated numbers, got '" +
                                  value + "'");
    s.gravitation = pbd::Vector3(pbd::Real(parts[0]), pbd::Real(parts[1]), pbd::Real(parts[2]));
  } else if (key == "contactTolerance" || key == "contactStiffnessRigidBody" ||
             key == "contactStiffnessParticleRigidBody") {
    const double v = parseNumber(key, value);
    if (v < 0) throw std::invalid_argument(key + ": must be ≥ 0, got '" + value + "'");
    (key == "contactTolerance"            ? s.contactTolerance
     : key == "contactStiffnessRigidBody" ? s.contactStiffnessRigidBody
                                          : s.contactStiffnessParticleRigidBody) = pbd::Real(v);
  } else {
    throw std::invalid_argument("unknown scene setting '" + key + "'");
  }
}

bool sceneSettingApplies(const std::string& key, const std::string& engine) {
  return key == "timeStepSize" || key == "gravitation" || engine == "pbd";
}

std::pair<std::string, std::string> splitAssignment(const std::string& text) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0)
    throw std::invalid_argument("expected key=value, got '" + text + "'");
  return {text.substr(0, eq), text.substr(eq + 1)};
}

std::map<std::string, std::string> applyAssignments(
    const std::vector<std::string>& assignments, const std::vector<std::string>& methodParameters,
    pbd::Scene& scene) {
  std::map<std::string, std::string> methodValues;
  for (const std::string& assignment : assignments) {
    const auto [key, value] = splitAssignment(assignment);
    if (std::find(methodParameters.begin(), methodParameters.end(), key) !=
        methodParameters.end()) {
      methodValues[key] = value;
    } else if (std::find(sceneOverrideKeys().begin(), sceneOverrideKeys().end(), key) !=
               sceneOverrideKeys().end()) {
      applySceneOverride(scene, key, value);
    } else {
      std::ostringstream known;
      for (const auto& p : methodParameters)
        known << p << ", ";
      for (const auto& k : sceneOverrideKeys())
        known << k << ", ";
      std::string list = known.str();
      if (list.size() >= 2) list.resize(list.size() - 2);
      throw std::invalid_argument("unknown setting '" + key +
                                  "' (method parameters and scene settings: " + list + ")");
    }
  }
  return methodValues;
}

}  // namespace pbdval
