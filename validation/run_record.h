// One run of the validation suite: what was asked (RunRequest) and what came of it
// (RunRecord), and their JSON form, shared by results.json, the isolated child processes,
// sweeps, baselines and the gate (docs/results.md).
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "validation/metrics.h"
#include "validation/simulation.h"

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
  MetricSet metrics;      ///< includes wall_time_s, steps, real_time_factor
  std::string stateHash;  ///< deterministic engines only
  std::string reference;  ///< description of the reference used ("" none)
};

/// Runs one request in this process: loads the case, runs the engine, builds the reference,
/// computes the metrics, writes the trajectory. Never throws: every failure becomes the
/// record's status and reason.
RunRecord executeRun(const RunRequest& request);

/// Runs requests each in its own child process (fork), at most `jobs` at a time, each with
/// `timeout` seconds of wall time (0 = none), so that a crash (signal) or a hang of an engine
/// becomes a status (`error` naming the signal, `timeout`) instead of taking the suite down.
/// Children report through files in `scratchFolder`. `onFinished` is called in the parent,
/// in completion order; `onTick` about every 20 ms with the requests running.
class RunScheduler {
 public:
  RunScheduler(int jobs, double timeout, std::string scratchFolder);
  std::vector<RunRecord> runAll(
      const std::vector<RunRequest>& requests,
      const std::function<void(const RunRecord&, std::size_t done, std::size_t total)>& onFinished,
      const std::function<void(const std::vector<const RunRequest*>& running)>& onTick = {});

 private:
  int jobs_;
  double timeout_;
  std::string scratchFolder_;
};

/// JSON text of a record (one entry of results.json's "runs") and back. fromJson throws
/// std::invalid_argument with the path of a missing or malformed field.
std::string toJsonText(const RunRecord& record);
RunRecord recordFromJsonText(const std::string& text, const std::string& where);

/// "engine/method" for tables.
inline std::string runLabel(const RunRequest& r) {
  return r.engine + "/" + r.method;
}

}  // namespace pbdval
