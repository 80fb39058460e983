#include "validation/io/results_folder.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <system_error>
#include <tuple>

#include "validation/io/atomic_file.h"
#include "validation/io/json_input.h"

namespace pbdval {
namespace {

namespace fs = std::filesystem;

constexpr const char* kLockName = ".pbdval.lock";
constexpr const char* kStagingPrefix = ".pbdval-staging-";

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw std::runtime_error(path + ": " + what);
}

bool exists(const std::string& path) {
  std::error_code error;
  return fs::symlink_status(path, error).type() != fs::file_type::not_found && !error;
}

/// What the lock file says about its holder: "another pbdval run is writing here (pid 123)".
/// The file holds "PID COMMAND" (written by the holder once it has the lock).
std::string holderOf(int descriptor) {
  char text[256] = {};
  const ssize_t read = ::pread(descriptor, text, sizeof text - 1, 0);
  std::string line = read > 0 ? std::string(text, std::size_t(read)) : "";
  line = line.substr(0, line.find('\n'));
  const std::size_t space = line.find(' ');
  if (space == std::string::npos || space == 0)
    return "another pbdval command is writing here (pid unknown)";
  return "another " + line.substr(space + 1) + " is writing here (pid " + line.substr(0, space) +
         ")";
}

}  // namespace

ResultsFolder::ResultsFolder(std::string folder, const std::string& command)
    : folder_(std::move(folder)) {
  if (folder_.empty()) fail("(empty path)", "expected a folder name");
  while (folder_.size() > 1 && folder_.back() == '/')
    folder_.pop_back();
  // The folders this command creates, so that an aborted command removes them again.
  for (fs::path p = folder_; !p.empty() && !exists(p.string()); p = p.parent_path()) {
    created_.insert(created_.begin(), p.string());
    if (p == p.parent_path()) break;
  }
  createFolders(folder_);
  const std::string lockPath = folder_ + "/" + kLockName;
  lock_ = ::open(lockPath.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0666);
  if (lock_ < 0) {
    const std::string reason = std::strerror(errno);
    for (auto it = created_.rbegin(); it != created_.rend(); ++it)
      ::rmdir(it->c_str());
    fail(folder_, "cannot create files in this folder (" + reason + ")");
  }
  if (::flock(lock_, LOCK_EX | LOCK_NB) != 0) {
    const std::string holder = holderOf(lock_);
    ::close(lock_);
    lock_ = -1;
    throw FolderBusy(folder_ + ": " + holder + "; wait for it to finish, or give another --out");
  }
  const std::string text = std::to_string(::getpid()) + " " + command + "\n";
  if (::ftruncate(lock_, 0) != 0 || ::pwrite(lock_, text.data(), text.size(), 0) < 0) {
    // The lock holds without its text; a second command would only not know who holds it.
  }
  // Staging folders of commands that were killed (SIGKILL, a crash): nobody holds them now.
  std::error_code error;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder_, error))
    if (entry.path().filename().string().rfind(kStagingPrefix, 0) == 0)
      fs::remove_all(entry.path(), error);
  try {
    staging_ = folder_ + "/" + kStagingPrefix + std::to_string(::getpid());
    createFolders(staging_);
  } catch (...) {
    staging_.clear();
    ::close(lock_);
    throw;
  }
}

ResultsFolder::~ResultsFolder() {
  if (!committed_ && !staging_.empty()) {
    std::error_code error;
    fs::remove_all(staging_, error);
  }
  if (!committed_ && !created_.empty()) {
    // Nothing was written: leave no folder behind that this command made.
    ::unlink((folder_ + "/" + kLockName).c_str());
    for (auto it = created_.rbegin(); it != created_.rend(); ++it)
      ::rmdir(it->c_str());
  }
  if (lock_ >= 0) ::close(lock_);
}

std::string ResultsFolder::finalPath(const std::string& stagedPath) const {
  const std::string prefix = staging_ + "/";
  if (stagedPath.rfind(prefix, 0) != 0) return stagedPath;
  return folder_ + "/" + stagedPath.substr(prefix.size());
}

