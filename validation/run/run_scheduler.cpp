// Isolation: every run in its own forked child process, so that a crash (signal) or a hang of
// an engine becomes a run status instead of taking the suite down.
#include "validation/run/run_scheduler.h"

#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <system_error>

#include "validation/external/external_engine.h"
#include "validation/io/atomic_file.h"
#include "validation/run/overrides.h"
#include "validation/run/run_execution.h"
#include "validation/run/run_plan.h"

namespace pbdval {
namespace {

using Clock = std::chrono::steady_clock;

struct Child {
  pid_t pid = -1;
  std::size_t index = 0;
  Clock::time_point start;
  bool killedForTimeout = false;  ///< over the wall-time limit (stopped, or ended past it)
};

std::string resultFile(const std::string& folder, std::size_t index) {
  return folder + "/run-" + std::to_string(::getpid()) + "-" + std::to_string(index) + ".json";
}

/// Removes what an unfinished child may leave: its result file and its temporary trajectory.
void removeLeftovers(const Child& child, const RunRequest& request, const std::string& file) {
  std::remove(file.c_str());
  if (!request.trajectoryPath.empty()) {
    std::vector<std::string> targets = companionPathsFor(request.trajectoryPath);
    targets.push_back(request.trajectoryPath);
    for (const std::string& target : targets) {
      const std::string temporary = target + ".tmp-" + std::to_string(child.pid);
      std::remove(temporary.c_str());
    }
  }
}

RunRecord collect(const Child& child, int waitStatus, const RunRequest& request,
                  const std::string& file, double timeout) {
  RunRecord record;
  record.request = request;
  if (child.killedForTimeout) {
    record.status = RunStatus::Timeout;
    std::ostringstream reason;
    reason << "exceeded the wall-time limit of " << timeout << " s"
           << (WIFSIGNALED(waitStatus) ? " and was stopped" : "");
    record.reason = reason.str();
  } else if (WIFSIGNALED(waitStatus)) {
    const int signal = WTERMSIG(waitStatus);
    record.status = RunStatus::Error;
    record.reason = "engine process crashed with signal " + std::to_string(signal) + " (" +
                    ::strsignal(signal) + ")";
  } else if (WIFEXITED(waitStatus) && WEXITSTATUS(waitStatus) == 0) {
    std::ifstream in(file);
    std::stringstream text;
    text << in.rdbuf();
    try {
      record = recordFromJsonText(text.str(), file);
    } catch (const std::exception& e) {
      record.status = RunStatus::Error;
      record.reason = std::string("unreadable result from the engine process: ") + e.what();
    }
  } else {
    record.status = RunStatus::Error;
    record.reason = "engine process exited with status " + std::to_string(WEXITSTATUS(waitStatus)) +
                    " without a result";
  }
  // A child that died mid-write leaves its temporary trajectory file behind; one that was
  // killed, an external engine's process group and scratch folder.
  removeLeftovers(child, request, file);
  if (child.killedForTimeout || !WIFEXITED(waitStatus) || WEXITSTATUS(waitStatus) != 0)
    removeEngineLeftovers(child.pid);
  return record;
}

}  // namespace

/// The engine servers of a scheduler (EngineEntry::startServer,
/// docs/external-engines.md#persistent-engines): one per engine, started when a run first needs
/// it and shared by every worker (a server runs several runs at a time, each in a child of its
/// own: the interpreter's start is paid once per command), restarted when it ended, all
/// stopped with the pool. A run that ended abnormally (killed, crashed) leaves the server
/// serving: its child's process group is killed by the run's engine (or by the server when the
/// run's connection closes, or by removeEngineLeftovers), never by stopping the server, which
/// may be running another worker's run. Their sockets are in a folder of their own under
/// $TMPDIR (a Unix socket path has at most 107 bytes).
class ServerPool {
 public:
  static constexpr std::size_t kMaxSocketPath = 108;  ///< sizeof(sockaddr_un::sun_path) on Linux

  ServerPool() {
    std::string pattern = (std::filesystem::temp_directory_path() /
                           ("pbdval-serve-" + std::to_string(::getpid()) + "-XXXXXX"))
                              .string();
    if (pattern.size() < 60 && ::mkdtemp(pattern.data())) folder_ = pattern;
  }
  ~ServerPool() {
    if (::getpid() != owner_) return;  // a forked copy: the servers are the scheduler's
    servers_.clear();
    if (!folder_.empty()) {
      std::error_code ignored;
      std::filesystem::remove_all(folder_, ignored);
    }
  }
  ServerPool(const ServerPool&) = delete;
  ServerPool& operator=(const ServerPool&) = delete;

