#include "validation/verdict/gate.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <ostream>
#include <set>
#include <sstream>

#include "validation/io/atomic_file.h"
#include "validation/io/json_input.h"
#include "validation/io/json_text.h"
#include "validation/run/sharding.h"

namespace pbdval {
namespace {

using Json = nlohmann::json;

std::string key(const RunRequest& r) {
  return r.caseName + " " + r.engine + "/" + r.method;
}

const RunRecord* findRun(const std::vector<RunRecord>& runs, const RunRequest& wanted) {
  for (const RunRecord& r : runs)
    if (r.request.caseName == wanted.caseName && r.request.engine == wanted.engine &&
        r.request.method == wanted.method && r.request.assignments == wanted.assignments)
      return &r;
  return nullptr;
}

std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", v);
  return text;
}

bool matches(const std::vector<std::string>& filter, const std::string& value) {
  return filter.empty() || std::find(filter.begin(), filter.end(), value) != filter.end();
}

/// What a check is about, for the report's table: the run, the metric and the numbers.
struct CheckSubject {
  std::string run, metric;
  std::optional<double> baselineValue, value, allowed;
};

/// Adds a check to the report; evaluateGate decides every verdict at the end.
void add(GateReport& report, std::string suite, std::string name, CheckFinding finding,
         std::string message, CheckSubject subject = {}) {
  GateOutcome o;
  o.suite = std::move(suite);
  o.name = std::move(name);
  o.finding = finding;
  o.message = std::move(message);
  o.run = std::move(subject.run);
  o.metric = std::move(subject.metric);
  o.baselineValue = subject.baselineValue;
  o.value = subject.value;
  o.allowed = subject.allowed;
  report.outcomes.push_back(std::move(o));
}

CheckFinding fails() {
  CheckFinding f;
  f.holds = false;
  return f;
}

CheckFinding absent() {
  CheckFinding f;
  f.present = false;
  return f;
}

/// A run that completed: its metrics describe the whole run.
bool completed(RunStatus status) {
  return status == RunStatus::Ok || status == RunStatus::Suspect;
}

/// +1 when `value` is worse than `base` beyond round-off, -1 when better, 0 otherwise.
int changeOf(double base, double value, bool higherIsBetter) {
  const double a = std::abs(base), b = std::abs(value);
  if (!std::isfinite(b)) return 1;
  if (std::abs(b - a) <= std::max(kRoundOffAbsolute, kRoundOffRelative * std::max(a, b))) return 0;
  return (b > a) != higherIsBetter ? 1 : -1;
}

/// The status check: a completed run (ok or suspect) must stay completed, and a run is suspect
/// only if it was in the baseline too (then it is a known failure).
void compareStatus(const RunRecord& base, const RunRecord& now, GateReport& report) {
  const RunStatus was = base.status, is = now.status;
  CheckFinding f;
  std::string message = std::string("status ") + runStatusName(is);
  if (was != is) message += " (baseline " + std::string(runStatusName(was)) + ")";
  if (completed(was) && !completed(is)) {
    f.holds = false;
    message = std::string("status was ") + runStatusName(was) + ", now " + runStatusName(is);
  } else if (is == RunStatus::Suspect) {
    f.holds = false;
    f.failedInBaseline = was == RunStatus::Suspect;
    message = was == RunStatus::Suspect
                  ? "suspect, as in the baseline"
                  : std::string("status was ") + runStatusName(was) + ", now suspect";
  } else if (was != is) {
    f.change = is == RunStatus::Ok ? -1 : 1;
  }
  if (!f.holds && !now.reason.empty()) message += ": " + now.reason;
  add(report, base.request.caseName, runLabel(base.request) + " status", f, message,
      {runLabel(base.request), "", {}, {}, {}});
}

void compareWithBaseline(const RunRecord& base, const RunRecord* now, const CaseGateData* pinned,
                         GateReport& report) {
  const std::string suite = base.request.caseName;
  const std::string label = runLabel(base.request);
  if (!now) {
    add(report, suite, label + " present", absent(),
        "run missing from the results (it is in the baseline)", {label, "", {}, {}, {}});
    return;
  }
  compareStatus(base, *now, report);
  // Metrics are compared between completed runs only: those of a run that stopped early
  // describe part of it.
  if (!completed(base.status) || !completed(now->status)) return;
  for (const auto& [metric, baseValue] : base.metrics.values) {
    MetricTolerance tolerance = defaultTolerance(metric);
    if (pinned) {
      const auto overridden = pinned->tolerances.find(metric);
      if (overridden != pinned->tolerances.end()) {
        tolerance.relative = overridden->second;
        tolerance.gated = true;
      }
    }
    if (!tolerance.gated) continue;
    const auto it = now->metrics.values.find(metric);
    if (it == now->metrics.values.end()) {
      add(report, suite, label + " " + metric, absent(),
          "metric missing from the results (baseline " + number(baseValue) + ")",
          {label, metric, baseValue, {}, {}});
      continue;
    }
    const double base0 = std::abs(baseValue), value = std::abs(it->second);
    CheckFinding f;
    double allowed;
    std::string limit;
    if (tolerance.higherIsBetter) {
      allowed = base0 * (1 - tolerance.relative) - tolerance.absolute;
      f.holds = value >= allowed;
      limit = "≥ " + number(allowed);
    } else {
      allowed = base0 * (1 + tolerance.relative) + tolerance.absolute;
      f.holds = std::isfinite(value) && value <= allowed;
      limit = "≤ " + number(allowed);
    }
    f.change = changeOf(baseValue, it->second, tolerance.higherIsBetter);
    add(report, suite, label + " " + metric, f,
        number(it->second) + " (baseline " + number(baseValue) + ", allowed " + limit + ")",
        {label, metric, baseValue, it->second, allowed});
  }
}

void evaluateChecksOf(const std::string& suite, const CaseGateData& data,
                      const ResultsFile& results, GateReport& report) {
  for (std::size_t i = 0; i < data.checks.size(); ++i) {
    const CheckSpec& check = data.checks[i];
    const std::string name =
        "check " + check.metric + (check.description.empty() ? "" : " (" + check.description + ")");
    if (!check.better.empty()) {
      const RunRecord *better = nullptr, *worse = nullptr;
      for (const RunRecord& r : results.runs) {
        if (r.request.caseName != suite || r.status != RunStatus::Ok) continue;
        if (r.request.method == check.better) better = &r;
        if (r.request.method == check.worse) worse = &r;
      }
      if (!better || !worse) {
        add(report, suite, name, fails(),
            "ordering " + check.better + " < " + check.worse +
                ": both runs must be in the results with status ok",
            {"", check.metric, {}, {}, {}});
        continue;
      }
      const auto b = better->metrics.values.find(check.metric),
                 w = worse->metrics.values.find(check.metric);
      if (b == better->metrics.values.end() || w == worse->metrics.values.end()) {
        add(report, suite, name, absent(), "metric " + check.metric + " missing from a run",
            {"", check.metric, {}, {}, {}});
        continue;
      }
      CheckFinding f;
      f.holds = std::abs(b->second) < std::abs(w->second);
      add(report, suite, name, f,
          check.better + " " + number(b->second) + (f.holds ? " < " : " ≥ ") + check.worse + " " +
              number(w->second),
          {"", check.metric, {}, {}, {}});
      continue;
    }
    bool any = false;
    for (const RunRecord& r : results.runs) {
      if (r.request.caseName != suite || !matches(check.engines, r.request.engine) ||
          !matches(check.methods, r.request.method) || r.status != RunStatus::Ok)
        continue;
      any = true;
      const std::string label = runLabel(r.request);
      const auto it = r.metrics.values.find(check.metric);
      if (it == r.metrics.values.end()) {
        add(report, suite, label + " " + name, absent(), "metric missing from the run",
            {label, check.metric, {}, {}, {}});
        continue;
      }
      const double v = it->second;
      CheckFinding f;
      f.holds =
          (!check.max || v <= *check.max) && (!check.min || v >= *check.min) && std::isfinite(v);
      std::string bounds;
      if (check.min) bounds += "≥ " + number(*check.min);
      if (check.max)
        bounds += std::string(bounds.empty() ? "" : " and ") + "≤ " + number(*check.max);
      add(report, suite, label + " " + name, f, number(v) + " (required " + bounds + ")",
          {label, check.metric, {}, v, check.max ? check.max : check.min});
    }
    if (!any) report.notes.push_back(suite + ": " + name + ": no ok run it applies to");
  }
}

void evaluateChecks(const std::string& suite, const CaseGateData& data, const ResultsFile& results,
                    GateReport& report) {
  const std::size_t first = report.outcomes.size();
  evaluateChecksOf(suite, data, results, report);
  for (std::size_t i = first; i < report.outcomes.size(); ++i)
    report.outcomes[i].caseCheck = true;
}

void decideAll(GateReport& report, const GateOptions& options) {
  for (GateOutcome& o : report.outcomes)
    o.verdict = decideVerdict(o.finding, options);
}

std::string escapeXml(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

}  // namespace

MetricTolerance defaultTolerance(const std::string& metric) {
  MetricTolerance t;
  auto startsWith = [&](const char* prefix) { return metric.rfind(prefix, 0) == 0; };
  const bool informational =
      metric.size() > 6 && metric.compare(metric.size() - 6, 6, "_scale") == 0;
  if (informational) {
    t.gated = false;  // energy_scale, momentum_*_scale: the normalisation used, not a result
  } else if (metric == "wall_time_s" || metric == "steps" || metric == "real_time_factor") {
    t.gated = false;  // timing is measured in benchmarks, not gated (noise)
    t.higherIsBetter = metric == "real_time_factor";
  } else if (startsWith("energy_drift")) {
    t = {0.10, 1e-6, true, false};
  } else if (startsWith("momentum_")) {
    t = {0.10, 1e-9, true, false};
  } else if (startsWith("joint_error")) {
    t = {0.25, 1e-9, true, false};
  } else if (startsWith("penetration")) {
    t = {0.25, 1e-5, true, false};
  } else if (startsWith("trajectory_error") || metric == "rotation_error_max") {
    t = {0.10, 1e-6, true, false};
  }
  return t;
}

const char* verdictName(Verdict verdict) {
  switch (verdict) {
    case Verdict::Regression:
      return "regression";
    case Verdict::Missing:
      return "missing";
    case Verdict::KnownFailure:
      return "known_failure";
    case Verdict::ToleratedChange:
      return "tolerated_change";
    case Verdict::Improvement:
      return "improvement";
    case Verdict::New:
      return "new";
    case Verdict::Pass:
      return "pass";
  }
  return "pass";
}

bool verdictFails(Verdict verdict) {
  return verdict == Verdict::Regression || verdict == Verdict::Missing;
}

Verdict decideVerdict(const CheckFinding& finding, const GateOptions& options) {
  if (finding.newSinceBaseline) return Verdict::New;
  if (!finding.present) return Verdict::Missing;
  if (!finding.holds)
    return finding.failedInBaseline && !options.knownFailuresFail ? Verdict::KnownFailure
                                                                  : Verdict::Regression;
  if (finding.change > 0) return Verdict::ToleratedChange;
  if (finding.change < 0) return Verdict::Improvement;
  return Verdict::Pass;
}

bool GateReport::passed() const {
  return failures() == 0;
}

std::size_t GateReport::failures() const {
  return counts().failed;
}

GateCounts GateReport::counts() const {
  GateCounts c;
  for (Verdict v : kVerdicts)
    c.verdicts[v] = 0;
  std::set<std::string> failingCases;
  for (const GateOutcome& o : outcomes) {
    ++c.verdicts[o.verdict];
    ++c.checks;
    if (verdictFails(o.verdict)) {
      ++c.failed;
      failingCases.insert(o.suite);
    }
  }
  c.failingCases = failingCases.size();
  return c;
}

std::string GateReport::summary() const {
  const GateCounts c = counts();
  auto count = [](std::size_t n, const char* one, const char* many) {
    return std::to_string(n) + " " + (n == 1 ? one : many);
  };
  std::string text =
      count(c.checks, "check", "checks") + ", " + std::to_string(c.failed) + " failed";
  if (c.failed)
    text += " in " + count(c.failingCases, "case", "cases") + " (" +
            count(c.verdicts.at(Verdict::Regression), "regression", "regressions") + ", " +
            std::to_string(c.verdicts.at(Verdict::Missing)) + " missing)";
  text += "; " + count(c.verdicts.at(Verdict::KnownFailure), "known failure", "known failures") +
          ", " +
          count(c.verdicts.at(Verdict::ToleratedChange), "tolerated change", "tolerated changes") +
          ", " + count(c.verdicts.at(Verdict::Improvement), "improvement", "improvements") + ", " +
          count(c.verdicts.at(Verdict::New), "new run", "new runs");
  return text;
}

std::vector<GateOutcome> evaluateCaseChecks(const std::map<std::string, CaseGateData>& cases,
                                            const ResultsFile& results) {
  GateReport report;
  for (const auto& [suite, data] : cases)
    evaluateChecks(suite, data, results, report);
  decideAll(report, {});
  return report.outcomes;
}

GateReport evaluateGate(const Baseline& baseline, const ResultsFile& results,
                        const GateOptions& options) {
  GateReport report;
  // Fail closed: a run listed twice, or a run whose case has no entry in the results (they were
  // not written by `pbdval run`), fails; so does a gate that checks nothing at all.
  std::map<std::string, int> seen;
  for (const RunRecord& now : results.runs) {
    std::string id = key(now.request);
    for (const std::string& assignment : now.request.assignments)
      id += " " + assignment;
    if (++seen[id] == 2)
      add(report, now.request.caseName, runLabel(now.request) + " unique", fails(),
          "run " + id + " appears more than once in the results");
    if (!results.cases.count(now.request.caseName))
      add(report, now.request.caseName, runLabel(now.request) + " case data", fails(),
          "the results have no \"cases\" entry for case " + now.request.caseName +
              " (its checks cannot be evaluated)");
  }
  auto pinnedOf = [&](const std::string& name) -> const CaseGateData* {
    const auto it = baseline.cases.find(name);
    return it == baseline.cases.end() ? nullptr : &it->second;
  };
  std::set<std::string> unpinned;
  for (const RunRecord& base : baseline.runs) {
    const CaseGateData* pinned = pinnedOf(base.request.caseName);
    if (!pinned && unpinned.insert(base.request.caseName).second)
      add(report, base.request.caseName, "pinned case data", fails(),
          "the baseline pins no checks or tolerances for case " + base.request.caseName);
    compareWithBaseline(base, findRun(results.runs, base.request), pinned, report);
  }
  for (const RunRecord& now : results.runs)
    if (!findRun(baseline.runs, now.request)) {
      CheckFinding f;
      f.newSinceBaseline = true;
      add(report, now.request.caseName, runLabel(now.request) + " new", f,
          std::string("not in the baseline (status ") + runStatusName(now.status) + ")",
          {runLabel(now.request), "", {}, {}, {}});
    }
  // The cases' own checks, as the baseline pins them, on the cases the results hold.
  std::map<std::string, CaseGateData> judged;
  for (const auto& [name, data] : results.cases) {
    if (const CaseGateData* pinned = pinnedOf(name))
      judged[name] = *pinned;
    else if (!data.checks.empty())
      report.notes.push_back("case " + name +
                             " is not in the baseline: its checks are not pinned, so not "
                             "evaluated (make a new baseline to gate them)");
  }
  const std::size_t firstCheck = report.outcomes.size();
  for (const auto& [suite, data] : judged)
    evaluateChecks(suite, data, results, report);
  for (std::size_t i = firstCheck; i < report.outcomes.size(); ++i) {
    GateOutcome& check = report.outcomes[i];
    check.finding.failedInBaseline =
        std::find(baseline.knownFailures.begin(), baseline.knownFailures.end(), check.id()) !=
        baseline.knownFailures.end();
  }
  if (report.outcomes.empty())
    add(report, "gate", "anything checked", fails(),
        "nothing to check: the baseline has no runs and the results have no case checks");
  decideAll(report, options);
  return report;
}

Baseline baselineFromResults(const ResultsFile& results) {
  Baseline b;
  b.source = results.metadata;
  b.cases = results.cases;
  b.runs = results.runs;
  for (const GateOutcome& check : evaluateCaseChecks(results.cases, results))
    if (!check.passed()) b.knownFailures.push_back(check.id());
  return b;
}

void writeBaseline(const std::string& path, const Baseline& baseline) {
  Json runs = Json::array();
  for (const RunRecord& r : baseline.runs) {
    Json metrics = Json::object();
    for (const auto& [name, value] : r.metrics.values) {
      if (std::isfinite(value)) {
        metrics[name] = value;
      } else if (r.status == RunStatus::Ok) {
        // Dropping it would leave the metric ungated; a run that was not ok is compared on its
        // status, so its non-finite metrics are left out.
        throw std::invalid_argument("run " + key(r.request) + ": metric " + name + " is " +
                                    number(value) +
                                    " (not finite) in an ok run; a baseline cannot gate it");
      }
    }
    Json run = {{"case", r.request.caseName},        {"engine", r.request.engine},
                {"method", r.request.method},        {"assignments", r.request.assignments},
                {"status", runStatusName(r.status)}, {"metrics", metrics}};
    // The run's effective settings, for the record: what the report compares a later run's
    // settings with (the gate judges none of them). Optional: older baselines lack them.
    if (!r.settings.empty()) run["settings"] = r.settings;
    if (!r.methodParameters.empty()) run["parameters"] = r.methodParameters;
    runs.push_back(run);
  }
  Json cases = Json::object();
  for (const auto& [name, data] : baseline.cases) {
    cases[name] = caseGateDataJson(data);
    cases[name]["sha256"] = data.fileSha256;  // written even when empty (a file not readable)
  }
  const Json document = {{"schema", "pbdval-baseline"},
                         {"schemaVersion", kBaselineSchemaVersion},
                         {"source",
                          {{"created", baseline.source.created},
                           {"commit", baseline.source.commit},
                           {"compiler", baseline.source.compiler},
                           {"buildType", baseline.source.buildType},
                           {"flags", baseline.source.flags},
                           {"precision", baseline.source.precision},
                           {"machine", baseline.source.cpu},
                           {"planDigest", baseline.source.planDigest}}},
                         {"cases", cases},
                         {"knownFailures", baseline.knownFailures},
                         {"runs", runs}};
  writeFileAtomically(path, jsonText(document) + "\n");
}

namespace {
Baseline baselineFrom(const Json& document, const std::string& path);
}  // namespace

Baseline readBaseline(const std::string& path) {
  return baselineFrom(readJsonFile(path, "baseline"), path);
}

Baseline parseBaselineText(const std::string& text, const std::string& sourceName) {
  return baselineFrom(parseJsonText(text, sourceName), sourceName);
}

namespace {
Baseline baselineFrom(const Json& document, const std::string& path) {
  JsonField root(document, path);
  if (!document.is_object() || root.stringOr("schema", "") != "pbdval-baseline")
    throw std::invalid_argument(path +
                                ": expected a pbdval baseline (\"schema\": \"pbdval-baseline\")");
  const double version = root.at("schemaVersion").number();
  if (version == 1)
    throw std::invalid_argument(
        path +
        ": schemaVersion 1: this baseline does not pin its cases' checks and tolerances (with "
        "each case file's SHA-256), so the gate cannot judge with it; make it again from a "
        "reviewed run: pbdval run --out out && pbdval baseline --results out --out " +
        path);
  if (version != kBaselineSchemaVersion)
    throw std::invalid_argument(path + ": schemaVersion: expected " +
                                std::to_string(kBaselineSchemaVersion));
  Baseline b;
  if (root.has("source")) {
    const JsonField source = root.at("source").expectObject();
    b.source.created = source.stringOr("created", "");
    b.source.commit = source.stringOr("commit", "");
    b.source.compiler = source.stringOr("compiler", "");
    b.source.buildType = source.stringOr("buildType", "");
    b.source.flags = source.stringOr("flags", "");
    b.source.precision = source.stringOr("precision", "");
    b.source.cpu = source.stringOr("machine", "");
    b.source.planDigest = source.stringOr("planDigest", "");
  }
  const JsonField cases = root.at("cases").expectObject();
  for (const std::string& name : cases.keys()) {
    const JsonField entry = cases.at(name).expectObject();
    CaseGateData data = caseGateDataFrom(entry);
    (void)entry.at("sha256").string();  // required: what the gate verifies the results by
    b.cases[name] = data;
  }
  if (root.has("knownFailures")) b.knownFailures = root.at("knownFailures").strings();
  const JsonField runs = root.at("runs").expectArray();
  // An empty baseline would gate nothing and pass whatever the results hold.
  if (runs.size() == 0) runs.fail("a non-empty array of runs (an empty baseline gates nothing)");
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const JsonField r = runs.at(i).expectObject();
    RunRecord record;
    record.request.caseName = r.at("case").string();
    record.request.engine = r.at("engine").string();
    record.request.method = r.at("method").string();
    if (r.has("assignments")) record.request.assignments = r.at("assignments").strings();
    const JsonField status = r.at("status");
    const std::string statusName = status.string();
    const std::optional<RunStatus> named = runStatusNamed(statusName);
    if (!named) status.fail("one of " + runStatusNameList());
    record.status = *named;
    const JsonField metrics = r.at("metrics").expectObject();
    for (const std::string& name : metrics.keys())
      record.metrics.values[name] = metrics.at(name).number();  // null is not a baseline value
    if (r.has("settings")) {  // optional (baselines made before they were recorded lack them)
      const JsonField settings = r.at("settings").expectObject();
      for (const std::string& name : settings.keys())
        record.settings[name] = settings.at(name).string();
    }
    if (r.has("parameters")) {
      const JsonField parameters = r.at("parameters").expectObject();
      for (const std::string& name : parameters.keys())
        record.methodParameters[name] = parameters.at(name).string();
    }
    if (findRun(b.runs, record.request))
      throw std::invalid_argument(path + ": " + r.path() + ": duplicate run " +
                                  key(record.request) + " (a baseline lists every run once)");
    if (!b.cases.count(record.request.caseName))
      throw std::invalid_argument(path + ": " + r.path() + ": case \"" + record.request.caseName +
                                  "\" has no entry in \"cases\" (its checks would be skipped)");
    b.runs.push_back(record);
  }
  return b;
}

}  // namespace

