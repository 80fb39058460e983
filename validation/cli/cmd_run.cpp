// pbdval run [CASES or folders ...] [--engines LIST] [--methods LIST] [--out DIR] [--jobs N]
//            [--timeout S] [--set KEY=VALUE ...] [--no-trajectories] [--strict] [--quiet]
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <thread>

#include "pbdval/build_info.h"
#include "validation/cli/args.h"
#include "validation/cli/commands.h"
#include "validation/cli/executors.h"
#include "validation/io/atomic_file.h"
#include "validation/io/results.h"
#include "validation/io/results_folder.h"
#include "validation/io/sha256.h"
#include "validation/run/case_library.h"
#include "validation/run/interrupts.h"
#include "validation/run/overrides.h"
#include "validation/run/run_plan.h"
#include "validation/run/run_scheduler.h"
#include "validation/run/sharding.h"
#include "validation/run/simulation.h"
#include "validation/verdict/summary.h"

namespace pbdval::cli {
namespace {

ArgParser runParser() {
  ArgParser parser(
      "run", "[CASES or folders ...] [options]",
      "Runs every case in every engine with each engine's default method (or the case's\n"
      "Validation.methods), each run isolated in its own process, and computes the metrics.\n"
      "Writes DIR/results.json (docs/results.md) and DIR/trajectories/CASE/ENGINE-METHOD.csv\n"
      "(or .npy: --trajectory-format), and prints a summary table. A run that diverges, times\n"
      "out, crashes or lacks a feature gets that status; the others still complete.");
  parser.positionals("CASES", "scene files or folders of them (default: cases/)", 0, -1)
      .option("engines", "LIST",
              "comma-separated engines; 'default' stands for those run when none is named "
              "(default: those; 'pbdval methods' marks the others 'by name only')")
      .option("methods", "LIST",
              "comma-separated methods (default: each case's, else each engine's default)")
      .option("out", "DIR",
              "output folder (default: out); written as one transaction, locked while the run "
              "goes (docs/cli.md#results-folders)")
      .flag("force", "replace the results of another plan that --out holds")
      .option("jobs", "N", "runs in parallel, 1 to 1024 (default: the number of cores)")
      .option("timeout", "S", "wall-time limit per run in seconds (default: 600; 0: none)")
      .option("set", "KEY=VALUE",
              "a method parameter or Simulation setting for every run; every run of the plan "
              "must honour it",
              true)
      .option("reference", "case|none|fine|METHOD[:KEY=VALUE,...]",
              "what every run is measured against: case (default) the case's "
              "Validation.reference; none; fine the same method at h/16; a method: its run of "
              "the same scene at the same step with these parameters (the converged reference: "
              "drake.rk3:targetAccuracy=1e-10, docs/convergence.md)")
      .option("shard", "K/N",
              "run only the K-th of N slices of the plan (batch schedulers; join the folders "
              "with 'pbdval merge', docs/cluster.md)")
      .option("executor", "local|dask",
              "where the runs execute: local (default: isolated processes on this machine) or "
              "dask (a Dask cluster: --scheduler or --scheduler-file; docs/cluster.md)")
      .option("scheduler", "ADDRESS", "the Dask scheduler, e.g. tcp://10.0.0.5:8786")
      .option("scheduler-file", "FILE",
              "the Dask scheduler's file (dask scheduler --scheduler-file)")
      .option("connect-timeout", "S", "dask: seconds to reach the scheduler (default 10)")
      .option("runs-per-task", "N", "dask: runs per task (default 1)")
      .flag("list-plan", "print the plan (its size, digest and runs) as JSON and run nothing")
      .option("fail-with", "REASON",
              "with --shard: record every run of the shard as status error with REASON, without "
              "running it (for executors that lost a run)")
      .flag("no-trajectories", "do not write trajectory files")
      .option("trajectory-format", "csv|npy",
              "trajectories as CSV text (default) or NPY (float64, the same rows and columns; "
              "no text conversion, numpy.load reads it)")
      .flag("strict", "treat scene warnings as errors")
      .flag("quiet", "no progress, only the summary")
      .epilog(
          "exit status: 0 when results.json was written (statuses are data; 'pbdval gate'\n"
          "judges them), 2 on bad usage, a busy --out or one holding another plan's results,\n"
          "128+N on signal N (the previous results stay as they were).\n"
          "example: pbdval run cases/joint_hinge.json cases/chain_10.json --engines pbd,ode --jobs "
          "2");
  return parser;
}

/// The largest --jobs: beyond it a machine runs out of processes long before it runs faster.
constexpr std::int64_t kMaxJobs = 1024;

/// `path` under `from` as the same path under `to`.
std::string rebase(const std::string& path, const std::string& from, const std::string& to) {
  return path.rfind(from + "/", 0) == 0 ? to + path.substr(from.size()) : path;
}

std::string withoutTrailingSlashes(std::string folder) {
  while (folder.size() > 1 && folder.back() == '/')
    folder.pop_back();
  return folder;
}

std::string clock(double seconds) {
  char text[16];
  std::snprintf(text, sizeof text, "%02d:%02d", int(seconds) / 60, int(seconds) % 60);
  return text;
}

}  // namespace

int runCommand(const Context& context, const Arguments& arguments) {
  const ArgParser parser = runParser();
  ParsedArgs args;
  if (const auto exit = parser.parseOrExit(arguments, args)) return *exit;
  const bool quiet = args.flags.count("quiet") > 0;
  PlanOptions options;
  RunPlan plan;
  std::optional<ShardInfo> shard;
  std::string wholePlanDigest;
  int jobs = 1;
  double timeout = kDefaultWallTimeLimit;
  // While servers run before the scheduler takes over, SIGINT, SIGTERM and SIGHUP wait (the
  // watch outlives the pool: a signal still pending when the command returns early is
  // delivered after the servers were stopped and their folder removed).
  std::optional<InterruptWatch> interruptsWhilePlanning;
  std::optional<ServerPool> servers;  // before anything that may return: it stops them
  try {
    options.engines = withDefaultEnginesExpanded(args.list("engines"), context.engines);
    options.methods = args.list("methods");
    checkNames(context.engines, "--engines", options.engines);
    checkNames(context.engines, "--methods", options.methods);
    options.assignments = args.values("set");
    const std::string reference = args.value("reference", "case");
    if (reference != "case" && reference != "none" && reference != "fine")
      parseEngineReference(reference, context.engines);  // throws naming what was expected
    options.referenceMode = reference == "case" ? "" : reference;
    options.outFolder = withoutTrailingSlashes(args.value("out", "out"));
    options.writeTrajectories = !args.flags.count("no-trajectories");
    const std::string format = args.value("trajectory-format", "csv");
    if (format != "csv" && format != "npy")
      throw UsageError("--trajectory-format: expected csv or npy, got '" + format + "'");
    options.trajectoryFormat = format == "npy" ? TrajectoryFormat::Npy : TrajectoryFormat::Csv;
    options.strictScene = args.flags.count("strict") > 0;
    jobs =
        int(args.integerIn("jobs", std::max(1u, std::thread::hardware_concurrency()), 1, kMaxJobs));
    timeout = args.number("timeout", kDefaultWallTimeLimit);
    if (timeout < 0) throw UsageError("--timeout: expected seconds ≥ 0");
    const std::vector<std::string> paths =
        args.positionals.empty() ? std::vector<std::string>{defaultCaseFolder()} : args.positionals;
    if (wantsDask(args)) return runOnDask("run", arguments);
    // The servers of the engines named (--engines, and those of --methods) start now, while the
    // cases are read and the plan is made: their interpreters' start (0.1-0.15 s of imports)
    // overlaps that instead of following it (docs/benchmarks.md#fourth-pass). A server the plan
    // turns out not to use is stopped with the pool.
    if (!args.flags.count("list-plan") && !args.has("fail-with")) {
      std::vector<std::string> named = options.engines;
      for (const std::string& method : options.methods)
        named.push_back(context.engines.method(method).engine);
      for (const std::string& name : named)
        if (context.engines.engine(name).startServer) {
          if (!servers) {
            interruptsWhilePlanning.emplace();
            servers.emplace();
          }
          servers->launch(context.engines.engine(name));
        }
    }
    const std::vector<std::string> caseFiles = collectCaseFiles(paths);
    plan = planRuns(caseFiles, options, context.engines);
    // Every --set must mean something in every run, with a value it accepts: checked here, not
    // found as an `error` in every run minutes later.
    std::vector<std::string> methods;
    for (const RunRequest& r : plan.requests)
      if (std::find(methods.begin(), methods.end(), r.method) == methods.end())
        methods.push_back(r.method);
    checkAssignments(options.assignments, methods, context.engines);
    if (args.flags.count("list-plan")) {
      printPlan(plan);
      return 0;
    }
    wholePlanDigest = runsDigest(plan);
    if (args.has("shard")) {
      ShardInfo info = parseShard(args.value("shard"));
      plan = shardOf(plan, info);
      shard = info;
    }
    std::vector<NamedPath> inputs;
    for (const std::string& file : caseFiles)
      inputs.push_back({"the case", file});
    checkOutputsAreNotInputs({{"--out", options.outFolder + "/results.json"}}, inputs);
  } catch (...) {
    return parser.exitForCurrentException();
  }

  // The output folder: locked, staged, and another plan's results never replaced silently.
  std::optional<ResultsFolder> folder;
  try {
    folder.emplace(options.outFolder, "pbdval run");
    std::vector<RunKey> planned;
    for (const RunRecord& u : plan.unreadable)
      planned.push_back({u.request.caseName, u.request.engine, u.request.method, {}});
    for (const RunRequest& r : plan.requests)
      planned.push_back({r.caseName, r.engine, r.method, r.assignments});
    const std::string previous = options.outFolder + "/results.json";
    if (const auto why = foreignResults(previous, planned); why && !args.flags.count("force"))
      return parser.inputError(previous + ": " + *why +
                               "; running would replace them: give another --out, or --force "
                               "to replace them");
  } catch (const std::exception& e) {
    return parser.inputError(e.what());
  }
  for (RunRequest& r : plan.requests)
    r.trajectoryPath = rebase(r.trajectoryPath, options.outFolder, folder->staging());

  std::ostringstream command;
  command << "pbdval run";
  for (const std::string& a : arguments)
    command << ' ' << a;
  ResultsFile results;
  results.metadata = currentMetadata(command.str());
  results.metadata.shard = shard;
  results.metadata.planDigest = wholePlanDigest;

  const bool terminal = !quiet && ::isatty(STDERR_FILENO);
  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  if (!quiet)
    std::fprintf(
        stderr, "pbdval run: %zu runs%s, %d in parallel, timeout %g s, output in %s/\n",
        plan.requests.size(),
        shard ? (" (shard " + std::to_string(shard->index) + "/" + std::to_string(shard->count) +
                 " of " + std::to_string(shard->planSize) + ")")
                    .c_str()
              : "",
        jobs, timeout, options.outFolder.c_str());
  for (const RunRecord& r : plan.unreadable)
    if (!quiet)
      std::fprintf(stderr, "  %s: error: %s\n", r.request.caseName.c_str(), r.reason.c_str());

  if (interruptsWhilePlanning) {
    // The scheduler takes the interrupts from here (and its runs must not inherit the watch's
    // mask). One that came while the plan was made ends the command as it would have then,
    // the servers stopped first.
    const int signal = interruptsWhilePlanning->pending();
    if (signal) servers.reset();
    interruptsWhilePlanning.reset();
    if (signal) ::raise(signal);
  }
  RunScheduler scheduler(context.engines, jobs, timeout, folder->staging() + "/.scratch",
                         servers ? &*servers : nullptr);
  int tick = 0;
  std::vector<RunRecord> records;
  if (args.has("fail-with"))
    records = failedRecords(plan.requests, args.value("fail-with"));
  else
    records = scheduler.runAll(
        plan.requests,
        [&](const RunRecord& r, std::size_t done, std::size_t total) {
          if (quiet) return;
          if (terminal) std::fprintf(stderr, "\r\033[K");
          if (!terminal || r.status != RunStatus::Ok)
            std::fprintf(stderr, "[%3zu/%zu] %s %-34s %-26s %s%s%s\n", done, total,
                         clock(elapsed()).c_str(), r.request.caseName.c_str(),
                         runLabel(r.request).c_str(), runStatusName(r.status),
                         r.reason.empty() ? "" : ": ", r.reason.substr(0, 100).c_str());
        },
        [&](const std::vector<const RunRequest*>& running) {
          if (!terminal || running.empty()) return;
          if (++tick % 10) return;  // redraw every ~0.2 s
          std::string names;
          for (const RunRequest* r : running)
            names += (names.empty() ? "" : ", ") + r->caseName + " " + runLabel(*r);
          if (names.size() > 90) names = names.substr(0, 87) + "...";
          std::fprintf(stderr, "\r\033[K  %s running: %s", clock(elapsed()).c_str(), names.c_str());
        });
  if (terminal) std::fprintf(stderr, "\r\033[K");
  std::filesystem::remove_all(folder->staging() + "/.scratch");
  for (RunRecord& r : records)
    r.request.trajectoryPath = folder->finalPath(r.request.trajectoryPath);

  // Each case file's hash: the gate refuses results run from another version of a case than the
  // one its baseline pins (docs/gate.md).
  for (const auto& [name, entry] : plan.cases)
    results.cases[name] = {entry.first, entry.second.description, entry.second.checks,
                           entry.second.tolerances, fileSha256(entry.first).value_or("")};
  // A case that could not be read still has its entry (no checks): results.json then reads back,
  // and the gate reports the run's error instead of refusing the file.
  for (const RunRecord& u : plan.unreadable)
    results.cases.emplace(u.request.caseName,
                          CaseGateData{u.request.caseFile,
                                       "could not be read: " + u.reason,
                                       {},
                                       {},
                                       fileSha256(u.request.caseFile).value_or("")});
  results.runs = plan.unreadable;
  results.runs.insert(results.runs.end(), records.begin(), records.end());
  const std::string resultsPath = options.outFolder + "/results.json";
  try {
    writeResults(folder->staging() + "/results.json", results);
    folder->commit({"trajectories", "results.json"}, "results.json");
  } catch (const std::exception& e) {
    return parser.inputError(e.what());
  }
  printSummaryTable(std::cout, results.runs);
  std::printf("%s in %s; results in %s\n", statusCounts(results.runs).c_str(),
              clock(elapsed()).c_str(), resultsPath.c_str());
  return 0;
}

}  // namespace pbdval::cli