  /// The server folder for a run of `engine`, its server started when needed and listening;
  /// empty when the engine has no server (or the pool has no folder: single-shot runs).
  std::string prepare(const EngineEntry& engine) {
    if (!engine.startServer || folder_.empty()) return "";
    // A socket path longer than a sockaddr_un holds (a long engine name): single-shot runs.
    if (serverSocketPath(folder_, engine.name).size() >= kMaxSocketPath) return "";
    std::unique_ptr<EngineServer>& server = servers_[engine.name];
    if (!server || !server->running()) {
      server.reset();
      server = engine.startServer(folder_);
    }
    server->awaitListening();
    return folder_;
  }

 private:
  pid_t owner_ = ::getpid();
  std::string folder_;
  std::map<std::string, std::unique_ptr<EngineServer>> servers_;
};

RunScheduler::RunScheduler(const EngineRegistry& registry, int jobs, double timeout,
                           std::string scratchFolder)
    : registry_(registry),
      jobs_(std::max(1, jobs)),
      timeout_(timeout),
      scratchFolder_(std::move(scratchFolder)) {}

namespace {

/// Blocks SIGINT and SIGTERM in the scheduling process for its lifetime, so that they are
/// taken synchronously (sigtimedwait) between runs instead of killing the scheduler halfway
/// through a bookkeeping step; the children get the previous mask back. SIGCHLD is blocked
/// too and wakes wait() when a run's process ends: the scheduler collects it at once instead
/// of at its next 20 ms check (10 ms of idle wall time per run on average, more than the
/// stepping of a 1,000-step run; docs/benchmarks.md#outside-the-stepping).
class InterruptBlock {
 public:
  InterruptBlock() {
    sigemptyset(&signals_);
    sigaddset(&signals_, SIGINT);
    sigaddset(&signals_, SIGTERM);
    wakeups_ = signals_;
    sigaddset(&wakeups_, SIGCHLD);
    pthread_sigmask(SIG_BLOCK, &wakeups_, &previous_);
  }
  ~InterruptBlock() {
    // A signal that arrived after the last check must not be lost: leave it pending.
    pthread_sigmask(SIG_SETMASK, &previous_, nullptr);
  }
  InterruptBlock(const InterruptBlock&) = delete;
  InterruptBlock& operator=(const InterruptBlock&) = delete;

  /// Waits up to `seconds` for SIGINT or SIGTERM, or for a child's end (SIGCHLD, taken: a
  /// child that ends after it is taken and before the next wait leaves another pending).
  /// Returns SIGINT or SIGTERM, or 0.
  int wait(double seconds) const {
    timespec timeout{static_cast<time_t>(seconds),
                     static_cast<long>((seconds - std::floor(seconds)) * 1e9)};
    const int signal = sigtimedwait(seconds > 0 ? &wakeups_ : &signals_, nullptr, &timeout);
    return signal > 0 && signal != SIGCHLD ? signal : 0;
  }
  /// For a child process: the mask the scheduler started with.
  void restoreInChild() const { pthread_sigmask(SIG_SETMASK, &previous_, nullptr); }