namespace {

/// The outcomes worth listing (every verdict but Pass), most severe first, in report order.
std::vector<const GateOutcome*> listed(const GateReport& report) {
  std::vector<const GateOutcome*> out;
  for (Verdict v : kVerdicts)
    if (v != Verdict::Pass)
      for (const GateOutcome& o : report.outcomes)
        if (o.verdict == v) out.push_back(&o);
  return out;
}

std::string verdictLabel(Verdict verdict) {
  std::string text = verdictName(verdict);
  std::replace(text.begin(), text.end(), '_', ' ');
  return text;
}

std::string escapeMarkdownCell(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '|') out += '\\';
    out += c == '\n' ? ' ' : c;
  }
  return out;
}

}  // namespace

void writeText(std::ostream& out, const GateReport& report, bool quiet) {
  if (!quiet) {
    for (const GateOutcome* o : listed(report)) {
      const char* prefix = verdictFails(o->verdict)              ? "FAIL"
                           : o->verdict == Verdict::KnownFailure ? "known failure"
                           : o->verdict == Verdict::New          ? "new"
                                                                 : nullptr;
      if (prefix) out << prefix << " " << o->suite << ": " << o->name << ": " << o->message << "\n";
    }
    for (const std::string& note : report.notes)
      out << "note: " << note << "\n";
  }
  out << "pbdval gate: " << (report.passed() ? "passed" : "FAILED") << " (" << report.summary()
      << ")\n";
}

