// The gate on synthetic results: pass, metric regression, status regression, missing run, the
// cases' bounds and orderings, bad input; one verdict per check, printed alike by every writer;
// checks and tolerances from the baseline only; and the sweep's convergence fit.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>

#include "engines/selftest_engine.h"
#include "validation/io/sha256.h"
#include "validation/run/sharding.h"
#include "validation/studies/sweep.h"
#include "validation/verdict/gate.h"

namespace pbdval {
namespace {

RunRecord run(const std::string& method, double drift, RunStatus status = RunStatus::Ok) {
  RunRecord r;
  r.request.caseName = "case_a";
  r.request.engine = testRegistry().method(method).engine;
  r.request.method = method;
  r.status = status;
  r.metrics.values = {
      {"energy_drift_max", drift}, {"joint_error_linear_max", 1e-6}, {"wall_time_s", 1.0}};
  return r;
}

ResultsFile results(std::vector<RunRecord> runs) {
  ResultsFile f;
  f.runs = std::move(runs);
  f.cases["case_a"].file = "case_a.json";
  return f;
}

TEST(Gate, IdenticalResultsPass) {
  const ResultsFile now = results({run("pbd", 0.01), run("selftest.ok", 0.02)});
  const GateReport report = evaluateGate(baselineFromResults(now), now);
  EXPECT_TRUE(report.passed());
  EXPECT_GT(report.outcomes.size(), 2u);
}

TEST(Gate, MetricWorseThanItsToleranceFails) {
  const Baseline base = baselineFromResults(results({run("pbd", 0.010)}));
  // energy_drift: relative 10 % + 1e-6. 0.0109 passes, 0.0111 fails.
  EXPECT_TRUE(evaluateGate(base, results({run("pbd", 0.0109)})).passed());
  const GateReport report = evaluateGate(base, results({run("pbd", 0.0111)}));
  EXPECT_FALSE(report.passed());
  EXPECT_EQ(report.failures(), 1u);
  // Wall time is not gated by default: 100x slower still passes.
  RunRecord slow = run("pbd", 0.01);
  slow.metrics.values["wall_time_s"] = 100;
  EXPECT_TRUE(evaluateGate(base, results({slow})).passed());
  // A case's tolerance override, as the baseline pins it, applies (relative): 50 % allows 0.0149.
  Baseline overridden = base;
  overridden.cases["case_a"].tolerances["energy_drift_max"] = 0.5;
  EXPECT_TRUE(evaluateGate(overridden, results({run("pbd", 0.0149)})).passed());
}

TEST(Gate, StatusRegressionAndMissingRunFail) {
  const Baseline base = baselineFromResults(results({run("pbd", 0.01), run("selftest.ok", 0.01)}));
  GateReport report = evaluateGate(
      base, results({run("pbd", 0.01, RunStatus::Diverged), run("selftest.ok", 0.01)}));
  EXPECT_EQ(report.failures(), 1u);
  report = evaluateGate(base, results({run("pbd", 0.01)}));
  EXPECT_EQ(report.failures(), 1u);
  bool named = false;
  for (const GateOutcome& o : report.outcomes)
    named =
        named || (o.verdict == Verdict::Missing && o.message.find("missing") != std::string::npos);
  EXPECT_TRUE(named);
}

// An engine upgrade gated against the old version's baseline: the results' method is compared
// with the baseline's other method, and nothing else is compared (no "missing" runs of the
// methods left out).
TEST(Gate, PairedMethodsCompareAcrossMethodNames) {
  const Baseline old = baselineFromResults(results({run("pbd", 0.010), run("selftest.ok", 0.5)}));
  const std::vector<MethodPairing> pairs = {{"selftest.ok", "selftest", "pbd"}};
  {
    Baseline base = old;
    ResultsFile now = results({run("selftest.ok", 0.0105)});  // within pbd's 0.010 + 10 %
    pairMethods(pairs, base, now);
    ASSERT_EQ(base.runs.size(), 1u);
    EXPECT_EQ(base.runs[0].request.method, "selftest.ok");
    EXPECT_EQ(base.runs[0].request.engine, "selftest");
    EXPECT_TRUE(evaluateGate(base, now).passed());
  }
  {
    Baseline base = old;
    ResultsFile now = results({run("selftest.ok", 0.02), run("pbd", 99)});  // 2x pbd's drift
    pairMethods(pairs, base, now);
    ASSERT_EQ(now.runs.size(), 1u);  // pbd's own run is not compared
    const GateReport report = evaluateGate(base, now);
    EXPECT_EQ(report.failures(), 1u);
  }
  Baseline base = old;
  ResultsFile now = results({run("selftest.ok", 0.01)});
  EXPECT_THROW(pairMethods({{"selftest.ok", "selftest", "no.such"}}, base, now),
               std::invalid_argument);
  EXPECT_THROW(pairMethods({{"selftest.crash", "selftest", "pbd"}}, base, now),
               std::invalid_argument);
}

// The checks are those the baseline pins for the case.
TEST(Gate, CaseBoundsAndOrderingsAreChecked) {
  const ResultsFile now = results({run("pbd", 0.01), run("selftest.ok", 0.02)});
  Baseline base = baselineFromResults(now);
  CheckSpec bound;
  bound.metric = "energy_drift_max";
  bound.max = 0.015;  // pbd 0.01 passes, selftest 0.02 fails
  base.cases["case_a"].checks = {bound};
  EXPECT_EQ(evaluateGate(base, now).failures(), 1u);
  bound.methods = {"pbd"};  // restricted to pbd: passes
  base.cases["case_a"].checks = {bound};
  EXPECT_TRUE(evaluateGate(base, now).passed());
  CheckSpec ordering;
  ordering.metric = "energy_drift_max";
  ordering.better = "pbd";
  ordering.worse = "selftest.ok";
  base.cases["case_a"].checks = {ordering};
  EXPECT_TRUE(evaluateGate(base, now).passed());
  std::swap(ordering.better, ordering.worse);
  base.cases["case_a"].checks = {ordering};
  EXPECT_FALSE(evaluateGate(base, now).passed());
}

// A check that already failed when the baseline was made is a known failure: reported, not
// failing the gate (a ratchet); a check that held in the baseline and fails now does fail.
TEST(Gate, KnownFailuresAreReportedButOnlyNewFailuresFail) {
  ResultsFile then = results({run("pbd", 0.01), run("selftest.ok", 0.02)});
  CheckSpec bound;
  bound.metric = "energy_drift_max";
  bound.max = 0.0105;  // selftest.ok (0.02) fails it already; pbd (0.01) holds
  then.cases["case_a"].checks = {bound};
  const Baseline base = baselineFromResults(then);
  ASSERT_EQ(base.knownFailures.size(), 1u);
  EXPECT_NE(base.knownFailures[0].find("selftest/selftest.ok"), std::string::npos);

  GateReport report = evaluateGate(base, then);
  EXPECT_TRUE(report.passed());
  EXPECT_EQ(report.counts().verdicts.at(Verdict::KnownFailure), 1u);

  ResultsFile now = results({run("pbd", 0.0104), run("selftest.ok", 0.02)});
  EXPECT_TRUE(evaluateGate(base, now).passed());            // within its tolerance and its bound
  now.runs[0].metrics.values["energy_drift_max"] = 0.0109;  // within its tolerance (10 %) ...
  report = evaluateGate(base, now);
  EXPECT_EQ(report.failures(), 1u);  // ... but breaks the bound that held in the baseline
  EXPECT_EQ(report.counts().verdicts.at(Verdict::ToleratedChange), 1u);

  GateOptions strict;
  strict.knownFailuresFail = true;
  EXPECT_FALSE(evaluateGate(base, then, strict).passed());
}

TEST(Gate, ReportsAreWellFormed) {
  const Baseline base = baselineFromResults(results({run("pbd", 0.01)}));
  const GateReport report = evaluateGate(base, results({run("pbd", 1.0)}));
  std::ostringstream xml, md;
  writeJUnit(xml, report);
  EXPECT_NE(xml.str().find("<failure type=\"regression\" message="), std::string::npos);
  EXPECT_NE(xml.str().find("failures=\"1\""), std::string::npos);
  writeMarkdown(md, report, results({}));
  EXPECT_NE(md.str().find("FAILED"), std::string::npos);
}

TEST(Gate, UnreadableBaselineIsAnError) {
  const auto path = std::filesystem::temp_directory_path() / "pbdval-bad-baseline.json";
  std::ofstream(path) << "{ not json";
  EXPECT_THROW(readBaseline(path.string()), std::invalid_argument);
  std::ofstream(path) << "{\"schema\": \"pbdval-results\"}";
  EXPECT_THROW(readBaseline(path.string()), std::invalid_argument);
  std::filesystem::remove(path);
}

// ---- fail closed (issue 9): each of these passed silently before ----------------------------

std::string temporaryJson(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / ("pbdval-gate-" + name + ".json");
  std::ofstream(path) << text;
  return path.string();
}

std::string invalidArgumentOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no std::invalid_argument)";
}

