// Isolation: every run in its own forked child process, so that a crash (signal) or a hang of
// an engine becomes a run status instead of taking the suite down.
#include "validation/run_scheduler.h"

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
#include <sstream>
#include <system_error>

#include "validation/atomic_file.h"
#include "validation/external_engine.h"
#include "validation/run_execution.h"
#include "validation/run_plan.h"

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

RunScheduler::RunScheduler(const EngineRegistry& registry, int jobs, double timeout,
                           std::string scratchFolder)
    : registry_(registry),
      jobs_(std::max(1, jobs)),
      timeout_(timeout),
      scratchFolder_(std::move(scratchFolder)) {}

namespace {

/// Blocks SIGINT and SIGTERM in the scheduling process for its lifetime, so that they are
/// taken synchronously (sigtimedwait) between runs instead of killing the scheduler halfway
/// through a bookkeeping step; the children get the previous mask back.
class InterruptBlock {
 public:
  InterruptBlock() {
    sigemptyset(&signals_);
    sigaddset(&signals_, SIGINT);
    sigaddset(&signals_, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &signals_, &previous_);
  }
  ~InterruptBlock() {
    // A signal that arrived after the last check must not be lost: leave it pending.
    pthread_sigmask(SIG_SETMASK, &previous_, nullptr);
  }
  InterruptBlock(const InterruptBlock&) = delete;
  InterruptBlock& operator=(const InterruptBlock&) = delete;

  /// Waits up to `seconds` for SIGINT or SIGTERM; returns it, or 0.
  int wait(double seconds) const {
    timespec timeout{static_cast<time_t>(seconds), static_cast<long>((seconds - std::floor(seconds)) * 1e9)};
    const int signal = sigtimedwait(&signals_, nullptr, &timeout);
    return signal > 0 ? signal : 0;
  }
  /// For a child process: the mask the scheduler started with.
  void restoreInChild() const { pthread_sigmask(SIG_SETMASK, &previous_, nullptr); }

 private:
  sigset_t signals_;
  sigset_t previous_;
};

}  // namespace

RunInterrupted::RunInterrupted(int signal, std::size_t finished, std::size_t total)
    : std::runtime_error(std::string("interrupted by ") + (signal == SIGINT ? "SIGINT" : "SIGTERM") +
                         " after " + std::to_string(finished) + " of " + std::to_string(total) +
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
  std::size_t next = 0, done = 0;
  const auto stopAll = [&](int signal) {
    for (const Child& child : running) ::kill(-child.pid, SIGKILL);
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
        const RunRecord record = executeRun(requests[next], registry_);
        try {
          writeFileAtomically(file, toJsonText(record));
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
    int status = 0;
    const pid_t finished = ::waitpid(-1, &status, WNOHANG);
    if (finished > 0) {
      for (std::size_t k = 0; k < running.size(); ++k) {
        if (running[k].pid != finished) continue;
        Child child = running[k];
        running.erase(running.begin() + static_cast<long>(k));
        // A run that ended after its limit but before the next check is over the limit all
        // the same: the limit holds to the scheduler's granularity, not 20 ms beyond it.
        const double elapsed = std::chrono::duration<double>(Clock::now() - child.start).count();
        if (timeout_ > 0 && elapsed > timeout_) child.killedForTimeout = true;
        records[child.index] = collect(child, status, requests[child.index],
                                       resultFile(scratchFolder_, child.index), timeout_);
        ++done;
        if (onFinished) onFinished(records[child.index], done, requests.size());
        break;
      }
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
