// pbdval merge SHARD_DIR... --out DIR
//
// Joins the results folders of `pbdval run --shard K/N` into the folder one run of the whole plan
// writes (docs/cluster.md): results.json in plan order and every trajectory.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>

#include "validation/atomic_file.h"
#include "validation/cli/args.h"
#include "validation/cli/commands.h"
#include "validation/results.h"
#include "validation/results_folder.h"
#include "validation/run_plan.h"
#include "validation/sharding.h"
#include "validation/summary.h"

namespace pbdval::cli {
namespace {

namespace fs = std::filesystem;

std::string fileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot be read");
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

/// Where a shard's trajectory goes under `out`: its path relative to the shard folder when it
/// lies inside it, else trajectories/CASE/<its name>.
std::string mergedTrajectoryPath(const std::string& shardFolder, const std::string& out,
                                 const RunRecord& r) {
  const fs::path relative = fs::path(r.request.trajectoryPath).lexically_relative(shardFolder);
  if (!relative.empty() && *relative.begin() != "..") return (fs::path(out) / relative).string();
  return (fs::path(out) / "trajectories" / r.request.caseName /
          fs::path(r.request.trajectoryPath).filename())
      .string();
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
    for (const std::string& folder : args.positionals) {
      if (fs::exists(out) && fs::exists(folder) && fs::equivalent(out, folder))
        throw UsageError("--out " + out + " is one of the shard folders");
      shards.push_back({folder, readResults(folder + "/results.json")});
    }
    const bool move = args.flags.count("move") > 0;
    ResultsFile merged = mergeShards(shards, command.str());
    merged.metadata.created = currentMetadata("").created;
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
    std::map<std::string, std::string> moved;  // a shard's trajectory path → the merged one
    for (const ShardResults& shard : shards)
      for (const RunRecord& r : shard.results.runs) {
        if (r.request.trajectoryPath.empty() || !fs::is_regular_file(r.request.trajectoryPath))
          continue;
        const std::string target = mergedTrajectoryPath(shard.folder, folder.staging(), r);
        if (!moved.emplace(r.request.trajectoryPath, target).second)
          throw std::invalid_argument(r.request.trajectoryPath + ": the trajectory of two runs");
        fs::create_directories(fs::path(target).parent_path());
        // The trajectory, and the particles and rod segments beside it when the run has them.
        const std::string& trajectoryFile = r.request.trajectoryPath;
        std::vector<std::pair<std::string, std::string>> files = {{trajectoryFile, target}};
        const std::vector<std::string> fromCompanions = companionPathsFor(trajectoryFile);
        const std::vector<std::string> toCompanions = companionPathsFor(target);
        for (std::size_t i = 0; i < fromCompanions.size(); ++i)
          files.emplace_back(fromCompanions[i], toCompanions[i]);
        for (const auto& [from, to] : files) {
          if (from != trajectoryFile && !fs::is_regular_file(from)) continue;
          std::error_code renamed;
          if (move) fs::rename(from, to, renamed);
          if (!move || renamed)  // another file system: copy
            writeFileAtomically(to, fileBytes(from));
        }
      }
    const std::size_t copied = moved.size();
    for (RunRecord& m : merged.runs) {
      const auto it = moved.find(m.request.trajectoryPath);
      if (it != moved.end()) m.request.trajectoryPath = folder.finalPath(it->second);
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