bool anyFailureSays(const GateReport& report, const std::string& text) {
  for (const GateOutcome& o : report.outcomes)
    if (!o.passed() && o.message.find(text) != std::string::npos) return true;
  return false;
}

const char* kBaselineHead = R"({"schema": "pbdval-baseline", "schemaVersion": 2,
    "cases": {"c": {"file": "c.json", "sha256": ""}}, "runs": )";

TEST(GateFailsClosed, EmptyBaselineIsAnError) {
  const std::string path = temporaryJson("empty", std::string(kBaselineHead) + "[]}");
  const std::string message = invalidArgumentOf([&] { readBaseline(path); });
  EXPECT_NE(message.find(path + ": runs: expected a non-empty array"), std::string::npos)
      << message;
  std::filesystem::remove(path);
  // In memory too: a gate that checks nothing fails.
  ResultsFile nothing;
  const GateReport report = evaluateGate(Baseline{}, nothing);
  EXPECT_FALSE(report.passed());
  EXPECT_TRUE(anyFailureSays(report, "nothing to check"));
}

TEST(GateFailsClosed, ResultsWithoutTheirCasesBlockAreAnError) {
  const auto folder = std::filesystem::temp_directory_path() / "pbdval-gate-no-cases";
  const std::string path = (folder / "results.json").string();
  writeResults(path, results({run("pbd", 0.01)}));
  EXPECT_EQ(readResults(path).cases.size(), 1u);  // the file as written reads back
  std::ifstream in(path);
  nlohmann::json document = nlohmann::json::parse(in);
  in.close();
  document.erase("cases");
  std::ofstream(path) << document.dump();
  EXPECT_NE(invalidArgumentOf([&] { readResults(path); }).find("missing required key \"cases\""),
            std::string::npos);
  document["cases"] = nlohmann::json::object();  // present, but without the run's case
  std::ofstream(path) << document.dump();
  EXPECT_NE(invalidArgumentOf([&] {
              readResults(path);
            }).find("runs[0]: case \"case_a\" has no entry in \"cases\""),
            std::string::npos);
  std::filesystem::remove_all(folder);
  // In memory: a run whose case has no gate data fails the gate.
  ResultsFile now = results({run("pbd", 0.01)});
  const Baseline base = baselineFromResults(now);
  now.cases.clear();
  const GateReport report = evaluateGate(base, now);
  EXPECT_FALSE(report.passed());
  EXPECT_TRUE(anyFailureSays(report, "no \"cases\" entry for case case_a"));
}

