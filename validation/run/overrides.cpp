#include "validation/run/overrides.h"

#include <algorithm>
#include <stdexcept>

#include "pbd/io/scene_loader.h"
#include "pbd/io/suggestion.h"

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
      std::vector<std::string> known;
      for (const ParameterSpec& p : method.parameters)
        known.push_back(p.name);
      std::vector<std::string> candidates = known;
      candidates.insert(candidates.end(), settings.begin(), settings.end());
      throw std::invalid_argument("unknown setting '" + key + "': not a parameter of method " +
                                  method.name + " (" + pbd::nameList(known) +
                                  ") nor a Simulation setting (" + pbd::nameList(settings) + ")" +
                                  pbd::didYouMean(key, candidates));
    }
  }
  return methodValues;
}

bool assignmentApplies(const std::string& key, const MethodInfo& method,
                       const EngineEntry& engine) {
  return method.find(key) != nullptr || contains(engine.honouredSettings, key);
}

std::string unknownSettingMessage(const std::string& key, const std::vector<std::string>& methods,
                                  const EngineRegistry& registry) {
  std::vector<std::string> candidates;
  std::string parameters;
  std::vector<std::string> engines;
  for (const std::string& name : methods) {
    const MethodInfo& info = registry.method(name);
    std::vector<std::string> own;
    for (const ParameterSpec& p : info.parameters)
      own.push_back(p.name);
    parameters += (parameters.empty() ? "" : "; ") + name + ": " + pbd::nameList(own);
    candidates.insert(candidates.end(), own.begin(), own.end());
    if (!contains(engines, info.engine)) engines.push_back(info.engine);
  }
  std::string honoured;
  for (const std::string& engine : engines) {
    const std::vector<std::string>& keys = registry.engine(engine).honouredSettings;
    honoured += (honoured.empty() ? "" : "; ") + engine + ": " + pbd::nameList(keys);
    for (const std::string& k : keys)
      if (!contains(candidates, k)) candidates.push_back(k);
  }
  for (const std::string& k : pbd::simulationSettingKeys())
    if (!contains(candidates, k)) candidates.push_back(k);
  return "unknown setting '" + key +
         "' (method parameters: " + (parameters.empty() ? std::string("none") : parameters) +
         "; Simulation settings honoured: " + honoured + ")" + pbd::didYouMean(key, candidates);
}

void checkAssignmentValue(const std::string& key, const std::string& value,
                          const MethodInfo& method, const std::string& origin) {
  if (const ParameterSpec* spec = method.find(key)) {
    try {
      parseParameter(*spec, value, method.name);
    } catch (const std::invalid_argument& e) {
      throw OptionError(origin + ": " + e.what());
    }
    return;
  }
  pbd::SimulationSettings settings;
  try {
    pbd::applySimulationSetting(settings, key, value, origin);
  } catch (const pbd::SceneError& e) {
    throw OptionError(e.what());
  }
}

void checkAssignments(const std::vector<std::string>& assignments,
                      const std::vector<std::string>& methods, const EngineRegistry& registry,
                      const std::string& option) {
  std::vector<std::string> seen;
  for (const std::string& assignment : assignments) {
    std::pair<std::string, std::string> split;
    try {
      split = splitAssignment(assignment);
    } catch (const std::invalid_argument& e) {
      throw OptionError(option + ": " + e.what());
    }
    const auto& [key, value] = split;
    if (contains(seen, key)) throw OptionError(option + " " + key + " is given more than once");
    seen.push_back(key);
    if (methods.empty()) continue;  // no run to apply it to (every case unreadable)
    std::vector<std::string> applies, ignores, ignoringEngines;
    for (const std::string& name : methods) {
      const MethodInfo& info = registry.method(name);
      const EngineEntry& engine = registry.engine(info.engine);
      const bool applied = assignmentApplies(key, info, engine);
      (applied ? applies : ignores).push_back(info.engine + "/" + name);
      if (!applied && !contains(ignoringEngines, info.engine))
        ignoringEngines.push_back(info.engine);
    }
    const std::vector<std::string> settings = pbd::simulationSettingKeys();
    if (applies.empty() && !contains(settings, key))
      throw OptionError(option + " " + assignment + ": " +
                        unknownSettingMessage(key, methods, registry));
    if (!ignores.empty()) {
      std::string honoured;
      for (const std::string& engine : ignoringEngines)
        honoured += (honoured.empty() ? "" : "; ") + engine + " honours " +
                    pbd::nameList(registry.engine(engine).honouredSettings) +
                    " and its methods' parameters";
      throw OptionError(option + " " + assignment + ": " + key + " has no effect in " +
                        pbd::nameList(ignores) + " (" + honoured + ")" +
                        (applies.empty() ? std::string("")
                                         : "; it applies to " + pbd::nameList(applies) +
                                               ": restrict --engines or --methods to those runs"));
    }
    for (const std::string& name : methods)
      checkAssignmentValue(key, value, registry.method(name), option + " " + assignment);
  }
}

bool isEngineReference(const std::string& referenceMode) {
  return !referenceMode.empty() && referenceMode != "fine" && referenceMode != "none";
}

EngineReference parseEngineReference(const std::string& text, const EngineRegistry& registry,
                                     const std::string& option) {
  EngineReference reference;
  const auto colon = text.find(':');
  reference.method = text.substr(0, colon);
  const MethodInfo* info = nullptr;
  try {
    info = &registry.method(reference.method);
  } catch (const std::invalid_argument& e) {
    throw OptionError(option + " " + text +
                      ": expected fine, case, none or METHOD[:KEY=VALUE,...]; " + e.what());
  }
  if (colon == std::string::npos) return reference;
  std::vector<std::string> keys;
  std::string rest = text.substr(colon + 1);
  while (true) {
    const auto comma = rest.find(',');
    const std::string assignment = rest.substr(0, comma);
    std::pair<std::string, std::string> split;
    try {
      split = splitAssignment(assignment);
    } catch (const std::invalid_argument& e) {
      throw OptionError(option + " " + text + ": " + e.what());
    }
    if (info->find(split.first) == nullptr) {
      std::vector<std::string> known;
      for (const ParameterSpec& p : info->parameters)
        known.push_back(p.name);
      throw OptionError(option + " " + text + ": '" + split.first + "' is not a parameter of " +
                        reference.method + " (" + pbd::nameList(known) + ")" +
                        pbd::didYouMean(split.first, known));
    }
    if (contains(keys, split.first))
      throw OptionError(option + " " + text + ": '" + split.first + "' is given twice");
    keys.push_back(split.first);
    checkAssignmentValue(split.first, split.second, *info, option + " " + text);
    reference.assignments.push_back(assignment);
    if (comma == std::string::npos) break;
    rest = rest.substr(comma + 1);
  }
  return reference;
}

}  // namespace pbdval
