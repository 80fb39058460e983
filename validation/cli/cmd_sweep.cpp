// pbdval sweep CASE --param NAME=v1,v2,... [--param ...] [--methods LIST] [--metric NAME]
//                   [--reference fine|case|METHOD[:KEY=VALUE,...]] [--out DIR] [--jobs N]
//                   [--timeout S]
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>
#include <thread>

#include "validation/cli/args.h"
#include "validation/cli/commands.h"
#include "validation/cli/executors.h"
#include "validation/cli/python_module.h"
#include "validation/external/standard_engines.h"
#include "validation/io/atomic_file.h"
#include "validation/io/results.h"
#include "validation/io/results_folder.h"
#include "validation/run/case_library.h"
#include "validation/run/overrides.h"
#include "validation/run/run_scheduler.h"
#include "validation/run/sharding.h"
#include "validation/run/simulation.h"
#include "validation/studies/sweep.h"
#include "validation/verdict/summary.h"

namespace pbdval::cli {

int sweepCommand(const Context& context, const Arguments& arguments) {
  ArgParser parser(
      "sweep", "CASE --param NAME=v1,v2,... [options]",
      "A convergence study: runs CASE for every value of each --param (a grid when several),\n"
      "for every method, and reports per method the error metric and the wall time against the\n"
      "parameters, the fitted convergence order (least squares on log-log, with R^2), and the\n"
      "Pareto front of error against wall time. Parameters: timeStepSize, subSteps,\n"
      "maxIterations, maxIterationsV, and each method's own ('pbdval methods').");
  parser.positionals("CASE", "a scene with a Validation block", 1, 1)
      .option("param", "NAME=v1,v2,...",
              "a parameter and its values (default: the case's Validation.sweeps)", true)
      .option("together", "NAME,NAME,...",
              "vary these --param lists together, the i-th values at the i-th point (one path, "
              "not a grid: a penalty stiffness raised as the step falls); the order is fitted in "
              "the first")
      .option("methods", "LIST",
              "comma-separated methods (default: the case's, else every engine's default)")
      .option("metric", "NAME",
              "the error metric (default: trajectory_error_max with a reference, else "
              "energy_drift_max)")
      .option("reference", "fine|case|METHOD[:KEY=VALUE,...]",
              "fine: compare with the same method at a tiny step (consistency, Erez et al. 2015); "
              "case (default): the case's Validation.reference; a method: its run of the same "
              "scene at each point's step with these parameters (the converged reference: "
              "drake.rk3:targetAccuracy=1e-10)")
      .option("fine-divisor", "N",
              "with --reference fine: the reference step is the smallest swept step / N, N from 2 "
              "to 1024 (default 16)")
      .option("fit", "power|floor",
              "the model fitted to each method's errors: power (default) e = C*x^p; floor e = F + "
              "C*x^p, for a method that converges to a nearby model (penalty joints), one "
              "parameter refined by a constant ratio (docs/convergence.md#a-floor)")
      .option("out", "DIR",
              "write DIR/sweep.json (default: out); locked while the sweep goes, replaced only "
              "at the end (docs/cli.md#results-folders)")
      .flag("force", "replace a sweep.json of another sweep that --out holds")
      .option("jobs", "N", "runs in parallel, 1 to 1024 (default: the number of cores)")
      .option("timeout", "S", "wall-time limit per run (default 600)")
      .option("repeat", "N",
              "passes over the runs, 1 to 100: each point's wall time is the median of its N "
              "(default 3)")
      .option("shard", "K/N", "run only the K-th of N slices of the sweep's runs (docs/cluster.md)")
      .option("from-shards", "DIR,...",
              "fit the runs of the shard folders (comma-separated) instead of running")
      .option("executor", "local|dask", "where the runs execute (docs/cluster.md)")
      .option("scheduler", "ADDRESS", "dask: the scheduler's address")
      .option("scheduler-file", "FILE", "dask: the scheduler's file")
      .option("connect-timeout", "S", "dask: seconds to reach the scheduler (default 10)")
      .option("runs-per-task", "N", "dask: runs per task")
      .option("fail-with", "REASON", "with --shard: record the runs as error without running")
      .flag("list-plan", "print the sweep's runs as JSON and run nothing")
      .flag("report", "also write DIR/report/convergence.html, the sweep's page of pbdval report")
      .flag("quiet", "no progress lines")
      .epilog(
          "example: pbdval sweep cases/projectile.json --param "
          "timeStepSize=0.01,0.005,0.0025,0.00125 --methods pbd");
  ParsedArgs args;
  SweepOptions options;
  if (const auto exit = parser.parseOrExit(arguments, args)) return *exit;
  std::string out;
  try {
    options.caseFile = args.positionals[0];
    for (const std::string& p : args.values("param")) {
      const auto [name, list] = splitAssignment(p);
      const std::vector<std::string> values = splitList(list);
      if (values.empty()) throw UsageError("--param " + name + ": no values");
      options.parameters.emplace_back(name, values);
    }
    options.together = args.list("together");
    if (args.has("together") && options.together.empty())
      throw UsageError("--together: expected two or more parameter names, got none");
    options.methods = args.list("methods");
    checkNames(context.engines, "--methods", options.methods);
    options.metric = args.value("metric");
    const std::string reference = args.value("reference", "case");
    if (reference != "fine" && reference != "case")
      parseEngineReference(reference, context.engines);  // throws naming what was expected
    options.referenceMode = reference == "case" ? "" : reference;
    if (args.has("fine-divisor") && reference != "fine")
      throw UsageError(
          "--fine-divisor sets the step of --reference fine; without it there is no "
          "fine reference");
    // Above 1024 the reference run costs more than a thousand of the finest swept runs, and its
    // step nears round-off.
    options.fineDivisor = int(args.integerIn("fine-divisor", 16, 2, 1024));
    options.jobs =
        int(args.integerIn("jobs", std::max(1u, std::thread::hardware_concurrency()), 1, 1024));
    options.timeout = args.number("timeout", kDefaultWallTimeLimit);
    options.repetitions = int(args.integerIn("repeat", kSweepRepetitions, 1, 100));
    const std::string fit = args.value("fit", "power");
    if (fit != "power" && fit != "floor")
      throw UsageError("--fit: expected power or floor, got '" + fit + "'");
    options.fitModel = fit == "floor" ? FitModel::PowerPlusFloor : FitModel::Power;
    if (options.timeout < 0) throw UsageError("--timeout: expected seconds ≥ 0");
    out = args.value("out", "out");
    while (out.size() > 1 && out.back() == '/')
      out.pop_back();
    if (wantsDask(args)) return runOnDask("sweep", arguments);
    checkOutputsAreNotInputs(
        {{"--out", out + (args.has("shard") ? "/results.json" : "/sweep.json")}},
        {{"the case", options.caseFile}});
  } catch (...) {
    return parser.exitForCurrentException();
  }
  std::ostringstream command;
  command << "pbdval sweep";
  for (const std::string& a : arguments)
    command << ' ' << a;
  const bool quiet = args.flags.count("quiet") > 0;
  auto progress = [quiet](const RunRecord& r, std::size_t done, std::size_t total) {
    if (quiet) return;
    std::string values;
    for (const std::string& a : r.request.assignments)
      values += " " + a;
    std::fprintf(stderr, "[%3zu/%zu] %s%s %s\n", done, total, runLabel(r.request).c_str(),
                 values.c_str(), runStatusName(r.status));
  };
  SweepPlan plan;
  RunPlan runs;  // the sweep's runs as a run plan: what shards, --list-plan and executors use
  try {
    plan = planSweep(options, context.engines);
    runs.requests = plan.requests;
  } catch (...) {
    return parser.exitForCurrentException();
  }
  if (args.flags.count("list-plan")) {
    printPlan(runs);
    return 0;
  }
  const bool sharded = args.has("shard");
  const std::string manifest = sharded ? "results.json" : "sweep.json";
  // The output folder: locked, staged, and another sweep's results never replaced silently.
  std::optional<ResultsFolder> folder;
  RunPlan part = runs;
  std::optional<ShardInfo> shard;
  try {
    if (sharded) {
      ShardInfo info = parseShard(args.value("shard"));
      part = shardOf(runs, info);
      shard = info;
    }
    folder.emplace(out, "pbdval sweep");
    std::vector<RunKey> planned;
    for (const RunRequest& r : part.requests)
      planned.push_back({r.caseName, r.engine, r.method, r.assignments});
    const std::string previous = out + "/" + manifest;
    if (const auto why = foreignResults(previous, planned); why && !args.flags.count("force"))
      return parser.inputError(previous + ": " + *why +
                               "; the sweep would replace it: give another --out, or --force to "
                               "replace it");
  } catch (const std::exception& e) {
    return parser.inputError(e.what());
  }
  const std::string scratch = folder->staging() + "/.scratch";
  try {
    if (shard) {
      ResultsFile results;
      results.metadata = currentMetadata(command.str());
      results.metadata.shard = shard;
      results.cases[plan.caseName] = {options.caseFile, "sweep of " + plan.caseName, {}, {}, ""};
      if (args.has("fail-with")) {
        results.runs = failedRecords(part.requests, args.value("fail-with"));
      } else {
        RunScheduler scheduler(context.engines, options.jobs, options.timeout, scratch);
        results.runs = scheduler.runAll(part.requests, progress);
        std::filesystem::remove_all(scratch);
      }
      writeResults(folder->staging() + "/results.json", results);
      folder->commit({"trajectories", "results.json"}, "results.json");
      std::printf("%s; results in %s/results.json\n", statusCounts(results.runs).c_str(),
                  out.c_str());
      return 0;
    }
    std::vector<RunRecord> records;
    std::vector<std::vector<RunRecord>> repeats;
    if (args.has("from-shards")) {
      std::vector<ShardResults> shards;
      for (const std::string& shardFolder : splitList(args.value("from-shards")))
        shards.push_back({shardFolder, readResults(shardFolder + "/results.json")});
      const ResultsFile merged = mergeShards(shards, command.str());
      const std::string digest = planDigest(runs);
      if (shards.front().results.metadata.shard->planDigest != digest)
        throw std::invalid_argument(shards.front().folder + ": shards of another sweep (plan " +
                                    shards.front().results.metadata.shard->planDigest +
                                    ", this one's " + digest + ")");
      records = merged.runs;
    } else {
      RunScheduler scheduler(context.engines, options.jobs, options.timeout, scratch);
      records = scheduler.runAll(plan.requests, progress);
      // Further passes for the wall times (their median: sweep.h SweepOptions::repetitions).
      for (int pass = 1; pass < options.repetitions; ++pass)
        repeats.push_back(scheduler.runAll(plan.requests, progress));
      std::filesystem::remove_all(scratch);
    }
    const SweepResult result = collectSweep(plan, records, repeats);
    const std::string path = out + "/sweep.json";
    writeSweepJson(folder->staging() + "/sweep.json", result, currentMetadata(command.str()));
    folder->commit({"sweep.json"}, "sweep.json");
    printSweepTable(std::cout, result);
    std::printf("wrote %s\n", path.c_str());
    if (args.flags.count("report")) {
      // The convergence page, by the report's own code (python/pbdval/report.py): the last step.
      std::vector<std::string> argv = {
          projectPython(), "-m", "pbdval.report", "--convergence", out, "--out", out + "/report"};
      if (quiet) argv.push_back("--quiet");
      folder.reset();  // the lock is released before this process becomes the report's
      return execPython(argv);
    }
  } catch (const RunInterrupted&) {
    throw;  // exit status 128 + the signal (main); the staging folder goes with `folder`
  } catch (...) {
    return parser.exitForCurrentException();
  }
  return 0;
}

}  // namespace pbdval::cli