TEST(GateFailsClosed, DuplicatedRunFails) {
  const Baseline base = baselineFromResults(results({run("pbd", 0.01)}));
  const GateReport report = evaluateGate(base, results({run("pbd", 0.01), run("pbd", 0.01)}));
  EXPECT_FALSE(report.passed());
  EXPECT_TRUE(anyFailureSays(report, "appears more than once"));
  // The same run with other assignments is another run.
  RunRecord other = run("pbd", 0.01);
  other.request.assignments = {"subSteps=10"};
  EXPECT_FALSE(anyFailureSays(evaluateGate(base, results({run("pbd", 0.01), other})),
                              "appears more than once"));
  // A baseline that lists a run twice is an error naming it.
  const std::string entry =
      R"({"case": "c", "engine": "pbd", "method": "pbd", "status": "ok", "metrics": {}})";
  const std::string path =
      temporaryJson("duplicate", std::string(kBaselineHead) + "[" + entry + ", " + entry + "]}");
  EXPECT_NE(invalidArgumentOf([&] { readBaseline(path); }).find("runs[1]: duplicate run c pbd/pbd"),
            std::string::npos);
  std::filesystem::remove(path);
}

TEST(GateFailsClosed, NonFiniteMetricOfAnOkRunCannotBeBaselined) {
  RunRecord broken = run("pbd", std::nan(""));
  const std::string path = temporaryJson("nan", "");
  const std::string message =
      invalidArgumentOf([&] { writeBaseline(path, baselineFromResults(results({broken}))); });
  EXPECT_NE(message.find("metric energy_drift_max is nan"), std::string::npos) << message;
  // A run that was not ok keeps only its finite metrics (it is compared on its status).
  broken.status = RunStatus::Diverged;
  writeBaseline(path, baselineFromResults(results({broken})));
  EXPECT_EQ(readBaseline(path).runs.at(0).metrics.values.count("energy_drift_max"), 0u);
  // A null metric written by hand is refused with its JSON path.
  std::ofstream(path) << kBaselineHead
                      << R"([{"case": "c", "engine": "pbd", "method": "pbd", "status": "ok",
                              "metrics": {"energy_drift_max": null}}]})";
  EXPECT_NE(invalidArgumentOf([&] {
              readBaseline(path);
            }).find("runs[0].metrics.energy_drift_max: expected a number, got null"),
            std::string::npos);
  std::filesystem::remove(path);
}

TEST(GateFailsClosed, BaselineErrorsNameTheJsonPath) {
  const std::string path = temporaryJson(
      "paths", std::string(kBaselineHead) +
                   R"([{"case": "c", "engine": "pbd", "method": "pbd", "status": 3}]})");
  std::string message = invalidArgumentOf([&] { readBaseline(path); });
  EXPECT_NE(message.find(path + ": runs[0].status: expected a string, got 3"), std::string::npos)
      << message;
  EXPECT_EQ(message.find("json.exception"), std::string::npos) << message;
  std::ofstream(path) << kBaselineHead << R"([{"case": "c", "engine": "pbd", "status": "ok"}]})";
  message = invalidArgumentOf([&] { readBaseline(path); });
  EXPECT_NE(message.find("runs[0]: missing required key \"method\""), std::string::npos) << message;
  std::ofstream(path) << kBaselineHead
                      << R"([{"case": "c", "engine": "pbd", "method": "pbd", "status": "fine",
                              "metrics": {}}]})";
  message = invalidArgumentOf([&] { readBaseline(path); });
  EXPECT_NE(message.find("runs[0].status: expected one of \"ok\""), std::string::npos) << message;
  std::filesystem::remove(path);
}