void writeJUnit(std::ostream& out, const GateReport& report) {
  std::map<std::string, std::vector<const GateOutcome*>> suites;
  for (const GateOutcome& o : report.outcomes)
    suites[o.suite].push_back(&o);
  const GateCounts counts = report.counts();
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  out << "<testsuites name=\"pbdval gate\" tests=\"" << counts.checks << "\" failures=\""
      << counts.failed << "\" skipped=\"" << counts.verdicts.at(Verdict::KnownFailure) << "\">\n";
  out << "  <properties><property name=\"summary\" value=\"" << escapeXml(report.summary())
      << "\"/></properties>\n";
  for (const auto& [suite, outcomes] : suites) {
    std::size_t failures = 0, skipped = 0;
    for (const GateOutcome* o : outcomes) {
      failures += verdictFails(o->verdict) ? 1 : 0;
      skipped += o->verdict == Verdict::KnownFailure ? 1 : 0;
    }
    out << "  <testsuite name=\"" << escapeXml(suite) << "\" tests=\"" << outcomes.size()
        << "\" failures=\"" << failures << "\" skipped=\"" << skipped << "\">\n";
    for (const GateOutcome* o : outcomes) {
      out << "    <testcase classname=\"" << escapeXml(suite) << "\" name=\"" << escapeXml(o->name)
          << "\"";
      if (o->verdict == Verdict::KnownFailure) {
        out << ">\n      <skipped message=\"known failure: " << escapeXml(o->message)
            << "\"/>\n    </testcase>\n";
      } else if (verdictFails(o->verdict)) {
        out << ">\n      <failure type=\"" << verdictName(o->verdict) << "\" message=\""
            << escapeXml(o->message) << "\"/>\n    </testcase>\n";
      } else if (o->verdict == Verdict::Pass) {
        out << "/>\n";
      } else {
        out << ">\n      <system-out>" << verdictLabel(o->verdict) << ": " << escapeXml(o->message)
            << "</system-out>\n    </testcase>\n";
      }
    }
    out << "  </testsuite>\n";
  }
  out << "</testsuites>\n";
}

