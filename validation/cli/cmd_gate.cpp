// pbdval gate --baseline FILE --results DIR [--junit FILE] [--markdown FILE]
// pbdval baseline --results DIR --out FILE
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <sstream>

#include "validation/atomic_file.h"
#include "validation/case_library.h"
#include "validation/cli/args.h"
#include "validation/cli/commands.h"
#include "validation/gate.h"

namespace pbdval::cli {
namespace {

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
  auto drop = [&](std::vector<RunRecord>& runs) {
    runs.erase(std::remove_if(runs.begin(), runs.end(),
                              [&](const RunRecord& r) { return !wanted(r.request.caseName); }),
               runs.end());
  };
  drop(baseline.runs);
  drop(results.runs);
  for (auto it = results.cases.begin(); it != results.cases.end();)
    it = wanted(it->first) ? std::next(it) : results.cases.erase(it);
}

std::string resultsPathOf(const std::string& folderOrFile) {
  return folderOrFile.size() > 5 && folderOrFile.substr(folderOrFile.size() - 5) == ".json"
             ? folderOrFile
             : folderOrFile + "/results.json";
}

}  // namespace

int gateCommand(const Context& context, const Arguments& arguments) {
  ArgParser parser("gate",
                   "--baseline FILE --results DIR [--junit FILE] [--markdown FILE] "
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
      .option("cases", "LIST", "compare only these cases (comma-separated); default: all")
      .option("compare-as", "METHOD=BASELINE_METHOD",
              "compare only the results' runs of METHOD, with the baseline's runs of "
              "BASELINE_METHOD (an engine upgrade or another binding; repeatable)",
              true)
      .flag("known-failures-fail", "fail on case checks that already failed in the baseline too")
      .flag("quiet", "print only the verdict")
      .epilog(
          "exit status: 0 every check holds, 1 a check fails, 2 bad usage or unreadable input.");
  ParsedArgs args;
  if (const auto exit = parser.parseOrExit(arguments, args)) return *exit;
  if (!args.has("baseline") || !args.has("results"))
    return parser.usageError("--baseline and --results are required");
  GateReport report;
  ResultsFile results;
  try {
    if (args.has("cases") && splitList(args.value("cases")).empty())
      return parser.usageError("--cases: expected a comma-separated list of case names");
    // The reports must not replace what they report on, nor each other.
    checkOutputsAreNotInputs(
        {{"--junit", args.value("junit")}, {"--markdown", args.value("markdown")}},
        {{"the baseline", args.value("baseline")},
         {"the results", resultsPathOf(args.value("results"))}});
    Baseline baseline = readBaseline(args.value("baseline"));
    results = readResults(resultsPathOf(args.value("results")));
    if (args.has("cases")) restrictToCases(splitList(args.value("cases")), baseline, results);
    if (args.has("compare-as")) {
      std::vector<MethodPairing> pairs;
      for (const std::string& text : args.values("compare-as")) {
        const std::size_t eq = text.find('=');
        if (eq == std::string::npos || eq == 0 || eq + 1 == text.size())
          return parser.usageError("--compare-as: expected METHOD=BASELINE_METHOD, got '" + text + "'");
        const std::string method = text.substr(0, eq);
        pairs.push_back({method, context.engines.method(method).engine, text.substr(eq + 1)});
      }
      pairMethods(pairs, baseline, results);
    }
    GateOptions options;
    options.knownFailuresFail = args.flags.count("known-failures-fail") > 0;
    report = evaluateGate(baseline, results, options);
    if (args.has("junit")) {
      std::ostringstream xml;
      writeJUnit(xml, report);
      writeFileAtomically(args.value("junit"), xml.str());
    }
    if (args.has("markdown")) {
      std::ostringstream md;
      writeMarkdown(md, report, results);
      writeFileAtomically(args.value("markdown"), md.str());
    }
  } catch (const std::exception& e) {
    return parser.inputError(e.what());
  }
  if (!args.flags.count("quiet")) {
    for (const GateOutcome& o : report.outcomes)
      if (!o.passed)
        std::printf("FAIL %s: %s: %s\n", o.suite.c_str(), o.name.c_str(), o.message.c_str());
    for (const std::string& note : report.notes)
      std::printf("note: %s\n", note.c_str());
  }
  std::size_t known = 0;
  for (const GateOutcome& o : report.outcomes)
    known += o.knownFailure ? 1 : 0;
  std::printf("pbdval gate: %s (%zu checks, %zu failed, %zu known failures)\n",
              report.passed() ? "passed" : "FAILED", report.outcomes.size(), report.failures(),
              known);
  return report.passed() ? 0 : 1;
}

int baselineCommand(const Context& /*context*/, const Arguments& arguments) {
  ArgParser parser("baseline", "--results DIR --out FILE",
                   "Writes a baseline (statuses and metrics of every run) from a results folder,\n"
                   "for 'pbdval gate'. The project's own baseline lives in reports/baselines/.");
  parser.option("results", "DIR", "a results folder (or its results.json)")
      .option("out", "FILE", "the baseline file to write (atomically)");
  ParsedArgs args;
  if (const auto exit = parser.parseOrExit(arguments, args)) return *exit;
  if (!args.has("results") || !args.has("out"))
    return parser.usageError("--results and --out are required");
  try {
    checkOutputsAreNotInputs({{"--out", args.value("out")}},
                             {{"the results", resultsPathOf(args.value("results"))}});
    const ResultsFile results = readResults(resultsPathOf(args.value("results")));
    writeBaseline(args.value("out"), baselineFromResults(results));
    std::printf("pbdval baseline: %zu runs from %s written to %s\n", results.runs.size(),
                resultsPathOf(args.value("results")).c_str(), args.value("out").c_str());
  } catch (const std::exception& e) {
    return parser.inputError(e.what());
  }
  return 0;
}

}  // namespace pbdval::cli