TEST(GateFailsClosed, DeepJsonIsRefusedWithTheLimit) {
  const std::string path =
      temporaryJson("deep", std::string(kBaselineHead) + std::string(100000, '['));
  const std::string message = invalidArgumentOf([&] { readBaseline(path); });
  EXPECT_NE(message.find(path + ": arrays and objects nested deeper than 64 levels"),
            std::string::npos)
      << message;
  std::filesystem::remove(path);
  EXPECT_NE(invalidArgumentOf([] {
              readResults("/dev/null");
            }).find("/dev/null: the results is a character device, not a regular file"),
            std::string::npos);
}

// ---- one verdict per check (issue 24) -------------------------------------------------------

TEST(GateVerdict, OneFunctionDecidesEachKindOfFinding) {
  const GateOptions lenient, strict{true};
  CheckFinding f;
  EXPECT_EQ(decideVerdict(f, lenient), Verdict::Pass);
  f.change = 1;
  EXPECT_EQ(decideVerdict(f, lenient), Verdict::ToleratedChange);
  f.change = -1;
  EXPECT_EQ(decideVerdict(f, lenient), Verdict::Improvement);
  f.holds = false;
  EXPECT_EQ(decideVerdict(f, lenient), Verdict::Regression);
  f.failedInBaseline = true;
  EXPECT_EQ(decideVerdict(f, lenient), Verdict::KnownFailure);
  EXPECT_EQ(decideVerdict(f, strict), Verdict::Regression);
  f.present = false;
  EXPECT_EQ(decideVerdict(f, lenient), Verdict::Missing);
  f.newSinceBaseline = true;
  EXPECT_EQ(decideVerdict(f, lenient), Verdict::New);
  for (Verdict v : kVerdicts)
    EXPECT_EQ(verdictFails(v), v == Verdict::Regression || v == Verdict::Missing) << verdictName(v);
}

// A metric worse than the baseline beyond round-off but within its tolerance is a tolerated
// change, one better an improvement; both pass; a difference at round-off level is no change.
TEST(GateVerdict, ChangesWithinToleranceAreToleratedAndImprovementsAreNamed) {
  const Baseline base = baselineFromResults(results({run("pbd", 0.010)}));
  const auto verdictOfDrift = [&](double drift) {
    for (const GateOutcome& o : evaluateGate(base, results({run("pbd", drift)})).outcomes)
      if (o.metric == "energy_drift_max") return o.verdict;
    return Verdict::Pass;
  };
  EXPECT_EQ(verdictOfDrift(0.0105), Verdict::ToleratedChange);  // +5 %, allowed +10 %
  EXPECT_EQ(verdictOfDrift(0.0050), Verdict::Improvement);
  EXPECT_EQ(verdictOfDrift(0.010 * (1 + 1e-12)), Verdict::Pass);  // below kRoundOffRelative
  EXPECT_EQ(verdictOfDrift(0.0111), Verdict::Regression);         // beyond 10 % + 1e-6
}

RunRecord withStatus(RunRecord r, RunStatus status) {
  r.status = status;
  return r;
}

Verdict statusVerdict(const GateReport& report) {
  for (const GateOutcome& o : report.outcomes)
    if (o.name == "pbd/pbd status") return o.verdict;
  ADD_FAILURE() << "no status check";
  return Verdict::Pass;
}

// A suspect run (its states break a sanity bound) fails unless the baseline has it suspect
// too (a known failure); suspect in the baseline and ok now passes, as an improvement.
TEST(GateVerdict, SuspectRunFailsUnlessTheBaselineRecordsItSuspect) {
  const RunRecord ok = run("pbd", 0.01), suspect = withStatus(ok, RunStatus::Suspect);
  const Baseline wasOk = baselineFromResults(results({ok}));
  const Baseline wasSuspect = baselineFromResults(results({suspect}));
  const Baseline wasDiverged = baselineFromResults(results({withStatus(ok, RunStatus::Diverged)}));
  GateReport report = evaluateGate(wasOk, results({suspect}));
  EXPECT_EQ(statusVerdict(report), Verdict::Regression);
  EXPECT_FALSE(report.passed());
  EXPECT_EQ(statusVerdict(evaluateGate(wasDiverged, results({suspect}))), Verdict::Regression);
  report = evaluateGate(wasSuspect, results({suspect}));
  EXPECT_EQ(statusVerdict(report), Verdict::KnownFailure);
  EXPECT_TRUE(report.passed());
  GateOptions strict;
  strict.knownFailuresFail = true;
  EXPECT_FALSE(evaluateGate(wasSuspect, results({suspect}), strict).passed());
  report = evaluateGate(wasSuspect, results({ok}));
  EXPECT_EQ(statusVerdict(report), Verdict::Improvement);
  EXPECT_TRUE(report.passed());
  // A suspect run's metrics are kept and gated: one 100x worse fails as well.
  report = evaluateGate(wasSuspect, results({withStatus(run("pbd", 1.0), RunStatus::Suspect)}));
  EXPECT_EQ(report.failures(), 1u);
  // A completed run that no longer completes fails.
  EXPECT_EQ(statusVerdict(evaluateGate(wasSuspect, results({withStatus(ok, RunStatus::Error)}))),
            Verdict::Regression);
}

