// `--set key=value`: method parameters first, then the scene's Simulation settings that a run
// may override (the sweep parameters).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "pbd/model/scene.h"

namespace pbdval {

/// Simulation keys a run may override (timeStepSize, gravitation, contact settings, ...).
const std::vector<std::string>& sceneOverrideKeys();
/// Sets one Simulation key from text; throws std::invalid_argument with the reason.
void applySceneOverride(pbd::Scene& scene, const std::string& key, const std::string& value);

/// Whether a scene setting has any effect in `engine`: timeStepSize and gravitation apply to
/// every engine; the solver and contact settings of the Simulation block only to pbd.
bool sceneSettingApplies(const std::string& key, const std::string& engine);

/// Splits "key=value"; throws std::invalid_argument when there is no '='.
std::pair<std::string, std::string> splitAssignment(const std::string& text);

/// Splits --set assignments into method parameters (those `methodParameters` names) and scene
/// overrides (applied to `scene`); throws std::invalid_argument for a key that is neither.
std::map<std::string, std::string> applyAssignments(
    const std::vector<std::string>& assignments, const std::vector<std::string>& methodParameters,
    pbd::Scene& scene);

}  // namespace pbdval
