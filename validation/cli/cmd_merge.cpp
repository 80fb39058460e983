// pbdval merge SHARD_DIR... --out DIR
//
// Joins the results folders of `pbdval run --shard K/N` into the folder one run of the whole plan
// writes (docs/cluster.md): results.json in plan order and every trajectory.
#include <algorithm>
#include <atomic>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <iostream>
#include <map>
#include <sstream>
#include <thread>

#include "validation/cli/args.h"
#include "validation/cli/commands.h"
#include "validation/io/results.h"
#include "validation/io/results_folder.h"
#include "validation/run/run_plan.h"
#include "validation/run/shard_files.h"
#include "validation/run/sharding.h"
#include "validation/verdict/summary.h"

namespace pbdval::cli {
namespace {

namespace fs = std::filesystem;

/// A shard's results.json as read, or why it could not be.
struct ReadShard {
  ResultsFile results;
  std::exception_ptr error;
};

/// The results of every shard folder, read side by side (a thread per core): each record is kept
/// as its text, to be copied on (readResultsCopyingRecords), with the metrics the summary table
/// shows. Errors are kept for the caller to report in the folders' order.
std::vector<ReadShard> readShards(const std::vector<std::string>& folders) {
  std::vector<ReadShard> read(folders.size());
  std::atomic<std::size_t> next{0};
  const auto work = [&] {
    for (std::size_t k = next++; k < folders.size(); k = next++) {
      try {
        read[k].results =
            readResultsCopyingRecords(folders[k] + "/results.json", summaryTableMetrics());
      } catch (...) {
        read[k].error = std::current_exception();
      }
    }
  };
  const std::size_t threads =
      std::min<std::size_t>(folders.size(), std::max(1u, std::thread::hardware_concurrency()));
  std::vector<std::thread> workers;
  for (std::size_t t = 1; t < threads; ++t)
    workers.emplace_back(work);
  work();
  for (std::thread& worker : workers)
    worker.join();
  return read;
}

}  // namespace

int mergeCommand(const Context& /*context*/, const Arguments& arguments) {
  ArgParser parser("merge", "SHARD_DIR... --out DIR",
                   "Joins the folders of 'pbdval run --shard K/N' (all N of them, from the same\n"
                   "plan and build) into one results folder: results.json with the runs in plan\n"
                   "order, and the trajectories. Refuses overlaps, gaps and mixed builds.");
  parser.positionals("SHARD_DIR", "results folders of the shards", 1, -1)
      .option("out", "DIR", "the merged results folder")
      .flag("move", "move the trajectories instead of copying them (the shard folders lose them)")
      .flag("force", "replace the results of another plan that --out holds")
      .flag("quiet", "print only the summary line")
      .epilog(
          "exit status: 0 merged, 2 bad usage or shards that do not make one plan.\n"
          "example: pbdval merge out-1 out-2 out-3 --out out");
  ParsedArgs args;
  if (const auto exit = parser.parseOrExit(arguments, args)) return *exit;
  if (!args.has("out")) return parser.usageError("--out is required");
  std::string out = args.value("out");
  while (out.size() > 1 && out.back() == '/')
    out.pop_back();
  std::ostringstream command;
  command << "pbdval merge";
  for (const std::string& a : arguments)
    command << ' ' << a;
  try {
    std::vector<ShardResults> shards;
    std::vector<ReadShard> read = readShards(args.positionals);
    for (std::size_t k = 0; k < read.size(); ++k) {
      const std::string& folder = args.positionals[k];
      if (fs::exists(out) && fs::exists(folder) && fs::equivalent(out, folder))
        throw UsageError("--out " + out + " is one of the shard folders");
      if (read[k].error) std::rethrow_exception(read[k].error);
      shards.push_back({folder, std::move(read[k].results)});
      // Without the plan's digest the merged runs cannot be checked against the plan.
      if (shards.back().results.metadata.planDigest.empty())
        throw std::invalid_argument(
            folder +
            "/results.json: metadata.planDigest: missing (results "
            "written before pbdval recorded the plan); run the shard again");
    }
    const bool move = args.flags.count("move") > 0;
    ResultsFile merged = mergeShards(shards, command.str());
    merged.metadata.created = currentMetadata("").created;
    // Every shard's files verified (inside its folder, no symbolic link, the trajectories of
    // its measured runs present) before anything is copied or moved.
    std::vector<ShardFile> files;
    std::map<std::string, std::string> owner;  // merged relative path → the shard holding it
    for (const ShardResults& shard : shards)
      for (ShardFile& file : verifiedShardFiles(shard)) {
        const auto [it, added] = owner.emplace(file.relative, shard.folder);
        if (!added)
          throw std::invalid_argument(file.relative + ": in two shards, " + it->second + " and " +
                                      shard.folder);
        files.push_back(std::move(file));
      }
    // The output folder: locked, staged, and another plan's results never replaced silently.
    ResultsFolder folder(out, "pbdval merge");
    std::vector<RunKey> planned;
    for (const RunRecord& r : merged.runs)
      planned.push_back(
          {r.request.caseName, r.request.engine, r.request.method, r.request.assignments});
    if (const auto why = foreignResults(out + "/results.json", planned);
        why && !args.flags.count("force"))
      return parser.inputError(out + "/results.json: " + *why +
                               "; merging would replace them: give another --out, or --force to "
                               "replace them");
    carryShardFiles(files, folder.staging(), move);
    std::size_t copied = 0;
    for (const ShardFile& file : files)
      copied += file.companion ? 0 : 1;
    // Each run's trajectory path: its place in the merged folder, as one run of the whole plan
    // records it (a failed run's too, whose file may not exist). verifiedShardFiles has checked
    // that the recorded name is ENGINE-METHOD.EXT.
    for (RunRecord& m : merged.runs) {
      if (m.request.trajectoryPath.empty()) continue;
      const std::string name = fs::path(m.request.trajectoryPath).filename().string();
      m.request.trajectoryPath =
          folder.finalPath(folder.staging() + "/trajectories/" + m.request.caseName + "/" + name);
    }
    writeResults(folder.staging() + "/results.json", merged);
    folder.commit({"trajectories", "results.json"}, "results.json");
    if (!args.flags.count("quiet")) printSummaryTable(std::cout, merged.runs);
    std::printf("pbdval merge: %zu shards: %s, %zu trajectories; results in %s/results.json\n",
                shards.size(), statusCounts(merged.runs).c_str(), copied, out.c_str());
  } catch (const UsageError& e) {
    return parser.usageError(e.what());
  } catch (const std::exception& e) {
    return parser.inputError(e.what());
  }
  return 0;
}

}  // namespace pbdval::cli
