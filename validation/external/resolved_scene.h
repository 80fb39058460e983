// The resolved scene: everything an external engine needs to build and run a scene, as one JSON
// document with nothing left to interpret (docs/external-engines.md, schema
// docs/schemas/resolved-scene.schema.json). Mass properties, principal frames, joint anchors
// and axes in both bodies' frames, and every contact pair's combined friction and restitution
// are computed here, once, from the loaded pbd::Scene, exactly as the built-in engines see them.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "adapters/registry.h"
#include "pbd/model/scene.h"
#include "validation/run/simulation.h"

namespace pbdval {

inline constexpr const char* kResolvedSceneFormat = "pbdval.resolved-scene";
inline constexpr int kResolvedSceneVersion = 1;

/// The resolved scene for a run of `length` with method `methodName` and its parameters
/// (`methodParameters`: a JSON object, name → number, bool or string). Throws
/// std::invalid_argument for a non-object `methodParameters` or an invalid run length.
nlohmann::json resolvedSceneJson(const pbd::Scene& scene, const std::string& methodName,
                                 const nlohmann::json& methodParameters, const RunLength& length);

/// A method's parameter values as typed JSON (numbers, true/false, strings), the resolved
/// scene's "method.parameters".
nlohmann::json methodParametersJson(const Method& method);

/// The case's run length: Validation.duration (else pauseAt > 0, else 5 s) and
/// Validation.sampleInterval (else every step). Throws std::invalid_argument for a bad
/// Validation block (the message names the file and the JSON path).
RunLength caseRunLength(const pbd::Scene& scene, const EngineRegistry& registry);

}  // namespace pbdval
