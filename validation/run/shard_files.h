// The files of a shard that `pbdval merge` carries into the merged folder (docs/cluster.md):
// every trajectory a shard's results.json lists is resolved inside that shard folder, in the
// layout `pbdval run` writes, or the shard is refused. Nothing outside a shard is read, copied
// or moved, whatever its results.json says.
#pragma once

#include <string>
#include <vector>

#include "validation/run/sharding.h"

namespace pbdval {

/// One file a shard holds for one of its runs.
struct ShardFile {
  std::size_t run = 0;     ///< index of the run in the shard's results
  std::string path;        ///< the file, inside the shard folder: SHARD/trajectories/CASE/NAME
  std::string relative;    ///< "trajectories/CASE/NAME": the same place in the merged folder
  bool companion = false;  ///< the run's particles or rod segments beside its trajectory
};

/// The files of `shard` that `pbdval merge` carries, verified. A run's recorded trajectory path
/// must be "OUT/trajectories/CASE/ENGINE-METHOD.EXT" with the run's own case, engine and method
/// and EXT csv or npy (OUT: the --out of the shard's run, anywhere, relative or absolute: the
/// file is always taken from the same place in the shard folder, never from OUT, so neither
/// ".." nor an absolute path can reach outside it). Throws std::invalid_argument naming the
/// shard folder, the run and the path for a path of another form (e.g. ending in "../x" or
/// "/etc/passwd") or with a NUL, a case, engine or method name that is not a plain file name, a
/// symbolic link on the way (trajectories/, CASE/ or the file), something that is not a regular
/// file, two runs with one file, or a missing trajectory of a measured run (ok, suspect: their
/// metrics are data; a run that failed may have none). The particle and segment files beside a
/// trajectory are carried when present, under the same rules.
std::vector<ShardFile> verifiedShardFiles(const ShardResults& shard);

/// Copies (or, with `move`, renames, copying across file systems) every file of `files` to
/// `folder`/relative, creating the folders on the way; writes atomically.
void carryShardFiles(const std::vector<ShardFile>& files, const std::string& folder, bool move);

}  // namespace pbdval