std::size_t countOf(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1))
    ++n;
  return n;
}

// A manufactured regression: one run of three with every metric 100x worse, another run gone.
// The text, JUnit, Markdown and JSON writers print the same counts, equal to the checks
// decideVerdict flagged: the scaled run's two gated metrics (energy_drift_max,
// joint_error_linear_max; wall_time_s is not gated) and the missing run.
TEST(GateVerdict, EveryWriterPrintsTheCountsOfTheVerdicts) {
  ResultsFile then =
      results({run("pbd", 0.01), run("selftest.ok", 0.02), run("selftest.crash", 0.03)});
  const Baseline base = baselineFromResults(then);
  ResultsFile now = then;
  for (auto& [metric, value] : now.runs[0].metrics.values)
    value *= 100;
  now.runs.pop_back();
  const GateReport report = evaluateGate(base, now);
  std::size_t flagged = 0;
  for (const GateOutcome& o : report.outcomes)
    flagged += verdictFails(decideVerdict(o.finding, GateOptions{})) ? 1 : 0;
  ASSERT_EQ(flagged, 3u);
  ASSERT_EQ(report.failures(), flagged);
  const std::string failed =
      std::to_string(flagged) + " failed in 1 case (2 regressions, 1 missing)";

  std::ostringstream text, xml, md, json;
  writeText(text, report, false);
  writeJUnit(xml, report);
  writeMarkdown(md, report, now);
  writeGateJson(json, report, now);
  EXPECT_EQ(countOf(text.str(), "\nFAIL ") + (text.str().rfind("FAIL ", 0) == 0), flagged);
  EXPECT_NE(text.str().find("pbdval gate: FAILED (" + std::to_string(report.outcomes.size()) +
                            " checks, " + failed),
            std::string::npos)
      << text.str();
  EXPECT_NE(xml.str().find("failures=\"" + std::to_string(flagged) + "\""), std::string::npos);
  EXPECT_EQ(countOf(xml.str(), "<failure "), flagged);
  EXPECT_EQ(countOf(md.str(), "\n| regression |") + countOf(md.str(), "\n| missing |"), flagged);
  EXPECT_NE(md.str().find(failed), std::string::npos) << md.str();
  const nlohmann::json document = nlohmann::json::parse(json.str());
  EXPECT_EQ(document["counts"]["failed"].get<std::size_t>(), flagged);
  std::size_t listed = 0;
  for (const auto& check : document["checks"])
    listed += check["verdict"] == "regression" || check["verdict"] == "missing" ? 1 : 0;
  EXPECT_EQ(listed, flagged);
  EXPECT_EQ(document["checks"].size(), report.outcomes.size());
}

// ---- the gate judges with the baseline's data, never the results' (issue 25) ----------------

// The attack of issue 25: a metric 100x worse, with a tolerance of 1e9 written into the results.
TEST(GateJudgesWithPinnedData, ToleranceWrittenIntoTheResultsIsIgnored) {
  const Baseline base = baselineFromResults(results({run("pbd", 0.01)}));
  ResultsFile tampered = results({run("pbd", 1.0)});
  tampered.cases["case_a"].tolerances["energy_drift_max"] = 1e9;
  const GateReport report = evaluateGate(base, tampered);
  EXPECT_FALSE(report.passed());
  EXPECT_TRUE(anyFailureSays(report, "allowed ≤ 0.011"));  // 0.01 (1 + 10 %) + 1e-6
}

// The same with a failing check deleted from the results: the baseline's check still applies.
TEST(GateJudgesWithPinnedData, CheckDeletedFromTheResultsStillApplies) {
  ResultsFile then = results({run("pbd", 0.01)});
  CheckSpec bound;
  bound.metric = "joint_error_linear_max";
  bound.max = 1e-5;
  then.cases["case_a"].checks = {bound};
  const Baseline base = baselineFromResults(then);
  ResultsFile now = results({run("pbd", 0.01)});
  now.runs[0].metrics.values["joint_error_linear_max"] = 1e-5 * 1.2;  // within 25 %, over the bound
  now.cases["case_a"].checks.clear();
  EXPECT_FALSE(evaluateGate(base, now).passed());
}

ResultsFile planned(std::vector<RunRecord> runs) {
  ResultsFile f = results(std::move(runs));
  f.metadata.planDigest = planDigestOfRuns(f.runs);
  f.cases["case_a"].fileSha256 = sha256Hex("case a, version 1");
  return f;
}

