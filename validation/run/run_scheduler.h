// Many runs at once, each isolated in its own child process (fork).
#pragma once

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "adapters/registry.h"
#include "validation/run/run_record.h"

namespace pbdval {

/// SIGINT or SIGTERM arrived while runs were going: they were stopped (SIGKILL), waited for,
/// and their temporary files removed. A command exits with 128 + signal().
class RunInterrupted : public std::runtime_error {
 public:
  RunInterrupted(int signal, std::size_t finished, std::size_t total);
  int signal() const { return signal_; }

 private:
  int signal_;
};

/// Runs requests each in its own child process (fork), at most `jobs` at a time, each with
/// `timeout` seconds of wall time (0 = none), so that a crash (signal) or a hang of an engine
/// becomes a status (`error` naming the signal, `timeout`) instead of taking the suite down.
/// Children report through files in `scratchFolder`. `onFinished` is called in the parent,
/// in completion order; `onTick` about every 20 ms with the requests running. SIGINT and SIGTERM
/// are taken between runs: the running children are stopped, their files removed, and
/// RunInterrupted is thrown; nothing half-written is left behind.
class RunScheduler {
 public:
  RunScheduler(const EngineRegistry& registry, int jobs, double timeout, std::string scratchFolder);
  std::vector<RunRecord> runAll(
      const std::vector<RunRequest>& requests,
      const std::function<void(const RunRecord&, std::size_t done, std::size_t total)>& onFinished,
      const std::function<void(const std::vector<const RunRequest*>& running)>& onTick = {});

 private:
  const EngineRegistry& registry_;
  int jobs_;
  double timeout_;
  std::string scratchFolder_;
};

}  // namespace pbdval
