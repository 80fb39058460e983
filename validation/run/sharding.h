// Sharded runs for batch schedulers (docs/cluster.md): `pbdval run --shard K/N` runs the K-th of
// N deterministic slices of a plan, and `pbdval merge` joins the shard folders into the results
// folder one run of the whole plan would have written.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "validation/io/results.h"
#include "validation/run/run_plan.h"

namespace pbdval {

/// "K/N" with 1 ≤ K ≤ N. Throws std::invalid_argument saying what was expected.
ShardInfo parseShard(const std::string& text);

/// A digest of a plan: every request (case, file, engine, method, assignments, reference and
/// sampling settings) and every unreadable case, in order. Equal plans have equal digests;
/// shards of different plans cannot be merged.
std::string planDigest(const RunPlan& plan);

/// The digest results carry (metadata.planDigest): like planDigest, without whether trajectories
/// are written (a run that fails writes none, and its record says so).
std::string runsDigest(const RunPlan& plan);

/// runsDigest of the plan a results file's runs imply: its runs in order, those of cases that
/// could not be read (engine "-") as the plan's unreadable cases. Equal to the results'
/// metadata.planDigest unless runs were lost, added, reordered or edited since `pbdval run`.
std::string planDigestOfRuns(const std::vector<RunRecord>& runs);

/// The runs of one shard: the plan's requests at positions p with p mod N = K − 1 (round robin,
/// so every shard gets a share of every case), the unreadable cases in shard 1. `shard` gets the
/// plan's size and digest.
RunPlan shardOf(const RunPlan& plan, ShardInfo& shard);

/// One shard's results and the folder they were read from.
struct ShardResults {
  std::string folder;
  ResultsFile results;
};

/// The results of the whole plan from its shards: runs in plan order, the cases' gate data
/// joined. Throws std::invalid_argument naming the folders for results that are not shards,
/// shards of different plans or builds, a shard given twice (overlap), a missing shard (gap),
/// a shard with another number of runs than its slice of the plan, or runs that are not the
/// plan's in its order (metadata.planDigest, when the shards record it). The shards' files are
/// verified by verifiedShardFiles (shard_files.h).
ResultsFile mergeShards(const std::vector<ShardResults>& shards, const std::string& command);

}  // namespace pbdval