TEST(GateJudgesWithPinnedData, ResultsNotOfTheirPlanAreRefusedByName) {
  const ResultsFile good = planned({run("pbd", 0.01), run("selftest.ok", 0.02)});
  EXPECT_NO_THROW(refuseUnjudgeableResults(good, "r.json"));
  ResultsFile edited = good;
  edited.runs.pop_back();  // a run removed by hand
  EXPECT_NE(invalidArgumentOf([&] {
              refuseUnjudgeableResults(edited, "r.json");
            }).find("r.json: runs: the runs listed are not those of the plan"),
            std::string::npos);
  edited = good;
  edited.runs[0].request.assignments = {"timeStepSize=0.02"};
  EXPECT_NE(
      invalidArgumentOf([&] { refuseUnjudgeableResults(edited, "r.json"); }).find("planDigest"),
      std::string::npos);
  ResultsFile old = good;
  old.metadata.planDigest.clear();
  EXPECT_NE(invalidArgumentOf([&] {
              refuseUnjudgeableResults(old, "r.json");
            }).find("r.json: metadata.planDigest: missing"),
            std::string::npos);
  ResultsFile shard = good;
  shard.metadata.shard = ShardInfo{2, 3, 6, good.metadata.planDigest};
  EXPECT_NE(invalidArgumentOf([&] {
              refuseUnjudgeableResults(shard, "r.json");
            }).find("shard 2/3 hold part of a plan"),
            std::string::npos);
  ResultsFile unhashed = good;
  unhashed.cases["case_a"].fileSha256.clear();
  EXPECT_NE(invalidArgumentOf([&] {
              refuseUnjudgeableResults(unhashed, "r.json");
            }).find("r.json: cases.case_a.sha256: missing"),
            std::string::npos);
}

TEST(GateJudgesWithPinnedData, BaselineRefusesWhatTheGateWouldRefuse) {
  EXPECT_NE(invalidArgumentOf([&] {
              refuseUnfitBaselineSource(planned({}), "r.json");
            }).find("r.json: runs: no runs"),
            std::string::npos);
  const ResultsFile twice = planned({run("pbd", 0.01), run("pbd", 0.01)});
  EXPECT_NE(invalidArgumentOf([&] {
              refuseUnfitBaselineSource(twice, "r.json");
            }).find("r.json: runs[1]: run case_a pbd/pbd is listed twice"),
            std::string::npos);
  const ResultsFile broken = planned(
      {run("pbd", 0.01, RunStatus::Error), run("selftest.ok", 0.01, RunStatus::Unsupported)});
  EXPECT_NE(invalidArgumentOf([&] {
              refuseUnfitBaselineSource(broken, "r.json");
            }).find("no run is ok (1 unsupported, 1 error)"),
            std::string::npos);
  ResultsFile otherPlan = planned({run("pbd", 0.01)});
  otherPlan.metadata.planDigest = planDigestOfRuns({run("selftest.ok", 0.01)});
  EXPECT_NE(invalidArgumentOf([&] {
              refuseUnfitBaselineSource(otherPlan, "r.json");
            }).find("not those of the plan"),
            std::string::npos);
  EXPECT_NO_THROW(refuseUnfitBaselineSource(planned({run("pbd", 0.01)}), "r.json"));
}

TEST(GateJudgesWithPinnedData, BaselineOfAnotherPrecisionIsRefused) {
  ResultsFile then = planned({run("pbd", 0.01)});
  then.metadata.precision = "double";
  const Baseline base = baselineFromResults(then);
  ResultsFile now = then;
  EXPECT_NO_THROW(refuseOtherBuild(base, now));
  now.metadata.precision = "float";
  EXPECT_NE(invalidArgumentOf([&] {
              refuseOtherBuild(base, now);
            }).find("the baseline was made by a double-precision build, the results by a float"),
            std::string::npos);
}

// `pbdval baseline` over a baseline of another plan (a partial run over the full baseline).
TEST(GateJudgesWithPinnedData, BaselineOfAnotherPlanIsNotReplacedSilently) {
  const ResultsFile full = planned({run("pbd", 0.01), run("selftest.ok", 0.02)});
  const Baseline existing = baselineFromResults(full);
  EXPECT_NO_THROW(refuseAnotherPlan(existing, "main.json", full));
  const ResultsFile partial = planned({run("pbd", 0.01)});
  EXPECT_NE(invalidArgumentOf([&] {
              refuseAnotherPlan(existing, "main.json", partial);
            }).find("main.json was made from another plan (2 runs of 1 cases"),
            std::string::npos);
}

/// A reader of case files from memory: file name → (bytes, checks).
CaseFileReader readerOf(
    std::map<std::string, std::pair<std::string, std::vector<CheckSpec>>> files) {
  return [files](const std::string& file) -> std::optional<CaseGateData> {
    const auto it = files.find(file);
    if (it == files.end()) return std::nullopt;
    CaseGateData data;
    data.file = file;
    data.fileSha256 = sha256Hex(it->second.first);
    data.checks = it->second.second;
    return data;
  };
}

