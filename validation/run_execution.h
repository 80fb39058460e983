// Running one request in this process (the body of every isolated child process).
#pragma once

#include "adapters/registry.h"
#include "validation/run_record.h"

namespace pbdval {

/// Runs one request in this process: loads the case, runs the engine from `registry`, builds the
/// reference, computes the metrics, writes the trajectory. Never throws: every failure becomes
/// the record's status and reason.
RunRecord executeRun(const RunRequest& request, const EngineRegistry& registry);

}  // namespace pbdval