void writeMarkdown(std::ostream& out, const GateReport& report, const ResultsFile& results) {
  out << "# pbdval gate: " << (report.passed() ? "passed" : "FAILED") << "\n\n";
  out << report.summary() << ". Results from commit `" << results.metadata.commit << "` ("
      << results.metadata.created << ", " << results.metadata.compiler << ").\n\n";
  const std::vector<const GateOutcome*> rows = listed(report);
  if (!rows.empty()) {
    out << "| verdict | case | check | result |\n|---|---|---|---|\n";
    for (const GateOutcome* o : rows)
      out << "| " << verdictLabel(o->verdict) << " | " << escapeMarkdownCell(o->suite) << " | "
          << escapeMarkdownCell(o->name) << " | " << escapeMarkdownCell(o->message) << " |\n";
    out << "\n";
  }
  if (!report.notes.empty()) {
    out << "Notes:\n\n";
    for (const std::string& n : report.notes)
      out << "- " << n << "\n";
  }
}

void writeGateJson(std::ostream& out, const GateReport& report, const ResultsFile& results) {
  const GateCounts counts = report.counts();
  Json verdicts = Json::object();
  for (Verdict v : kVerdicts)
    verdicts[verdictName(v)] = counts.verdicts.at(v);
  Json checks = Json::array();
  for (const GateOutcome& o : report.outcomes) {
    Json c = {
        {"case", o.suite},      {"name", o.name},           {"verdict", verdictName(o.verdict)},
        {"message", o.message}, {"caseCheck", o.caseCheck}, {"run", o.run},
        {"metric", o.metric}};
    auto optionalNumber = [](const std::optional<double>& v) {
      return v && std::isfinite(*v) ? Json(*v) : Json(nullptr);
    };
    c["baseline"] = optionalNumber(o.baselineValue);
    c["now"] = optionalNumber(o.value);
    c["allowed"] = optionalNumber(o.allowed);
    checks.push_back(std::move(c));
  }
  std::ostringstream markdown;  // for report.md: the same summary as --markdown
  writeMarkdown(markdown, report, results);
  const Json document = {{"schema", "pbdval-gate"},
                         {"schemaVersion", kGateJsonSchemaVersion},
                         {"passed", report.passed()},
                         {"summary", report.summary()},
                         {"counts",
                          {{"checks", counts.checks},
                           {"failed", counts.failed},
                           {"failingCases", counts.failingCases},
                           {"verdicts", verdicts}}},
                         {"results",
                          {{"commit", results.metadata.commit},
                           {"created", results.metadata.created},
                           {"compiler", results.metadata.compiler}}},
                         {"checks", checks},
                         {"notes", report.notes},
                         {"markdown", markdown.str()}};
  out << jsonText(document) << "\n";
}