void ResultsFolder::commit(const std::vector<std::string>& entries, const std::string& manifest) {
  if (committed_) fail(folder_, "already committed");
  const std::string oldManifest = folder_ + "/" + manifest;
  // 1. The previous manifest goes first: from here on nothing in the folder gates as it.
  if (exists(oldManifest) && ::unlink(oldManifest.c_str()) != 0)
    fail(oldManifest,
         std::string("cannot remove the previous results (") + std::strerror(errno) + ")");
  // 2. The other entries: the previous ones moved into the staging folder (removed with it),
  //    the staged ones into place.
  for (const std::string& entry : entries) {
    if (entry == manifest) continue;
    const std::string target = folder_ + "/" + entry;
    const std::string staged = staging_ + "/" + entry;
    if (exists(target)) {
      const std::string replaced = staging_ + "/.replaced-" + entry;
      if (::rename(target.c_str(), replaced.c_str()) != 0)
        fail(target,
             std::string("cannot move the previous files aside (") + std::strerror(errno) + ")");
    }
    if (exists(staged) && ::rename(staged.c_str(), target.c_str()) != 0)
      fail(target,
           std::string("cannot move the new files into place (") + std::strerror(errno) + ")");
  }
  // 3. The new manifest last.
  const std::string stagedManifest = staging_ + "/" + manifest;
  if (::rename(stagedManifest.c_str(), oldManifest.c_str()) != 0)
    fail(oldManifest,
         std::string("cannot move the new results into place (") + std::strerror(errno) + ")");
  committed_ = true;
  std::error_code error;
  fs::remove_all(staging_, error);
}

bool RunKey::operator==(const RunKey& other) const {
  return caseName == other.caseName && engine == other.engine && method == other.method &&
         assignments == other.assignments;
}

bool RunKey::operator<(const RunKey& other) const {
  return std::tie(caseName, engine, method, assignments) <
         std::tie(other.caseName, other.engine, other.method, other.assignments);
}

std::string RunKey::text() const {
  std::string t = caseName + " " + engine + "/" + method;
  for (const std::string& a : assignments)
    t += " " + a;
  return t;
}

std::optional<std::string> foreignResults(const std::string& manifestPath,
                                          const std::vector<RunKey>& planned) {
  if (!exists(manifestPath)) return std::nullopt;
  std::vector<RunKey> held;
  try {
    std::ifstream in(manifestPath, std::ios::binary);
    if (!in) return "it cannot be read";
    std::ostringstream text;
    text << in.rdbuf();
    // Only each run's key is kept (results.json's runs, sweep.json's points[].run), read as the
    // parser streams them: a results.json of 10,000 runs is never held whole.
    std::map<std::string, std::vector<RunKey>> keys;  // by top-level key: "runs", "points"
    std::map<std::string, std::string> problems;      // the first bad element's, by the same
    const auto keyOf = [](const nlohmann::json& r) {
      return RunKey{r.at("case").get<std::string>(), r.at("engine").get<std::string>(),
                    r.at("method").get<std::string>(),
                    r.value("assignments", std::vector<std::string>{})};
    };
    const nlohmann::json document = parseJsonTextStreaming(
        text.str(), manifestPath, {"runs", "points"},
        [&](const std::string& key) {
          keys[key].clear();
          problems.erase(key);
        },
        [&](const std::string& key, std::size_t, nlohmann::json& element) {
          if (problems.count(key)) return;
          try {
            keys[key].push_back(keyOf(key == "runs" ? element : element.at("run")));
          } catch (const std::exception& e) {
            problems[key] = e.what();
          }
        });
    const std::string key = document.contains("runs") ? "runs" : "points";
    if (!document.contains(key)) document.at(key);  // throws: neither
    if (!document.at(key).is_array()) throw std::invalid_argument(key + " is not an array");
    if (problems.count(key)) throw std::invalid_argument(problems.at(key));
    held = std::move(keys[key]);
  } catch (const std::exception& e) {
    return std::string("it is not a pbdval results file (") + e.what() + ")";
  }
  std::vector<RunKey> wanted = planned;
  // The order of the --set assignments does not change a run (each key is given once).
  for (std::vector<RunKey>* keys : {&held, &wanted})
    for (RunKey& key : *keys)
      std::sort(key.assignments.begin(), key.assignments.end());
  std::sort(held.begin(), held.end());
  std::sort(wanted.begin(), wanted.end());
  if (held == wanted) return std::nullopt;
  std::vector<RunKey> onlyHeld, onlyWanted;
  std::set_difference(held.begin(), held.end(), wanted.begin(), wanted.end(),
                      std::back_inserter(onlyHeld));
  std::set_difference(wanted.begin(), wanted.end(), held.begin(), held.end(),
                      std::back_inserter(onlyWanted));
  std::ostringstream why;
  why << "it holds " << held.size() << (held.size() == 1 ? " run" : " runs")
      << " of another plan (this command makes " << wanted.size() << ")";
  if (!onlyHeld.empty())
    why << "; e.g. " << onlyHeld.front().text() << " is not in this command's plan";
  else if (!onlyWanted.empty())
    why << "; e.g. " << onlyWanted.front().text() << " is not in the file";
  return why.str();
}

}  // namespace pbdval