 private:
  sigset_t signals_;  ///< SIGINT, SIGTERM
  sigset_t wakeups_;  ///< and SIGCHLD
  sigset_t previous_;
};

}  // namespace

RunInterrupted::RunInterrupted(int signal, std::size_t finished, std::size_t total)
    : std::runtime_error(std::string("interrupted by ") +
                         (signal == SIGINT ? "SIGINT" : "SIGTERM") + " after " +
                         std::to_string(finished) + " of " + std::to_string(total) +
                         " runs: the running ones were stopped and their files removed"),
      signal_(signal) {}

std::vector<RunRecord> RunScheduler::runAll(
    const std::vector<RunRequest>& requests,
    const std::function<void(const RunRecord&, std::size_t, std::size_t)>& onFinished,
    const std::function<void(const std::vector<const RunRequest*>&)>& onTick) {
  const InterruptBlock interrupts;
  createFolders(scratchFolder_);
  std::vector<RunRecord> records(requests.size());
  std::vector<Child> running;
  ServerPool servers;
  std::map<std::string, std::string> caseReferenceEngines;  ///< case file → referenceEngineOf
  std::size_t next = 0, done = 0;
  const auto stopAll = [&](int signal) {
    for (const Child& child : running)
      ::kill(-child.pid, SIGKILL);
    for (const Child& child : running) {
      int status = 0;
      ::waitpid(child.pid, &status, 0);
      removeLeftovers(child, requests[child.index], resultFile(scratchFolder_, child.index));
      removeEngineLeftovers(child.pid);
    }
    std::error_code ignored;
    std::filesystem::remove(scratchFolder_, ignored);  // only if empty
    throw RunInterrupted(signal, done, requests.size());
  };
  while (done < requests.size()) {
    while (static_cast<int>(running.size()) < jobs_ && next < requests.size()) {
      std::string serverFolder;
      try {
        serverFolder = servers.prepare(registry_.engine(requests[next].engine));
        // An engine reference (--reference METHOD, or the case's of type "engine") runs in
        // the same command: its engine's server too (one folder, a socket per engine). The
        // case's is read once per case file.
        const RunRequest& request = requests[next];
        const auto known = request.referenceMode.empty()
                               ? caseReferenceEngines.find(request.caseFile)
                               : caseReferenceEngines.end();
        const std::string referenceEngine = known != caseReferenceEngines.end()
                                                ? known->second
                                                : referenceEngineOf(request, registry_);
        if (request.referenceMode.empty()) caseReferenceEngines[request.caseFile] = referenceEngine;
        if (!referenceEngine.empty()) {
          const std::string referenceFolder = servers.prepare(registry_.engine(referenceEngine));
          if (serverFolder.empty()) serverFolder = referenceFolder;
        }
      } catch (const std::exception&) {
        // an unknown engine or reference, an unreadable case: the run says so
      }
      std::fflush(nullptr);  // nothing buffered may be written twice
      const std::string file = resultFile(scratchFolder_, next);
      const pid_t scheduler = ::getpid();
      const pid_t pid = ::fork();
      if (pid < 0) throw std::runtime_error(std::string("fork failed: ") + std::strerror(errno));
      if (pid == 0) {
        // Its own process group, so that stopping it also stops what it started (an external
        // engine's process).
        ::setpgid(0, 0);
        // A scheduler killed outright (SIGKILL) takes its runs with it, and they their
        // external engines (PR_SET_PDEATHSIG there too), instead of leaving them running.
        ::prctl(PR_SET_PDEATHSIG, SIGKILL);
        if (::getppid() != scheduler) ::_exit(4);  // the scheduler died before prctl
        interrupts.restoreInChild();
        // Nothing may unwind out of here: the scheduler's objects (its servers) are not this
        // process's to destroy.
        try {
          EngineOptions options = registry_.options();
          options.serverFolder = serverFolder;
          const RunRecord record = executeRun(requests[next], registry_.withOptions(options));
          // A scratch file, read by the scheduler once this process has exited and removed:
          // the rename keeps a crashed run from leaving half a record; no fsync.
          writeFileAtomically(file, toJsonText(record), Durability::ProcessCrash);
        } catch (...) {
          ::_exit(3);
        }
        ::_exit(0);
      }
      ::setpgid(pid, pid);  // also here: whichever of the two runs first
      running.push_back({pid, next, Clock::now(), false});
      ++next;
    }
    if (const int signal = interrupts.wait(0)) stopAll(signal);
    // Each run's child by its pid: the workers' engine servers are children too, reaped by
    // the pool alone.
    int status = 0;
    std::size_t finished = running.size();
    for (std::size_t k = 0; k < running.size() && finished == running.size(); ++k)
      if (::waitpid(running[k].pid, &status, WNOHANG) == running[k].pid) finished = k;
    if (finished < running.size()) {
      Child child = running[finished];
      running.erase(running.begin() + static_cast<long>(finished));
      // A run that ended after its limit but before the next check is over the limit all
      // the same: the limit holds to the scheduler's granularity, not 20 ms beyond it.
      const double elapsed = std::chrono::duration<double>(Clock::now() - child.start).count();
      if (timeout_ > 0 && elapsed > timeout_) child.killedForTimeout = true;
      records[child.index] = collect(child, status, requests[child.index],
                                     resultFile(scratchFolder_, child.index), timeout_);
      ++done;
      if (onFinished) onFinished(records[child.index], done, requests.size());
      continue;
    }
    for (Child& child : running) {
      const double elapsed = std::chrono::duration<double>(Clock::now() - child.start).count();
      if (timeout_ > 0 && elapsed > timeout_ && !child.killedForTimeout) {
        ::kill(-child.pid, SIGKILL);
        child.killedForTimeout = true;
      }
    }
    if (onTick) {
      std::vector<const RunRequest*> active;
      for (const Child& child : running)
        active.push_back(&requests[child.index]);
      onTick(active);
    }
    if (const int signal = interrupts.wait(0.02)) stopAll(signal);
  }
  std::error_code ignored;
  std::filesystem::remove(scratchFolder_, ignored);  // only if empty
  return records;
}

}  // namespace pbdval