// ---- refusals --------------------------------------------------------------------------------

void refuseUnjudgeableResults(const ResultsFile& results, const std::string& name) {
  if (results.metadata.shard && results.metadata.shard->count > 1)
    throw std::invalid_argument(
        name + ": metadata.shard: the results of shard " +
        std::to_string(results.metadata.shard->index) + "/" +
        std::to_string(results.metadata.shard->count) +
        " hold part of a plan; merge the shards first (pbdval merge, docs/cluster.md)");
  if (results.metadata.planDigest.empty())
    throw std::invalid_argument(
        name +
        ": metadata.planDigest: missing (results written before pbdval recorded the plan "
        "they were made from); run them again with pbdval run");
  const std::string fromRuns = planDigestOfRuns(results.runs);
  if (fromRuns != results.metadata.planDigest)
    throw std::invalid_argument(
        name +
        ": runs: the runs listed are not those of the plan the results were made from "
        "(metadata.planDigest " +
        results.metadata.planDigest + ", the runs give " + fromRuns +
        "): runs were lost, added, reordered or edited since pbdval run");
  for (const auto& [caseName, data] : results.cases)
    if (data.fileSha256.empty() && data.description.rfind("could not be read", 0) != 0)
      throw std::invalid_argument(name + ": cases." + caseName +
                                  ".sha256: missing (the hash of the case file the runs were "
                                  "made from); run the results again with pbdval run");
}

