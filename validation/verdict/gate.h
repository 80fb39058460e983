// The release gate (docs/gate.md): compares a results folder with a baseline and with each
// case's own checks. Every check records what it found (CheckFinding); one function,
// decideVerdict, turns that into the check's verdict; the text summary, the JUnit, Markdown and
// JSON writers and the Python report only print verdicts, so their counts agree by construction.
#pragma once

#include <functional>
#include <iosfwd>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "validation/io/results.h"

namespace pbdval {

/// 2: the baseline pins each case's checks and tolerances with its file's SHA-256 ("cases").
inline constexpr int kBaselineSchemaVersion = 2;
inline constexpr int kGateJsonSchemaVersion = 1;

/// A baseline: the statuses and metrics of a trusted results file, and the case data (checks,
/// tolerances, file hash) the gate judges with.
struct Baseline {
  RunMetadata source;  ///< the results it was made from (build, plan digest)
  /// The cases' checks and tolerances, pinned with their files' SHA-256: the gate takes them from
  /// here (or, with --repin-cases, from the case files), never from the results it judges.
  std::map<std::string, CaseGateData> cases;
  std::vector<RunRecord> runs;
  /// The case checks that failed in those results ("case: check name"): known failures. The
  /// gate reports them but fails only on checks that held in the baseline (a ratchet).
  std::vector<std::string> knownFailures;
};

/// The baseline of `results`: its runs, its known failures, and its cases' data as pinned.
/// `pbdval baseline` first refuses unfit results (refuseUnfitBaselineSource) and takes the case
/// data from the case files themselves (takeCaseDataFromFiles).
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
/// results method and engine, and the results' runs of the results methods; drops the orderings
/// (of the baseline's pinned case checks) between methods that are not both kept. Throws
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

/// The verdict on one check, in the order summaries list them. Regression and Missing fail
/// the gate; the others pass it.
enum class Verdict {
  Regression,       ///< worse than its tolerance; a check that fails; ok (or suspect) no more
  Missing,          ///< a run or metric of the baseline is not in the results
  KnownFailure,     ///< fails as it did in the baseline (a ratchet: reported, not failing)
  ToleratedChange,  ///< worse than the baseline beyond round-off, within its tolerance
  Improvement,      ///< better than the baseline beyond round-off
  New,              ///< a run not in the baseline (nothing to compare it with)
  Pass,             ///< holds, unchanged up to round-off
};
inline constexpr Verdict kVerdicts[] = {
    Verdict::Regression,  Verdict::Missing, Verdict::KnownFailure, Verdict::ToleratedChange,
    Verdict::Improvement, Verdict::New,     Verdict::Pass};
/// "regression", "missing", "known_failure", "tolerated_change", "improvement", "new", "pass".
const char* verdictName(Verdict verdict);
bool verdictFails(Verdict verdict);

/// A relative difference up to this (or an absolute one up to kRoundOffAbsolute) between a
/// metric and its baseline value is round-off: neither a change nor an improvement.
inline constexpr double kRoundOffRelative = 1e-9;
inline constexpr double kRoundOffAbsolute = 1e-12;

/// What a check found, before it is judged.
struct CheckFinding {
  bool newSinceBaseline = false;  ///< a run the baseline does not have
  bool present = true;            ///< what is checked (a run, a metric) is in the results
  bool holds = true;              ///< within tolerance, bound or ordering; status not regressed
  bool failedInBaseline = false;  ///< the check failed in the baseline too
  int change = 0;                 ///< against the baseline: +1 worse, -1 better, 0 round-off
};

struct GateOptions {
  /// Fail on every failing case check, known to the baseline or not.
  bool knownFailuresFail = false;
};

/// The one function that judges a check.
Verdict decideVerdict(const CheckFinding& finding, const GateOptions& options);

struct GateOutcome {
  std::string suite;  ///< case name ("gate" for the gate as a whole)
  std::string name;   ///< "pbd/pbd energy_drift_max", "pbd/pbd check energy_drift_final (...)"
  CheckFinding finding;
  std::string message;
  Verdict verdict = Verdict::Pass;  ///< decideVerdict(finding, options)
  bool caseCheck = false;           ///< from Validation.checks (not a baseline comparison)
  std::string run;                  ///< "engine/method" ("" for an ordering or the whole gate)
  std::string metric;               ///< "" for a status or presence check
  std::optional<double> baselineValue, value, allowed;
  bool passed() const { return !verdictFails(verdict); }
  std::string id() const { return suite + ": " + name; }
};

/// The counts every writer prints (one computation, so that they agree).
struct GateCounts {
  std::map<Verdict, std::size_t> verdicts;  ///< every verdict, zero included
  std::size_t checks = 0;
  std::size_t failed = 0;        ///< Regression + Missing
  std::size_t failingCases = 0;  ///< cases with at least one failed check
};

struct GateReport {
  std::vector<GateOutcome> outcomes;
  std::vector<std::string> notes;  ///< what was not checked, and why; re-pinned cases
  bool passed() const;
  std::size_t failures() const;
  GateCounts counts() const;
  /// "412 checks, 50 failed in 1 case (48 regressions, 2 missing); 3 tolerated changes, ..."
  std::string summary() const;
};

GateReport evaluateGate(const Baseline& baseline, const ResultsFile& results,
                        const GateOptions& options = {});
/// The case checks of `cases` evaluated on `results` (what baselineFromResults records as
/// known failures), judged without a baseline.
std::vector<GateOutcome> evaluateCaseChecks(const std::map<std::string, CaseGateData>& cases,
                                            const ResultsFile& results);

/// `pbdval gate`'s text: a line per failed check, known failure and new run, the notes (all
/// but the verdict when `quiet`), then "pbdval gate: passed|FAILED (summary)".
void writeText(std::ostream& out, const GateReport& report, bool quiet);
void writeJUnit(std::ostream& out, const GateReport& report);
void writeMarkdown(std::ostream& out, const GateReport& report, const ResultsFile& results);
/// The verdicts as JSON (docs/gate.md#json): what `pbdval report` shows.
void writeGateJson(std::ostream& out, const GateReport& report, const ResultsFile& results);

// ---- what the gate refuses to judge (std::invalid_argument, naming the file and the field) ---

/// Results the gate cannot judge: without a plan digest, one shard of a plan, runs that do not
/// give back the plan digest (lost, added or edited), a case without its file's hash.
void refuseUnjudgeableResults(const ResultsFile& results, const std::string& name);
/// Results a baseline cannot be made from: those the gate refuses, and empty results, a run
/// listed twice, results in which no run is ok (a baseline that passes with every run broken).
void refuseUnfitBaselineSource(const ResultsFile& results, const std::string& name);
/// A baseline made by another precision (float/double) than the results.
void refuseOtherBuild(const Baseline& baseline, const ResultsFile& results);
/// For `pbdval baseline` over an existing baseline: results of another plan than the one it was
/// made from (other cases, engines, methods or --set assignments) would silently change what
/// is gated, e.g. shrink the project's baseline to a partial run. `existingPath` names it.
void refuseAnotherPlan(const Baseline& existing, const std::string& existingPath,
                       const ResultsFile& results);

/// A case file's gate data read from disk (checks, tolerances, SHA-256 of its bytes); nullopt
/// when its bytes cannot be read. A file that is not a valid case has its hash and no checks.
using CaseFileReader = std::function<std::optional<CaseGateData>(const std::string& file)>;

/// For `pbdval baseline`: replaces each case's data in `results` by its file's (the checks to
/// pin come from the case files, not from the results' copy). Throws naming the case when its
/// file cannot be read or has changed since the results were made.
void takeCaseDataFromFiles(ResultsFile& results, const CaseFileReader& readCase);

/// For `pbdval gate`: refuses results run from other case files than the baseline pins, and
/// case files on disk that differ from the pinned ones, by name. With `repin`, such a case's
/// checks and tolerances are instead taken from its file on disk, which must be the file the
/// results were run from; the returned notes name each case re-pinned.
std::vector<std::string> checkCaseFiles(Baseline& baseline, const ResultsFile& results,
                                        const CaseFileReader& readCase, bool repin);

}  // namespace pbdval
