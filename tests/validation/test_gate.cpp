// The gate on synthetic results: pass, metric regression, status regression, missing run, the
// cases' bounds and orderings, bad input; and the sweep's convergence fit.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>

#include "engines/selftest_engine.h"
#include "validation/gate.h"
#include "validation/sweep.h"

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
  // A case's tolerance override applies (relative): 50 % allows 0.0149.
  ResultsFile overridden = results({run("pbd", 0.0149)});
  overridden.cases["case_a"].tolerances["energy_drift_max"] = 0.5;
  EXPECT_TRUE(evaluateGate(base, overridden).passed());
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
    named = named || (!o.passed && o.message.find("missing") != std::string::npos);
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

TEST(Gate, CaseBoundsAndOrderingsAreChecked) {
  ResultsFile now = results({run("pbd", 0.01), run("selftest.ok", 0.02)});
  const Baseline base = baselineFromResults(now);
  CheckSpec bound;
  bound.metric = "energy_drift_max";
  bound.max = 0.015;  // pbd 0.01 passes, selftest 0.02 fails
  now.cases["case_a"].checks = {bound};
  EXPECT_EQ(evaluateGate(base, now).failures(), 1u);
  bound.methods = {"pbd"};  // restricted to pbd: passes
  now.cases["case_a"].checks = {bound};
  EXPECT_TRUE(evaluateGate(base, now).passed());
  CheckSpec ordering;
  ordering.metric = "energy_drift_max";
  ordering.better = "pbd";
  ordering.worse = "selftest.ok";
  now.cases["case_a"].checks = {ordering};
  EXPECT_TRUE(evaluateGate(base, now).passed());
  std::swap(ordering.better, ordering.worse);
  now.cases["case_a"].checks = {ordering};
  EXPECT_FALSE(evaluateGate(base, now).passed());
}

// A check that already failed when the baseline was made is a known failure: reported, not
// failing the gate (a ratchet); a check that held in the baseline and fails now does fail.
TEST(Gate, KnownFailuresAreReportedButOnlyNewFailuresFail) {
  ResultsFile then = results({run("pbd", 0.01), run("selftest.ok", 0.02)});
  CheckSpec bound;
  bound.metric = "energy_drift_max";
  bound.max = 0.015;  // selftest.ok (0.02) fails it already
  then.cases["case_a"].checks = {bound};
  const Baseline base = baselineFromResults(then);
  ASSERT_EQ(base.knownFailures.size(), 1u);
  EXPECT_NE(base.knownFailures[0].find("selftest/selftest.ok"), std::string::npos);

  GateReport report = evaluateGate(base, then);
  EXPECT_TRUE(report.passed());
  bool marked = false;
  for (const GateOutcome& o : report.outcomes)
    marked = marked || o.knownFailure;
  EXPECT_TRUE(marked);

  ResultsFile now = results({run("pbd", 0.01), run("selftest.ok", 0.02)});
  now.cases = then.cases;
  now.runs[0].metrics.values["energy_drift_max"] = 0.0109;  // within its baseline tolerance
  EXPECT_TRUE(evaluateGate(base, now).passed());
  now.cases["case_a"].checks[0].max = 0.0105;  // now pbd (0.0109) fails a check that held
  EXPECT_FALSE(evaluateGate(base, now).passed());

  GateOptions strict;
  strict.knownFailuresFail = true;
  EXPECT_FALSE(evaluateGate(base, then, strict).passed());
}

TEST(Gate, ReportsAreWellFormed) {
  const Baseline base = baselineFromResults(results({run("pbd", 0.01)}));
  const GateReport report = evaluateGate(base, results({run("pbd", 1.0)}));
  std::ostringstream xml, md;
  writeJUnit(xml, report);
  EXPECT_NE(xml.str().find("<failure message="), std::string::npos);
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
    if (!o.passed && o.message.find(text) != std::string::npos) return true;
  return false;
}

const char* kBaselineHead = R"({"schema": "pbdval-baseline", "schemaVersion": 1, "runs": )";

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