void refuseUnfitBaselineSource(const ResultsFile& results, const std::string& name) {
  if (results.runs.empty())
    throw std::invalid_argument(name + ": runs: no runs (a baseline of nothing gates nothing)");
  refuseUnjudgeableResults(results, name);
  std::set<std::string> seen;
  for (std::size_t i = 0; i < results.runs.size(); ++i) {
    const RunRequest& r = results.runs[i].request;
    std::string id = key(r);
    for (const std::string& assignment : r.assignments)
      id += " " + assignment;
    if (!seen.insert(id).second)
      throw std::invalid_argument(name + ": runs[" + std::to_string(i) + "]: run " + id +
                                  " is listed twice (a baseline lists every run once)");
  }
  std::map<std::string, std::size_t> statuses;
  for (const RunRecord& r : results.runs)
    ++statuses[runStatusName(r.status)];
  if (!statuses.count(runStatusName(RunStatus::Ok))) {
    std::string counts;
    for (RunStatus status : kRunStatuses)
      if (statuses.count(runStatusName(status)))
        counts += (counts.empty() ? "" : ", ") + std::to_string(statuses[runStatusName(status)]) +
                  " " + runStatusName(status);
    throw std::invalid_argument(name + ": no run is ok (" + counts +
                                "): a baseline made from them would pass with every run broken");
  }
}

