#include "validation/overrides.h"

#include <algorithm>
#include <stdexcept>

#include "pbd/io/scene_loader.h"

namespace pbdval {
namespace {

bool contains(const std::vector<std::string>& list, const std::string& item) {
  return std::find(list.begin(), list.end(), item) != list.end();
}

}  // namespace

std::pair<std::string, std::string> splitAssignment(const std::string& text) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0)
    throw std::invalid_argument("expected key=value, got '" + text + "'");
  return {text.substr(0, eq), text.substr(eq + 1)};
}

std::map<std::string, std::string> applyAssignments(const std::vector<std::string>& assignments,
                                                    const MethodInfo& method, pbd::Scene& scene) {
  const std::vector<std::string> settings = pbd::simulationSettingKeys();
  std::map<std::string, std::string> methodValues;
  for (const std::string& assignment : assignments) {
    const auto [key, value] = splitAssignment(assignment);
    if (method.find(key)) {
      methodValues[key] = value;
    } else if (contains(settings, key)) {
      try {
        pbd::applySimulationSetting(scene.simulation, key, value, "--set " + assignment);
      } catch (const pbd::SceneError& e) {
        throw std::invalid_argument(e.what());
      }
    } else {
      std::string known;
      for (const ParameterSpec& p : method.parameters) known += p.name + ", ";
      known = known.empty() ? "none" : known.substr(0, known.size() - 2);
      std::string keys;
      for (const std::string& k : settings) keys += (keys.empty() ? "" : ", ") + k;
      throw std::invalid_argument("unknown setting '" + key + "': not a parameter of method " +
                                  method.name + " (" + known +
                                  ") nor a Simulation setting (" + keys + ")");
    }
  }
  return methodValues;
}

bool assignmentApplies(const std::string& key, const MethodInfo& method, const EngineEntry& engine) {
  return method.find(key) != nullptr || contains(engine.honouredSettings, key);
}

}  // namespace pbdval
