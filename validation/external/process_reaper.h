// Ends every process an external engine started, wherever it went. Killing the engine's
// process group reaches what stayed in it; a process that left it (setsid(), a daemon's double
// fork, a new process group) is found by a mark in its environment that every descendant
// inherits: PBDVAL_ENGINE_RUN=<pid>-<counter>-<nanoseconds>, one value per engine run.
//
// Used by the external-engine launcher (validation/external/external_engine.cpp runProcess): a
// reaper is made before the fork, mark() is called in the child before exec, and killRemaining()
// after the engine was reaped. While the reaper lives, this process is a child subreaper
// (PR_SET_CHILD_SUBREAPER), so the engine's orphans are re-parented to it rather than to init,
// and the ones it kills are reaped here instead of staying zombies.
#pragma once

#include <sys/types.h>

#include <string>

namespace pbdval {

class ProcessReaper {
 public:
  /// The environment variable that carries the mark.
  static constexpr const char* kVariable = "PBDVAL_ENGINE_RUN";

  ProcessReaper();
  /// Restores the subreaper setting this process had before.
  ~ProcessReaper();
  ProcessReaper(const ProcessReaper&) = delete;
  ProcessReaper& operator=(const ProcessReaper&) = delete;

  /// In the forked child, before exec: sets the mark in its environment.
  void mark() const;

  /// Sends SIGKILL to every process that carries this reaper's mark (other than this one), and
  /// again to what they started meanwhile, until none is left or 2 s have passed; reaps those
  /// that are this process's children, except `engine` (the engine's own process, which the
  /// caller reaps for its exit status). Call it before the engine is reaped: a zombie engine
  /// keeps its process group id, and its orphans are this subreaper's children to reap. Returns
  /// how many processes it killed.
  int killRemaining(pid_t engine) const;

  /// The mark's value, for a process that must end the engine's processes after this one
  /// died (the scheduler, when a run's worker was killed: killProcessesMarked).
  const std::string& value() const { return value_; }

 private:
  std::string value_;
  int previousSubreaper_ = 0;
};

/// Sends SIGKILL to every process that carries the mark `value` (ProcessReaper::value) until none
/// is left or 2 s have passed, without reaping any. Returns how many it killed.
int killProcessesMarked(const std::string& value);

}  // namespace pbdval