void refuseOtherBuild(const Baseline& baseline, const ResultsFile& results) {
  const std::string& was = baseline.source.precision;
  const std::string& is = results.metadata.precision;
  if (!was.empty() && !is.empty() && was != is)
    throw std::invalid_argument("the baseline was made by a " + was +
                                "-precision build, the results by a " + is +
                                "-precision one: their metrics cannot be compared");
}

void refuseAnotherPlan(const Baseline& existing, const std::string& existingPath,
                       const ResultsFile& results) {
  const std::string& was = existing.source.planDigest;
  if (was.empty() || was == results.metadata.planDigest) return;
  std::set<std::string> cases;
  for (const RunRecord& r : existing.runs)
    cases.insert(r.request.caseName);
  throw std::invalid_argument(
      existingPath + " was made from another plan (" + std::to_string(existing.runs.size()) +
      " runs of " + std::to_string(cases.size()) + " cases, planDigest " + was +
      ") than these results (" + std::to_string(results.runs.size()) + " runs of " +
      std::to_string(results.cases.size()) + " cases, planDigest " + results.metadata.planDigest +
      "); pass --new-plan to replace it with a baseline of this plan");
}

namespace {
std::string shortHash(const std::string& hash) {
  return hash.empty() ? "(none)" : hash.substr(0, 12);
}
}  // namespace

void takeCaseDataFromFiles(ResultsFile& results, const CaseFileReader& readCase) {
  for (auto& [name, data] : results.cases) {
    const std::optional<CaseGateData> file = readCase(data.file);
    if (!file)
      throw std::invalid_argument(
          "case " + name + ": its file " + data.file +
          " cannot be read; a baseline pins each case's checks and tolerances from its file "
          "(make it where the case files are, from the folder pbdval run was started in)");
    if (file->fileSha256 != data.fileSha256)
      throw std::invalid_argument("case " + name + ": " + data.file +
                                  " has changed since the runs (sha256 " +
                                  shortHash(file->fileSha256) + " now, " +
                                  shortHash(data.fileSha256) + " when run); run the results again");
    data.checks = file->checks;
    data.tolerances = file->tolerances;
    data.description = file->description;
  }
}

