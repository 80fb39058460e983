// Many runs at once, each isolated in its own child process (fork).
#pragma once

#include <sys/types.h>

#include <functional>
#include <map>
#include <memory>
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

/// The engine servers of a command (EngineEntry::startServer,
/// docs/external-engines.md#persistent-engines): one per engine, started when a run first needs
/// it (or earlier, by launch(), while the command still reads its cases) and shared by every
/// worker (a server runs several runs at a time, each in a child of its own: the interpreter's
/// start is paid once per command), restarted when it ended, all stopped with the pool. A run
/// that ended abnormally (killed, crashed) leaves the server serving: its child's process group
/// is killed by the run's engine (or by the server when the run's connection closes, or by
/// removeEngineLeftovers), never by stopping the server, which may be running another worker's
/// run. Their sockets are in a folder of their own under $TMPDIR, or under /tmp when $TMPDIR's
/// path is too long for a socket's (a Unix socket path has at most 107 bytes); the folder holds
/// only the sockets and the servers' standard error, and goes with the pool.
class ServerPool {
 public:
  static constexpr std::size_t kMaxSocketPath = 108;  ///< sizeof(sockaddr_un::sun_path) on Linux
  /// The longest server folder: leaves 47 bytes for "/<engine name>.socket".
  static constexpr std::size_t kMaxFolderPath = 60;

  ServerPool();
  ~ServerPool();
  ServerPool(const ServerPool&) = delete;
  ServerPool& operator=(const ServerPool&) = delete;

  /// Starts the server of `engine` unless it runs already, without waiting for it to listen
  /// (its interpreter's imports overlap what the command does meanwhile); nothing for an
  /// engine without a server.
  void launch(const EngineEntry& engine);
  /// The server folder for a run of `engine`, its server started when needed and listening;
  /// empty when the engine has no server (or the pool has no folder: single-shot runs).
  std::string prepare(const EngineEntry& engine);

 private:
  /// Whether `engine` runs through a server of this pool.
  bool serves(const EngineEntry& engine) const;

  pid_t owner_;
  std::string folder_;
  std::map<std::string, std::unique_ptr<EngineServer>> servers_;
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
  /// `servers`: the command's engine servers, when it started some already (ServerPool::launch);
  /// null: runAll starts its own when a run needs one.
  RunScheduler(const EngineRegistry& registry, int jobs, double timeout, std::string scratchFolder,
               ServerPool* servers = nullptr);
  std::vector<RunRecord> runAll(
      const std::vector<RunRequest>& requests,
      const std::function<void(const RunRecord&, std::size_t done, std::size_t total)>& onFinished,
      const std::function<void(const std::vector<const RunRequest*>& running)>& onTick = {});

 private:
  const EngineRegistry& registry_;
  int jobs_;
  double timeout_;
  std::string scratchFolder_;
  ServerPool* servers_;
};

}  // namespace pbdval
