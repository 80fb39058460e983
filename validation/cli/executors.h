// What `pbdval run` and `pbdval sweep` share to run on other executors (docs/cluster.md): the
// plan as JSON, and handing over to the Dask client.
#pragma once

#include <string>
#include <vector>

#include "validation/cli/args.h"
#include "validation/run/run_plan.h"

namespace pbdval::cli {

/// The plan as JSON on standard output (--list-plan): its size, digest and runs, for executors
/// and for a user checking a study before starting it.
void printPlan(const RunPlan& plan);

/// Checks the executor options of `run` and `sweep`: true when --executor is dask (then call
/// runOnDask); throws UsageError for another executor, Dask options without it, or --fail-with
/// without --shard.
bool wantsDask(const ParsedArgs& args);

/// The requests as runs of status error with `reason`, none of them run (--fail-with).
std::vector<RunRecord> failedRecords(const std::vector<RunRequest>& requests,
                                     const std::string& reason);

/// --executor dask: replaces this process by the Dask client (python -m pbdval.cluster COMMAND
/// ARGUMENTS..., the project's virtual environment), with --executor and its value removed.
/// Returns only when that fails (exit status 2).
int runOnDask(const std::string& command, const std::vector<std::string>& arguments);

}  // namespace pbdval::cli