std::vector<std::string> checkCaseFiles(Baseline& baseline, const ResultsFile& results,
                                        const CaseFileReader& readCase, bool repin) {
  std::vector<std::string> notes;
  const std::string howTo =
      "review the change, then make a new baseline (pbdval baseline), or pass --repin-cases to "
      "gate with the case file's current checks and tolerances";
  for (const auto& [name, data] : results.cases) {
    const auto pinnedIt = baseline.cases.find(name);
    if (pinnedIt == baseline.cases.end()) continue;  // a new case: its runs are new
    CaseGateData& pinned = pinnedIt->second;
    const std::optional<CaseGateData> onDisk = readCase(data.file);
    const bool resultsMatch = data.fileSha256 == pinned.fileSha256;
    const bool diskMatches = !onDisk || onDisk->fileSha256 == pinned.fileSha256;
    if (resultsMatch && diskMatches) continue;
    if (!repin) {
      if (!resultsMatch)
        throw std::invalid_argument("case " + name + ": the results were run from " + data.file +
                                    " with sha256 " + shortHash(data.fileSha256) +
                                    ", the baseline pins " + pinned.file + " with sha256 " +
                                    shortHash(pinned.fileSha256) + "; " + howTo);
      throw std::invalid_argument("case " + name + ": " + data.file + " on disk has sha256 " +
                                  shortHash(onDisk->fileSha256) + ", the baseline pins sha256 " +
                                  shortHash(pinned.fileSha256) + "; " + howTo);
    }
    // Re-pinned from the file the results were run from, and only from it.
    if (!onDisk)
      throw std::invalid_argument("case " + name + ": --repin-cases: " + data.file +
                                  " cannot be read (the checks are re-pinned from the case file)");
    if (onDisk->fileSha256 != data.fileSha256)
      throw std::invalid_argument("case " + name + ": --repin-cases: " + data.file +
                                  " on disk has sha256 " + shortHash(onDisk->fileSha256) +
                                  ", the results were run from sha256 " +
                                  shortHash(data.fileSha256) + "; run the results again");
    pinned.checks = onDisk->checks;
    pinned.tolerances = onDisk->tolerances;
    pinned.file = data.file;
    pinned.fileSha256 = onDisk->fileSha256;
    notes.push_back("case " + name + " re-pinned (--repin-cases) from " + data.file + " (sha256 " +
                    shortHash(onDisk->fileSha256) + ")");
  }
  return notes;
}

void pairMethods(const std::vector<MethodPairing>& pairs, Baseline& baseline,
                 ResultsFile& results) {
  std::vector<RunRecord> paired;
  for (const MethodPairing& pair : pairs) {
    std::size_t found = 0;
    for (const RunRecord& r : baseline.runs) {
      if (r.request.method != pair.baselineMethod) continue;
      RunRecord renamed = r;
      renamed.request.method = pair.resultsMethod;
      renamed.request.engine = pair.resultsEngine;
      paired.push_back(std::move(renamed));
      ++found;
    }
    if (found == 0)
      throw std::invalid_argument("no run of method " + pair.baselineMethod + " in the baseline");
    const bool inResults =
        std::any_of(results.runs.begin(), results.runs.end(),
                    [&](const RunRecord& r) { return r.request.method == pair.resultsMethod; });
    if (!inResults)
      throw std::invalid_argument("no run of method " + pair.resultsMethod + " in the results");
  }
  baseline.runs = std::move(paired);
  // Orderings compare two methods of the results; with only the paired methods kept, one that
  // names another method could never hold, and would fail for the pairing, not the engine.
  auto kept = [&](const std::string& method) {
    return std::any_of(pairs.begin(), pairs.end(),
                       [&](const MethodPairing& p) { return p.resultsMethod == method; });
  };
  for (auto& [name, entry] : baseline.cases) {
    std::vector<CheckSpec>& checks = entry.checks;
    checks.erase(std::remove_if(checks.begin(), checks.end(),
                                [&](const CheckSpec& c) {
                                  return !c.better.empty() && !(kept(c.better) && kept(c.worse));
                                }),
                 checks.end());
  }
  results.runs.erase(std::remove_if(results.runs.begin(), results.runs.end(),
                                    [&](const RunRecord& r) {
                                      return std::none_of(
                                          pairs.begin(), pairs.end(), [&](const MethodPairing& p) {
                                            return p.resultsMethod == r.request.method;
                                          });
                                    }),
                     results.runs.end());
}

}  // namespace pbdval
