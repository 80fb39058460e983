// External engines: programs in any language joined through the process protocol v1
// (docs/external-engines.md). The runner writes the resolved scene, runs the engine's command
// with a wall-time limit, and reads back trajectory.csv and status.json; everything an engine
// gets wrong (a missing command, a non-zero exit, a malformed or truncated file, wrong rows or
// bodies, a hang) becomes the run's status with a reason, never a failure of the runner. The
// engine runs in a process group of its own, killed after every run (whatever it started ends
// with it); SIGINT, SIGTERM or SIGHUP during a run stop it and throw SignalInterrupt
// (validation/run/interrupts.h), its scratch folder removed.
#pragma once

#include <sys/types.h>

#include <memory>
#include <string>
#include <vector>

#include "adapters/engine.h"

namespace pbdval {

inline constexpr int kExternalProtocolVersion = 1;
/// The version of the serve protocol (a catalogue's `serve.protocol`): how the runner hands a
/// persistent engine process its runs.
inline constexpr int kExternalServeProtocolVersion = 1;

/// How to start one external engine: its command (argv, "{python}" already replaced), the
/// folder it runs in (its catalogue's) and, for a command that names "{python}", the folder
/// put first on the engine's PYTHONPATH (where the package pbdval is; empty: PYTHONPATH as
/// inherited).
struct ExternalCommand {
  std::vector<std::string> argv;
  std::string workingFolder;
  std::string pythonPackageFolder;
};

/// An external engine. Each run is a fresh process: the engine's command started for it
/// (single-shot), or, when the engine declares a `serve` command and `serverFolder` holds this
/// command's server for it (EngineEntry::startServer), a child the server forks for it
/// (docs/external-engines.md#persistent-engines). Either way the run is checked the same way.
struct WholeRun;

class ExternalEngine final : public Engine {
 public:
  /// `features`: the catalogue's feature table; empty when the catalogue declares none.
  ExternalEngine(std::string name, ExternalCommand command, FeatureTable features = {});
  /// With a server: runs go to the server listening in `serverFolder` (serverSocketPath), when
  /// that folder is given; else each starts `command`.
  ExternalEngine(std::string name, ExternalCommand command, FeatureTable features,
                 std::string serverFolder);

  std::string_view name() const override { return name_; }
  /// What the catalogue's feature table declares unsupported (nothing without a table): such a
  /// run is reported without starting the engine. The engine still says in its status what it
  /// lacks beyond the table (conditions only a run finds).
  std::vector<std::string> unsupported(const pbd::Scene& scene,
                                       const Method& method) const override;
  EngineRunResult run(const pbd::Scene& scene, const Method& method, const RunLength& length,
                      const StepPlan& plan, double wallTimeLimit, RunObserver& observer) override;

 private:
  /// The engine's process (or the server's child) run, its files read back and checked.
  EngineRunResult runWhole(const pbd::Scene& scene, const Method& method, const RunLength& length,
                           const StepPlan& plan, double wallTimeLimit, WholeRun& run);

  std::string name_;
  ExternalCommand command_;
  FeatureTable features_;
  std::string serverFolder_;
};

/// Where the server of engine `name` listens in `serverFolder` (a Unix socket), and
/// where its own standard error goes.
std::string serverSocketPath(const std::string& serverFolder, const std::string& name);
std::string serverLogPath(const std::string& serverFolder, const std::string& name);

/// Starts engine `name`'s server: `serve` with `--socket <serverSocketPath>` appended, in a
/// process group of its own (killed when the returned object goes, or when this process dies),
/// and waits up to `startLimit` seconds for it to accept a connection. A server that ends or
/// does not listen in time is stopped; running() is then false, and the runs sent to it are
/// errors quoting its standard error.
std::unique_ptr<EngineServer> startExternalServer(const std::string& name,
                                                  const ExternalCommand& serve,
                                                  const std::string& serverFolder,
                                                  double startLimit = 60);
/// startExternalServer without the wait: returns as soon as the process is started;
/// EngineServer::awaitListening() waits (the `startLimit` counted from here). What
/// EngineEntry::startServer does, so that servers can start side by side.
std::unique_ptr<EngineServer> launchExternalServer(const std::string& name,
                                                   const ExternalCommand& serve,
                                                   const std::string& serverFolder,
                                                   double startLimit = 60);

/// Ends what the external-engine runs of process `owner` left when `owner` was killed before
/// it could clean up (a wall-time limit or an interrupt of `pbdval run`): kills each run's
/// engine process group and removes its scratch folder ($TMPDIR/pbdval-engine-<owner>-*).
/// For the process that started `owner`, after `owner` has ended.
void removeEngineLeftovers(pid_t owner);

}  // namespace pbdval
