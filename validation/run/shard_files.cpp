#include "validation/run/shard_files.h"

#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

#include "validation/io/atomic_file.h"
#include "validation/run/run_plan.h"

namespace pbdval {
namespace {

namespace fs = std::filesystem;

/// A name that is one path component: not empty, ".", "..", and without '/' or NUL.
bool plainName(const std::string& name) {
  return !name.empty() && name != "." && name != ".." &&
         name.find_first_of(std::string("/\0", 2)) == std::string::npos;
}

/// What lstat finds at `path`: 'f' a regular file, 'd' a folder, 'l' a symbolic link, '?'
/// anything else, 0 nothing.
char kindOf(const std::string& path) {
  struct stat info {};
  if (::lstat(path.c_str(), &info) != 0) return 0;
  if (S_ISLNK(info.st_mode)) return 'l';
  if (S_ISREG(info.st_mode)) return 'f';
  if (S_ISDIR(info.st_mode)) return 'd';
  return '?';
}

std::string fileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot be read");
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

}  // namespace

std::vector<ShardFile> verifiedShardFiles(const ShardResults& shard) {
  std::vector<ShardFile> files;
  std::set<std::string> taken;
  for (std::size_t k = 0; k < shard.results.runs.size(); ++k) {
    const RunRecord& run = shard.results.runs[k];
    const RunRequest& request = run.request;
    const std::string& recorded = request.trajectoryPath;
    if (recorded.empty()) continue;  // --no-trajectories
    const std::string where = shard.folder + "/results.json: runs[" + std::to_string(k) + "] (" +
                              request.caseName + " " + request.engine + "/" + request.method +
                              "): trajectory ";
    auto refuse = [&](const std::string& why) {
      // (the path is quoted as JSON would: it may hold any byte)
      throw std::invalid_argument(where + "'" + recorded + "': " + why +
                                  "; the shard is not merged");
    };
    if (recorded.find('\0') != std::string::npos) refuse("a path cannot hold a NUL character");
    if (!plainName(request.caseName) || !plainName(request.engine) || !plainName(request.method))
      refuse("the run's case, engine and method must be plain names (no '/', '.' or '..')");
    const std::string stem = request.engine + "-" + request.method;
    std::string name;
    for (const char* extension : {".csv", ".npy"}) {
      const std::string tail = "/trajectories/" + request.caseName + "/" + stem + extension;
      if (recorded.size() >= tail.size() &&
          recorded.compare(recorded.size() - tail.size(), tail.size(), tail) == 0)
        name = stem + extension;
    }
    if (name.empty())
      refuse("expected OUT/trajectories/" + request.caseName + "/" + stem +
             ".csv or .npy, the path 'pbdval run' writes for this run");
    // Resolved inside the shard, component by component, following no symbolic link.
    const std::string folder = shard.folder + "/trajectories";
    const std::string caseFolder = folder + "/" + request.caseName;
    const std::string relative = "trajectories/" + request.caseName + "/" + name;
    const std::string path = caseFolder + "/" + name;
    const bool required = isMeasured(run.status);
    bool present = true;
    for (const std::string& step : {folder, caseFolder}) {
      const char kind = kindOf(step);
      if (kind == 'l') refuse(step + " is a symbolic link; a shard's files must lie inside it");
      if (kind != 'd' && kind != 0) refuse(step + " is not a folder");
      if (kind == 0) present = false;
    }
    const char kind = present ? kindOf(path) : char(0);
    if (kind == 'l') refuse(path + " is a symbolic link; a shard's files must lie inside it");
    if (kind != 'f' && kind != 0) refuse(path + " is not a regular file");
    if (kind == 0) {
      if (required)
        refuse(path + " does not exist; a run with status " +
               std::string(runStatusName(run.status)) + " has its trajectory");
      continue;
    }
    if (!taken.insert(relative).second) refuse("the trajectory of another run too");
    files.push_back({k, path, relative, false});
    const std::vector<std::string> companions = companionPathsFor(path);
    const std::vector<std::string> companionsRelative = companionPathsFor(relative);
    for (std::size_t c = 0; c < companions.size(); ++c) {
      const char companionKind = kindOf(companions[c]);
      if (companionKind == 0) continue;
      if (companionKind != 'f')
        refuse(companions[c] + " is " +
               (companionKind == 'l' ? "a symbolic link" : "not a regular file") +
               "; a shard's files must be regular files inside it");
      files.push_back({k, companions[c], companionsRelative[c], true});
    }
  }
  return files;
}

void carryShardFiles(const std::vector<ShardFile>& files, const std::string& folder, bool move) {
  for (const ShardFile& file : files) {
    const std::string to = folder + "/" + file.relative;
    fs::create_directories(fs::path(to).parent_path());
    std::error_code renamed;
    if (move) fs::rename(file.path, to, renamed);
    if (!move || renamed)  // another file system: copy
      writeFileAtomically(to, fileBytes(file.path));
  }
}

}  // namespace pbdval