TEST(GateJudgesWithPinnedData, CaseFilesMustBeThosePinned) {
  const ResultsFile then = planned({run("pbd", 0.01)});
  CheckSpec strictBound;
  strictBound.metric = "energy_drift_max";
  strictBound.max = 0.001;  // pbd (0.01) fails it
  const Baseline base = baselineFromResults(then);
  // The same file everywhere, or no file on disk: nothing to say.
  Baseline b = base;
  EXPECT_TRUE(checkCaseFiles(b, then, readerOf({{"case_a.json", {"case a, version 1", {}}}}), false)
                  .empty());
  EXPECT_TRUE(checkCaseFiles(b, then, readerOf({}), false).empty());
  // Results run from another version of the case: refused by name.
  ResultsFile changed = then;
  changed.cases["case_a"].fileSha256 = sha256Hex("case a, version 2");
  const auto disk = readerOf({{"case_a.json", {"case a, version 2", {strictBound}}}});
  EXPECT_NE(invalidArgumentOf([&] {
              checkCaseFiles(b, changed, disk, false);
            }).find("case case_a: the results were run from case_a.json with sha256 "),
            std::string::npos);
  // The file on disk edited since the baseline: refused by name.
  EXPECT_NE(invalidArgumentOf([&] {
              checkCaseFiles(b, then, disk, false);
            }).find("case case_a: case_a.json on disk has sha256 "),
            std::string::npos);
  // Re-pinned on request, from the file the results were run from: its checks apply.
  const std::vector<std::string> notes = checkCaseFiles(b, changed, disk, true);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("case case_a re-pinned"), std::string::npos);
  ASSERT_EQ(b.cases["case_a"].checks.size(), 1u);
  EXPECT_FALSE(evaluateGate(b, changed).passed());
  // ... and only from that file.
  b = base;
  EXPECT_NE(
      invalidArgumentOf([&] {
        checkCaseFiles(b, changed, readerOf({{"case_a.json", {"case a, version 3", {}}}}), true);
      }).find("the results were run from sha256"),
      std::string::npos);
}

// `pbdval baseline` pins the checks of the case files, not the results' copy of them.
TEST(GateJudgesWithPinnedData, BaselineTakesChecksFromTheCaseFiles) {
  ResultsFile then = planned({run("pbd", 0.01)});
  then.cases["case_a"].tolerances["energy_drift_max"] = 1e9;  // written into the results
  CheckSpec bound;
  bound.metric = "energy_drift_max";
  bound.max = 1;
  takeCaseDataFromFiles(then, readerOf({{"case_a.json", {"case a, version 1", {bound}}}}));
  EXPECT_TRUE(then.cases["case_a"].tolerances.empty());
  EXPECT_EQ(then.cases["case_a"].checks.size(), 1u);
  ResultsFile edited = planned({run("pbd", 0.01)});
  EXPECT_NE(invalidArgumentOf([&] {
              takeCaseDataFromFiles(edited, readerOf({{"case_a.json", {"case a, version 2", {}}}}));
            }).find("case case_a: case_a.json has changed since the runs"),
            std::string::npos);
  EXPECT_NE(invalidArgumentOf([&] {
              takeCaseDataFromFiles(edited, readerOf({}));
            }).find("case case_a: its file case_a.json cannot be read"),
            std::string::npos);
}

TEST(GateJudgesWithPinnedData, BaselineOfTheFirstVersionSaysHowToRegenerateIt) {
  const std::string path =
      temporaryJson("v1", R"({"schema": "pbdval-baseline", "schemaVersion": 1, "runs": []})");
  const std::string message = invalidArgumentOf([&] { readBaseline(path); });
  EXPECT_NE(message.find("schemaVersion 1"), std::string::npos) << message;
  EXPECT_NE(message.find("pbdval baseline --results out --out " + path), std::string::npos)
      << message;
  std::filesystem::remove(path);
}

TEST(GateJudgesWithPinnedData, BaselineRoundTripKeepsThePins) {
  ResultsFile then = planned({run("pbd", 0.01)});
  CheckSpec bound;
  bound.metric = "energy_drift_max";
  bound.max = 1;
  then.cases["case_a"].checks = {bound};
  then.cases["case_a"].tolerances["energy_drift_max"] = 0.5;
  const std::string path = temporaryJson("roundtrip", "");
  writeBaseline(path, baselineFromResults(then));
  const Baseline back = readBaseline(path);
  EXPECT_EQ(back.source.planDigest, then.metadata.planDigest);
  EXPECT_EQ(back.cases.at("case_a").fileSha256, then.cases["case_a"].fileSha256);
  EXPECT_EQ(back.cases.at("case_a").checks.size(), 1u);
  EXPECT_EQ(back.cases.at("case_a").tolerances.at("energy_drift_max"), 0.5);
  std::filesystem::remove(path);
}

