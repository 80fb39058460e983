// Which (case, engine, method) runs a `pbdval run` makes.
//
// Engines: --engines, else every engine; a case's Validation.engines restricts them further.
// Methods: --methods (each belonging to a selected engine), else the case's Validation.methods,
// else each selected engine's run methods (EngineEntry::runMethods: the PBD library runs both
// of its methods, every other engine its default).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "adapters/registry.h"
#include "validation/io/trajectory.h"
#include "validation/run/case_spec.h"
#include "validation/run/run_record.h"

namespace pbdval {

struct PlanOptions {
  std::vector<std::string> engines;      ///< empty: all
  std::vector<std::string> methods;      ///< empty: the case's, else the engines' defaults
  std::vector<std::string> assignments;  ///< --set, passed to every run
  std::string referenceMode;             ///< --reference: RunRequest::referenceMode of every run
  std::string outFolder = "out";
  bool writeTrajectories = true;
  TrajectoryFormat trajectoryFormat = TrajectoryFormat::Csv;
  bool strictScene = false;
};

struct RunPlan {
  std::vector<RunRequest> requests;
  /// The Validation blocks of the cases read, by case name.
  std::map<std::string, std::pair<std::string, CaseSpec>> cases;  ///< name → (file, spec)
  /// Cases that could not be read: one `error` record each, reported with the results.
  std::vector<RunRecord> unreadable;
};

/// Throws std::invalid_argument for unknown engines or methods in `options`.
RunPlan planRuns(const std::vector<std::string>& caseFiles, const PlanOptions& options,
                 const EngineRegistry& registry);

/// "trajectories/CASE/ENGINE-METHOD.csv" (or ".npy") under the out folder.
std::string trajectoryPathFor(const std::string& outFolder, const std::string& caseName,
                              const std::string& engine, const std::string& method,
                              TrajectoryFormat format = TrajectoryFormat::Csv);

/// Where a run's particle states go beside its trajectory (cloth, solids, rods, fluids):
/// "DIR/trajectories/CASE/ENGINE-METHOD.particles.csv" for ".../ENGINE-METHOD.csv" (the same
/// extension, docs/cli.md#particles).
std::string particlePathFor(const std::string& trajectoryPath);
/// Where a run's Cosserat-rod segment states go: ".../ENGINE-METHOD.segments.csv" (the same
/// extension, docs/cli.md#segments).
std::string segmentPathFor(const std::string& trajectoryPath);
/// Every file a run may write beside its trajectory: particlePathFor, segmentPathFor.
std::vector<std::string> companionPathsFor(const std::string& trajectoryPath);

}  // namespace pbdval
