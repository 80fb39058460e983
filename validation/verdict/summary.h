// The summary table printed at the end of `pbdval run` (and by `pbdval report`-like tools):
// one row per run, grouped by case, with the status and the main metrics.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

#include "validation/run/run_record.h"

namespace pbdval {

/// The metrics printSummaryTable shows, in its columns' order (a reader that keeps only some of a
/// record's metrics, pbdval merge's, keeps these).
const std::vector<std::string>& summaryTableMetrics();

void printSummaryTable(std::ostream& out, const std::vector<RunRecord>& runs);
/// "112 runs: 98 ok, 10 unsupported, 3 diverged, 1 error"
std::string statusCounts(const std::vector<RunRecord>& runs);

}  // namespace pbdval
