// The output folder of `pbdval run`, `sweep` and `merge`, written as one transaction
// (docs/cli.md#results-folders):
//
//   - a lock: DIR/.pbdval.lock is held (flock) for the command's lifetime; a second command
//     writing the same folder is refused, naming the holder's pid and command (exit 2);
//   - staging: everything the command writes goes to a fresh folder DIR/.pbdval-staging-PID;
//   - commit(): the previous results are replaced by the staged ones: the previous manifest
//     (results.json, sweep.json) is removed first, the staged files are moved in, the new
//     manifest last. At no moment does a manifest list files of another run: a crash in between
//     leaves no manifest, never an old one beside new trajectories;
//   - without commit (an error, SIGINT, SIGTERM): the staging folder is removed and the previous
//     results are untouched; a folder this command created is removed again if it holds nothing
//     else;
//   - another plan's results are never replaced silently: foreignResults() tells the command
//     (which refuses unless --force).
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace pbdval {

/// Another pbdval command holds the folder's lock.
class FolderBusy : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class ResultsFolder {
 public:
  /// Creates `folder` (and its parents) if needed, takes its lock (throws FolderBusy naming the
  /// holder), removes the staging folders of commands that were killed, and creates this
  /// command's staging folder. `command` ("pbdval run") is recorded in the lock file. Throws
  /// std::runtime_error naming the folder when it cannot be created or written.
  ResultsFolder(std::string folder, const std::string& command);
  ~ResultsFolder();
  ResultsFolder(const ResultsFolder&) = delete;
  ResultsFolder& operator=(const ResultsFolder&) = delete;

  const std::string& folder() const { return folder_; }
  /// Where the command writes: "FOLDER/.pbdval-staging-PID".
  const std::string& staging() const { return staging_; }
  /// A path under staging() as it will be after commit() (the same path under folder()); other
  /// paths unchanged. For the paths a results file records.
  std::string finalPath(const std::string& stagedPath) const;

  /// Replaces the folder's `entries` (top-level names this command owns, e.g. "trajectories"
  /// and "results.json") by the staged ones: `manifest` (one of the entries) is removed first and
  /// moved in last; an entry the staging folder lacks is removed from the folder. Then the
  /// staging folder is removed. Throws std::runtime_error naming the file on failure.
  void commit(const std::vector<std::string>& entries, const std::string& manifest);

 private:
  std::string folder_;
  std::string staging_;
  std::vector<std::string> created_;  ///< folders this command created, outermost first
  int lock_ = -1;
  bool committed_ = false;
};

/// The identity of one run in a results file: case, engine, method and assignments.
struct RunKey {
  std::string caseName, engine, method;
  std::vector<std::string> assignments;
  bool operator==(const RunKey& other) const;
  bool operator<(const RunKey& other) const;
  std::string text() const;  ///< "case engine/method a=1 b=2"
};

/// Why `manifestPath` (a results.json or sweep.json) holds results of another plan than the
/// runs `planned`, or nullopt when it does not exist or holds exactly those runs (in any order).
/// A file that cannot be read as a pbdval results file counts as foreign (and says so).
std::optional<std::string> foreignResults(const std::string& manifestPath,
                                          const std::vector<RunKey>& planned);

}  // namespace pbdval
