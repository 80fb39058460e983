// `--set KEY=VALUE`, the one route from text to a run's configuration: a key that is a
// parameter of the run's method becomes a method parameter (parsed and checked against its
// declaration by the registry); a key of the scene's Simulation block is applied to the scene
// with the scene loader's own checks (pbd::applySimulationSetting), so a value is accepted
// from `--set` exactly when it would be accepted in the scene file.
#pragma once

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "adapters/engine.h"
#include "pbd/model/scene.h"

namespace pbdval {

/// Splits "key=value"; throws std::invalid_argument when there is no '=' or no key.
std::pair<std::string, std::string> splitAssignment(const std::string& text);

/// Applies the Simulation-setting assignments to `scene` and returns the method-parameter ones
/// (key → text, for resolveMethod). Throws std::invalid_argument for a key that is neither (naming
/// both lists) and for a Simulation value the loader would reject (naming the accepted range).
std::map<std::string, std::string> applyAssignments(const std::vector<std::string>& assignments,
                                                    const MethodInfo& method, pbd::Scene& scene);

/// Whether `key` is a parameter of `method` or a Simulation setting that `engine` honours
/// (a sweep over a setting the engine ignores would measure nothing).
bool assignmentApplies(const std::string& key, const MethodInfo& method, const EngineEntry& engine);

}  // namespace pbdval
