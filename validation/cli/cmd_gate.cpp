// pbdval gate --baseline FILE --results DIR [--junit FILE] [--markdown FILE] [--json FILE]
// pbdval baseline --results DIR --out FILE
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>

#include "pbd/io/scene_loader.h"
#include "validation/cli/args.h"
#include "validation/cli/commands.h"
#include "validation/io/atomic_file.h"
#include "validation/io/sha256.h"
#include "validation/run/case_library.h"
#include "validation/run/case_spec.h"
#include "validation/verdict/gate.h"

namespace pbdval::cli {
namespace {

/// Keeps, in both the baseline and the results, only the runs `wanted` accepts.
template <typename Predicate>
void keepRuns(const Predicate& wanted, Baseline& baseline, ResultsFile& results) {
  for (std::vector<RunRecord>* runs : {&baseline.runs, &results.runs})
    runs->erase(
        std::remove_if(runs->begin(), runs->end(), [&](const RunRecord& r) { return !wanted(r); }),
        runs->end());
}

/// Keeps only the named cases in both the baseline and the results.
void restrictToCases(const std::vector<std::string>& cases, Baseline& baseline,
                     ResultsFile& results) {
  auto wanted = [&](const std::string& name) {
    return std::find(cases.begin(), cases.end(), name) != cases.end();
  };
  // A misspelt case would otherwise select nothing, and nothing passes.
  for (const std::string& name : cases) {
    const bool inBaseline =
        std::any_of(baseline.runs.begin(), baseline.runs.end(),
                    [&](const RunRecord& r) { return r.request.caseName == name; });
    if (!inBaseline && !results.cases.count(name))
      throw UsageError("--cases: no case \"" + name + "\" in the baseline or the results");
  }
  keepRuns([&](const RunRecord& r) { return wanted(r.request.caseName); }, baseline, results);
  for (auto it = results.cases.begin(); it != results.cases.end();)
    it = wanted(it->first) ? std::next(it) : results.cases.erase(it);
}

/// Keeps only the runs of the named engines (`default`: those run when none is named) in both
/// the baseline and the results: `--engines default` gates a run made without --engines against
/// a baseline that also holds engines run by name only.
void restrictToEngines(const std::vector<std::string>& named, const EngineRegistry& registry,
                       Baseline& baseline, ResultsFile& results) {
  const std::vector<std::string> engines = withDefaultEnginesExpanded(named, registry);
  checkNames(registry, "--engines", engines);
  keepRuns(
      [&](const RunRecord& r) {
        return std::find(engines.begin(), engines.end(), r.request.engine) != engines.end();
      },
      baseline, results);
}

/// A case file's gate data as `pbdval run` would record it: its checks and tolerances, and the
/// SHA-256 of its bytes; a file that is not a valid case keeps its hash and no checks.
CaseFileReader caseFileReader(const EngineRegistry& engines) {
  return [&engines](const std::string& file) -> std::optional<CaseGateData> {
    const std::optional<std::string> hash = fileSha256(file);
    if (!hash) return std::nullopt;
    CaseGateData data;
    data.file = file;
    data.fileSha256 = *hash;
    try {
      const CaseSpec spec = parseCaseSpec(pbd::loadScene(file).scene, engines);
      data.description = spec.description;
      data.checks = spec.checks;
      data.tolerances = spec.tolerances;
    } catch (const std::exception& e) {
      data.description = std::string("could not be read: ") + e.what();
    }
    return data;
  };
}

/// Writes what `write` prints to `path`, atomically.
template <typename Write>
void writeReport(const std::string& path, Write write) {
  std::ostringstream text;
  write(text);
  writeFileAtomically(path, text.str());
}

std::string resultsPathOf(const std::string& folderOrFile) {
  return folderOrFile.size() > 5 && folderOrFile.substr(folderOrFile.size() - 5) == ".json"
             ? folderOrFile
             : folderOrFile + "/results.json";
}

}  // namespace

int gateCommand(const Context& context, const Arguments& arguments) {
  ArgParser parser("gate",
                   "--baseline FILE --results DIR [--junit FILE] [--markdown FILE] [--json FILE] "
                   "[--compare-as METHOD=BASELINE_METHOD]",
                   "Compares a results folder with a baseline and with each case's own checks\n"
                   "(docs/gate.md): every metric no worse than the baseline by more than its\n"
                   "tolerance, no run that was ok and is not any more, no run missing, and the\n"
                   "cases' bounds and orderings.");
  parser
      .option("baseline", "FILE",
              "a baseline written by 'pbdval baseline' (e.g. reports/baselines/main.json)")
      .option("results", "DIR", "a results folder (or its results.json) written by 'pbdval run'")
      .option("junit", "FILE", "also write JUnit XML for CI systems")
      .option("markdown", "FILE", "also write a Markdown summary")
      .option("json", "FILE",
              "also write every check's verdict as JSON (what 'pbdval report' shows)")
      .option("cases", "LIST", "compare only these cases (comma-separated); default: all")
      .option("engines", "LIST",
              "compare only the runs of these engines (comma-separated; 'default': those "
              "'pbdval run' runs when none is named); default: all")
      .option("compare-as", "METHOD=BASELINE_METHOD",
              "compare only the results' runs of METHOD, with the baseline's runs of "
              "BASELINE_METHOD (an engine upgrade or another binding; repeatable)",
              true)
      .flag("known-failures-fail", "fail on case checks that already failed in the baseline too")
      .flag("repin-cases",
            "gate a case whose file changed since the baseline with the file's current checks and "
            "tolerances (default: refuse it by name)")
      .flag("quiet", "print only the verdict")
      .epilog(
          "exit status: 0 every check holds, 1 a check fails, 2 bad usage, unreadable input, or\n"
          "results it refuses to judge (another plan or case files than the baseline pins).");
  ParsedArgs args;
  if (const auto exit = parser.parseOrExit(arguments, args)) return *exit;
  if (!args.has("baseline") || !args.has("results"))
    return parser.usageError("--baseline and --results are required");
  GateReport report;
  ResultsFile results;
  try {
    if (args.has("cases") && splitList(args.value("cases")).empty())
      return parser.usageError("--cases: expected a comma-separated list of case names");
    if (args.has("engines") && splitList(args.value("engines")).empty())
      return parser.usageError("--engines: expected a comma-separated list of engine names");
    // The reports must not replace what they report on, nor each other.
    checkOutputsAreNotInputs({{"--junit", args.value("junit")},
                              {"--markdown", args.value("markdown")},
                              {"--json", args.value("json")}},
                             {{"the baseline", args.value("baseline")},
                              {"the results", resultsPathOf(args.value("results"))}});
    Baseline baseline = readBaseline(args.value("baseline"));
    const std::string resultsPath = resultsPathOf(args.value("results"));
    results = readResults(resultsPath);
    refuseUnjudgeableResults(results, resultsPath);
    refuseOtherBuild(baseline, results);
    if (args.has("cases")) restrictToCases(splitList(args.value("cases")), baseline, results);
    if (args.has("engines"))
      restrictToEngines(splitList(args.value("engines")), context.engines, baseline, results);
    const std::vector<std::string> repinned = checkCaseFiles(
        baseline, results, caseFileReader(context.engines), args.flags.count("repin-cases") > 0);
    if (args.has("compare-as")) {
      std::vector<MethodPairing> pairs;
      for (const std::string& text : args.values("compare-as")) {
        const std::size_t eq = text.find('=');
        if (eq == std::string::npos || eq == 0 || eq + 1 == text.size())
          return parser.usageError("--compare-as: expected METHOD=BASELINE_METHOD, got '" + text +
                                   "'");
        const std::string method = text.substr(0, eq);
        pairs.push_back({method, context.engines.method(method).engine, text.substr(eq + 1)});
      }
      pairMethods(pairs, baseline, results);
    }
    GateOptions options;
    options.knownFailuresFail = args.flags.count("known-failures-fail") > 0;
    report = evaluateGate(baseline, results, options);
    report.notes.insert(report.notes.end(), repinned.begin(), repinned.end());
    if (args.has("junit"))
      writeReport(args.value("junit"), [&](std::ostream& out) { writeJUnit(out, report); });
    if (args.has("markdown"))
      writeReport(args.value("markdown"),
                  [&](std::ostream& out) { writeMarkdown(out, report, results); });
    if (args.has("json"))
      writeReport(args.value("json"),
                  [&](std::ostream& out) { writeGateJson(out, report, results); });
  } catch (const std::exception& e) {
    return parser.inputError(e.what());
  }
  writeText(std::cout, report, args.flags.count("quiet") > 0);
  std::cout.flush();
  return report.passed() ? 0 : 1;
}

int baselineCommand(const Context& context, const Arguments& arguments) {
  ArgParser parser(
      "baseline", "--results DIR --out FILE [--new-plan]",
      "Writes a baseline from a results folder, for 'pbdval gate': the statuses and\n"
      "metrics of every run, the case checks that fail (known failures), and each\n"
      "case's checks and tolerances read from its file, pinned with the file's\n"
      "SHA-256. Refuses results the gate would refuse, empty results, a run listed\n"
      "twice, results in which no run is ok, and results of another plan than the\n"
      "baseline they replace. The project's own baseline lives in reports/baselines/.");
  parser.option("results", "DIR", "a results folder (or its results.json)")
      .option("out", "FILE", "the baseline file to write (atomically)")
      .flag("new-plan",
            "replace an existing baseline made from another plan (other cases, engines, methods "
            "or --set assignments); default: refuse");
  ParsedArgs args;
  if (const auto exit = parser.parseOrExit(arguments, args)) return *exit;
  if (!args.has("results") || !args.has("out"))
    return parser.usageError("--results and --out are required");
  try {
    checkOutputsAreNotInputs({{"--out", args.value("out")}},
                             {{"the results", resultsPathOf(args.value("results"))}});
    const std::string resultsPath = resultsPathOf(args.value("results"));
    ResultsFile results = readResults(resultsPath);
    refuseUnfitBaselineSource(results, resultsPath);
    const std::string out = args.value("out");
    if (!args.flags.count("new-plan") && std::filesystem::exists(out)) {
      // An existing baseline this one replaces; one that cannot be read (an old version) is
      // replaced without comparing plans.
      std::optional<Baseline> existing;
      try {
        existing = readBaseline(out);
      } catch (const std::invalid_argument&) {
      }
      if (existing) refuseAnotherPlan(*existing, out, results);
    }
    takeCaseDataFromFiles(results, caseFileReader(context.engines));
    writeBaseline(out, baselineFromResults(results));
    std::printf("pbdval baseline: %zu runs of %zu cases from %s written to %s\n",
                results.runs.size(), results.cases.size(), resultsPath.c_str(), out.c_str());
  } catch (const std::exception& e) {
    return parser.inputError(e.what());
  }
  return 0;
}

}  // namespace pbdval::cli