// The settings a run was made with travel with the baseline, so that the report can say what
// differs between a later run and it; a baseline without them (made before) still reads.
TEST(GateJudgesWithPinnedData, BaselineRoundTripKeepsEachRunsSettingsAndTheBuildFlags) {
  ResultsFile then = planned({run("pbd", 0.01)});
  then.runs[0].settings = {{"timeStepSize", "0.005"}, {"subSteps", "5"}};
  then.runs[0].methodParameters = {{"threads", "1"}};
  then.metadata.flags = "-O3 -DNDEBUG";
  then.metadata.buildType = "Release";
  const std::string path = temporaryJson("settings", "");
  writeBaseline(path, baselineFromResults(then));
  const Baseline back = readBaseline(path);
  EXPECT_EQ(back.runs.at(0).settings, then.runs[0].settings);
  EXPECT_EQ(back.runs.at(0).methodParameters, then.runs[0].methodParameters);
  EXPECT_EQ(back.source.flags, "-O3 -DNDEBUG");
  EXPECT_EQ(back.source.buildType, "Release");
  std::ofstream(path) << kBaselineHead
                      << R"([{"case": "c", "engine": "pbd", "method": "pbd", "status": "ok",
                              "metrics": {}, "settings": {"subSteps": 5}}]})";
  EXPECT_NE(invalidArgumentOf([&] {
              readBaseline(path);
            }).find("runs[0].settings.subSteps: expected a string, got 5"),
            std::string::npos);
  std::filesystem::remove(path);
}

// FIPS 180-2, appendix B: the digests of "abc", of a two-block message and of a million "a"s;
// and of the empty string (well known).
TEST(Sha256, MatchesThePublishedTestVectors) {
  EXPECT_EQ(sha256Hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(sha256Hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(sha256Hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  EXPECT_EQ(sha256Hex(std::string(1000000, 'a')),
            "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

// The fit recovers known orders: e = 3 h² exactly (order 2, R² = 1); e ∝ n⁻¹ for a count-like
// parameter (order 1); two parameters at once.
TEST(SweepFit, RecoversKnownOrders) {
  std::vector<std::vector<double>> h;
  std::vector<double> e;
  for (double step : {0.01, 0.005, 0.0025, 0.00125}) {
    h.push_back({step});
    e.push_back(3 * step * step);
  }
  SweepFit fit = fitConvergence("m", {"timeStepSize"}, h, e);
  ASSERT_EQ(fit.orders.size(), 1u);
  EXPECT_NEAR(fit.orders[0], 2, 1e-9);  // exact power law: round-off only
  EXPECT_NEAR(fit.rSquared, 1, 1e-12);

  std::vector<std::vector<double>> n;
  e.clear();
  for (double count : {1.0, 2.0, 4.0, 8.0}) {
    n.push_back({count});
    e.push_back(0.5 / count);
  }
  fit = fitConvergence("m", {"subSteps"}, n, e);
  EXPECT_NEAR(fit.orders[0], 1, 1e-9);

  std::vector<std::vector<double>> grid;
  e.clear();
  for (double step : {0.01, 0.005, 0.0025})
    for (double count : {1.0, 2.0, 4.0}) {
      grid.push_back({step, count});
      e.push_back(step * step / count);
    }
  fit = fitConvergence("m", {"timeStepSize", "subSteps"}, grid, e);
  ASSERT_EQ(fit.orders.size(), 2u);
  EXPECT_NEAR(fit.orders[0], 2, 1e-9);
  EXPECT_NEAR(fit.orders[1], 1, 1e-9);
  EXPECT_TRUE(fit.warning.empty()) << fit.warning;

  // An error that grows as the step shrinks (round-off accumulating over more steps, e ∝ 1/h):
  // the fit still reports its slope, and warns that this is a floor, not an order.
  e.clear();
  for (const auto& step : h)
    e.push_back(1e-16 / step[0]);
  fit = fitConvergence("m", {"timeStepSize"}, h, e);
  EXPECT_NEAR(fit.orders[0], -1, 1e-9);
  EXPECT_NE(fit.warning.find("does not fall"), std::string::npos) << fit.warning;

  // Too few usable points: no fit, with a reason.
  fit = fitConvergence("m", {"timeStepSize"}, {{0.01}, {0.02}}, {1.0, std::nan("")});
  EXPECT_FALSE(fit.note.empty());
}

TEST(SweepFit, ParetoFrontKeepsNonDominatedPoints) {
  std::vector<SweepPoint> points(4);
  points[0].metric = 1e-2, points[0].wallTime = 1;
  points[1].metric = 1e-3, points[1].wallTime = 2;
  points[2].metric = 2e-2, points[2].wallTime = 3;  // dominated by 0
  points[3].metric = std::nan(""), points[3].wallTime = 0.1;
  markParetoFront(points);
  EXPECT_TRUE(points[0].pareto);
  EXPECT_TRUE(points[1].pareto);
  EXPECT_FALSE(points[2].pareto);
  EXPECT_FALSE(points[3].pareto);
}

}  // namespace
}  // namespace pbdval
