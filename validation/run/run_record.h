// One run of the validation suite: what was asked (RunRequest) and what came of it
// (RunRecord), and their JSON form, shared by results.json, the isolated child processes,
// sweeps, baselines and the gate (docs/results.md). Running a request: run_execution.h; many
// at once, isolated: run_scheduler.h.
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "validation/measure/metrics.h"
#include "validation/run/simulation.h"

namespace pbdval {

inline constexpr int kResultsSchemaVersion = 1;

struct RunRequest {
  std::string caseName;  ///< file stem, e.g. "joint_hinge"
  std::string caseFile;  ///< path of the scene
  std::string engine;
  std::string method;
  std::vector<std::string> assignments;  ///< --set KEY=VALUE (method parameters, scene settings)
  std::string trajectoryPath;            ///< write the CSV here ("" = don't)
  /// Reference override: "" uses the case's Validation.reference; "fine" the same method at
  /// timeStepSize / fineDivisor; "none" no reference.
  std::string referenceMode;
  int fineDivisor = 16;
  /// Absolute step of the "fine" reference (s); 0: the run's timeStepSize / fineDivisor. Sweeps
  /// over timeStepSize fix it so that every point is compared with the same reference.
  double referenceStepSize = 0;
  /// Sample interval (s) overriding the case's; 0: the case's. Sweeps use a common one.
  double sampleInterval = 0;
  bool strictScene = false;
};

struct RunRecord {
  RunRequest request;
  RunStatus status = RunStatus::Error;
  std::string reason;
  std::map<std::string, std::string> methodParameters;  ///< resolved values
  std::map<std::string, std::string> settings;          ///< Engine::effectiveSettings()
  RunFacts facts;                                       ///< Engine::runFacts()
  MetricSet metrics;      ///< includes wall_time_s, steps, real_time_factor
  std::string stateHash;  ///< deterministic engines only
  std::string reference;  ///< description of the reference used ("" none)
};

/// JSON text of a record (one entry of results.json's "runs") and back. fromJson throws
/// std::invalid_argument with the path of a missing or malformed field.
std::string toJsonText(const RunRecord& record);
RunRecord recordFromJsonText(const std::string& text, const std::string& where);
/// The same as JSON values (results.json's reader and writer: no text in between).
nlohmann::json recordJson(const RunRecord& record);
RunRecord recordFromJson(const nlohmann::json& json, const std::string& where);

/// "engine/method" for tables.
inline std::string runLabel(const RunRequest& r) {
  return r.engine + "/" + r.method;
}

}  // namespace pbdval
