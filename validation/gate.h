// The release gate (docs/gate.md): compares a results folder with a baseline and with each
// case's own checks. Every check yields a pass/fail outcome with a message; the CLI turns them
// into an exit code, JUnit XML and a Markdown summary.
#pragma once

#include <iosfwd>
#include <map>
#include <string>
#include <vector>

#include "validation/results.h"

namespace pbdval {

inline constexpr int kBaselineSchemaVersion = 1;

/// A baseline: the statuses and metrics of a trusted results file.
struct Baseline {
  RunMetadata source;  ///< the results it was made from
  std::vector<RunRecord> runs;
  /// The case checks that failed in those results ("case: check name"): known failures. The
  /// gate reports them but fails only on checks that held in the baseline (a ratchet).
  std::vector<std::string> knownFailures;
};

Baseline baselineFromResults(const ResultsFile& results);
void writeBaseline(const std::string& path, const Baseline& baseline);
/// Throws std::invalid_argument naming the file and field on bad input.
Baseline readBaseline(const std::string& path);
/// The same on the file's text; `sourceName` names it in messages.
Baseline parseBaselineText(const std::string& text, const std::string& sourceName);

/// A comparison across methods: the results' runs of `resultsMethod` (of `resultsEngine`) are
/// compared with the baseline's runs of `baselineMethod`, as when gating an engine upgrade
/// (mujoco-python.euler.newton, MuJoCo 4.0.0, against mujoco.euler, MuJoCo 2.2.2).
struct MethodPairing {
  std::string resultsMethod;
  std::string resultsEngine;
  std::string baselineMethod;
};

/// Keeps only the paired runs: the baseline's runs of each baseline method, relabelled as the
/// results method and engine, and the results' runs of the results methods; drops the cases'
/// orderings between methods that are not both kept. Throws
/// std::invalid_argument when a baseline method has no run in the baseline or a results method
/// none in the results (a misspelt name would otherwise compare nothing and pass).
void pairMethods(const std::vector<MethodPairing>& pairs, Baseline& baseline, ResultsFile& results);

/// How much worse than the baseline a metric may get: new ≤ base·(1 + relative) + absolute
/// (on magnitudes, for signed metrics). `gated` false: not compared by default (cost metrics).
struct MetricTolerance {
  double relative = 0.25;
  double absolute = 1e-9;
  bool gated = true;
  bool higherIsBetter = false;
};
/// The default tolerance of a metric (docs/gate.md lists them).
MetricTolerance defaultTolerance(const std::string& metric);

struct GateOutcome {
  std::string suite;  ///< case name
  std::string name;   ///< "pbd/pbd energy_drift_max vs baseline", "checks[0] ..."
  bool passed = true;
  std::string message;
  bool knownFailure = false;  ///< a case check that failed in the baseline too (not counted)
  bool caseCheck = false;     ///< from Validation.checks (not a baseline comparison)
  std::string id() const { return suite + ": " + name; }
};

struct GateReport {
  std::vector<GateOutcome> outcomes;
  std::vector<std::string> notes;  ///< runs new since the baseline, metrics without baseline value
  bool passed() const;
  std::size_t failures() const;
};

struct GateOptions {
  /// Fail on every failing case check, known to the baseline or not.
  bool knownFailuresFail = false;
};

GateReport evaluateGate(const Baseline& baseline, const ResultsFile& results,
                        const GateOptions& options = {});
/// The case checks alone, evaluated on `results` (what baselineFromResults records).
std::vector<GateOutcome> evaluateCaseChecks(const ResultsFile& results);

void writeJUnit(std::ostream& out, const GateReport& report);
void writeMarkdown(std::ostream& out, const GateReport& report, const ResultsFile& results);

}  // namespace pbdval
