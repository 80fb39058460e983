#include "validation/verdict/summary.h"

#include <cmath>
#include <cstdio>
#include <map>
#include <ostream>

namespace pbdval {
namespace {

std::string cell(const MetricSet& m, const char* name) {
  const auto it = m.values.find(name);
  if (it == m.values.end()) return "-";
  char text[32];
  std::snprintf(text, sizeof text, "%.2e", it->second);
  return text;
}

std::string padded(const std::string& text, std::size_t width) {
  return text.size() >= width ? text : text + std::string(width - text.size(), ' ');
}

}  // namespace

const std::vector<std::string>& summaryTableMetrics() {
  static const std::vector<std::string> metrics = {"energy_drift_max", "joint_error_linear_max",
                                                   "penetration_max", "trajectory_error_max",
                                                   "real_time_factor"};
  return metrics;
}

void printSummaryTable(std::ostream& out, const std::vector<RunRecord>& runs) {
  std::size_t caseWidth = 4, runWidth = 13;
  for (const RunRecord& r : runs) {
    caseWidth = std::max(caseWidth, r.request.caseName.size());
    runWidth = std::max(runWidth, runLabel(r.request).size());
  }
  const char* columns[] = {"energy_drift", "joint_err_m", "penetr_m", "traj_err_m", "rtf"};
  out << padded("case", caseWidth) << "  " << padded("engine/method", runWidth) << "  "
      << padded("status", 11);
  for (const char* c : columns)
    out << padded(c, 13);
  out << '\n';
  std::string previousCase;
  for (const RunRecord& r : runs) {
    const bool newCase = r.request.caseName != previousCase;
    previousCase = r.request.caseName;
    out << padded(newCase ? r.request.caseName : "", caseWidth) << "  "
        << padded(runLabel(r.request), runWidth) << "  " << padded(runStatusName(r.status), 11);
    if (isMeasured(r.status)) {
      const std::vector<std::string>& metrics = summaryTableMetrics();
      for (std::size_t k = 0; k + 1 < metrics.size(); ++k)
        out << padded(cell(r.metrics, metrics[k].c_str()), 13);
      const auto rtf = r.metrics.values.find(metrics.back());
      char text[32];
      std::snprintf(text, sizeof text, "%.0f", rtf == r.metrics.values.end() ? 0.0 : rtf->second);
      out << text;
      if (r.status == RunStatus::Suspect) {
        // Why, on a line of its own under the metrics: the check, the value and the bound.
        std::string reason = r.reason;
        if (reason.size() > 110) reason = reason.substr(0, 107) + "...";
        out << '\n'
            << padded("", caseWidth) << "  " << padded("", runWidth) << "  " << padded("", 11)
            << reason;
      }
    } else {
      std::string reason = r.reason;
      if (reason.size() > 90) reason = reason.substr(0, 87) + "...";
      out << reason;
    }
    out << '\n';
  }
}

std::string statusCounts(const std::vector<RunRecord>& runs) {
  std::map<std::string, int> counts;
  for (const RunRecord& r : runs)
    ++counts[runStatusName(r.status)];
  std::string text = std::to_string(runs.size()) + " runs:";
  bool first = true;
  for (RunStatus s : kRunStatuses) {
    const char* status = runStatusName(s);
    if (!counts.count(status)) continue;
    text += std::string(first ? " " : ", ") + std::to_string(counts[status]) + " " + status;
    first = false;
  }
  return text;
}

}  // namespace pbdval
