#include "validation/cli/executors.h"

#include <cstdio>
#include <nlohmann/json.hpp>

#include "validation/cli/python_module.h"
#include "validation/external/standard_engines.h"
#include "validation/io/json_text.h"
#include "validation/run/sharding.h"

namespace pbdval::cli {

void printPlan(const RunPlan& plan) {
  nlohmann::json runs = nlohmann::json::array();
  for (const RunRequest& r : plan.requests)
    runs.push_back({{"case", r.caseName},
                    {"caseFile", r.caseFile},
                    {"engine", r.engine},
                    {"method", r.method},
                    {"assignments", r.assignments}});
  nlohmann::json unreadable = nlohmann::json::array();
  for (const RunRecord& u : plan.unreadable)
    unreadable.push_back(
        {{"case", u.request.caseName}, {"caseFile", u.request.caseFile}, {"reason", u.reason}});
  const nlohmann::json document = {{"planSize", plan.requests.size() + plan.unreadable.size()},
                                   {"planDigest", planDigest(plan)},
                                   {"runs", runs},
                                   {"unreadable", unreadable}};
  std::printf("%s\n", jsonText(document).c_str());
}

bool wantsDask(const ParsedArgs& args) {
  const std::string executor = args.value("executor", "local");
  if (executor == "dask") return true;
  if (executor != "local")
    throw UsageError("--executor: expected local or dask, got '" + executor + "'");
  for (const char* option : {"scheduler", "scheduler-file", "connect-timeout", "runs-per-task"})
    if (args.has(option)) throw UsageError(std::string("--") + option + " needs --executor dask");
  if (args.has("fail-with") && !args.has("shard")) throw UsageError("--fail-with needs --shard");
  return false;
}

std::vector<RunRecord> failedRecords(const std::vector<RunRequest>& requests,
                                     const std::string& reason) {
  std::vector<RunRecord> records;
  for (const RunRequest& request : requests) {
    RunRecord failed;
    failed.request = request;
    failed.request.trajectoryPath.clear();
    failed.status = RunStatus::Error;
    failed.reason = reason;
    records.push_back(failed);
  }
  return records;
}

int runOnDask(const std::string& command, const std::vector<std::string>& arguments) {
  std::vector<std::string> argv = {projectPython(), "-m", "pbdval.cluster", command};
  for (std::size_t i = 0; i < arguments.size(); ++i) {
    if (arguments[i] == "--executor") {
      ++i;  // its value
      continue;
    }
    if (arguments[i].rfind("--executor=", 0) == 0) continue;
    argv.push_back(arguments[i]);
  }
  return execPython(argv);
}

}  // namespace pbdval::cli
