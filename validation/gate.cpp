#include "validation/gate.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <ostream>
#include <sstream>

#include "validation/atomic_file.h"
#include "validation/json_input.h"
#include "validation/json_text.h"

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

void compareWithBaseline(const RunRecord& base, const RunRecord* now, const ResultsFile& results,
                         GateReport& report) {
  const std::string suite = base.request.caseName;
  const std::string label = runLabel(base.request);
  if (!now) {
    report.outcomes.push_back(
        {suite, label + " present", false, "run missing from the results (it is in the baseline)"});
    return;
  }
  const bool wasOk = base.status == RunStatus::Ok;
  const bool isOk = now->status == RunStatus::Ok;
  report.outcomes.push_back({suite, label + " status", !(wasOk && !isOk),
                             wasOk && !isOk ? std::string("status was ok, now ") +
                                                  runStatusName(now->status) + ": " + now->reason
                                            : std::string("status ") + runStatusName(now->status)});
  if (!isOk) return;
  const auto caseData = results.cases.find(suite);
  for (const auto& [metric, baseValue] : base.metrics.values) {
    MetricTolerance tolerance = defaultTolerance(metric);
    if (caseData != results.cases.end()) {
      const auto overridden = caseData->second.tolerances.find(metric);
      if (overridden != caseData->second.tolerances.end()) {
        tolerance.relative = overridden->second;
        tolerance.gated = true;
      }
    }
    if (!tolerance.gated) continue;
    const auto it = now->metrics.values.find(metric);
    if (it == now->metrics.values.end()) {
      report.outcomes.push_back(
          {suite, label + " " + metric, false,
           "metric missing from the results (baseline " + number(baseValue) + ")"});
      continue;
    }
    const double base0 = std::abs(baseValue), value = std::abs(it->second);
    bool ok;
    std::string limit;
    if (tolerance.higherIsBetter) {
      const double floor = base0 * (1 - tolerance.relative) - tolerance.absolute;
      ok = value >= floor;
      limit = "≥ " + number(floor);
    } else {
      const double ceiling = base0 * (1 + tolerance.relative) + tolerance.absolute;
      ok = std::isfinite(value) && value <= ceiling;
      limit = "≤ " + number(ceiling);
    }
    report.outcomes.push_back(
        {suite, label + " " + metric, ok,
         number(it->second) + " (baseline " + number(baseValue) + ", allowed " + limit + ")"});
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
        report.outcomes.push_back({suite, name, false,
                                   "ordering " + check.better + " < " + check.worse +
                                       ": both runs must be in the results with status ok"});
        continue;
      }
      const auto b = better->metrics.values.find(check.metric),
                 w = worse->metrics.values.find(check.metric);
      if (b == better->metrics.values.end() || w == worse->metrics.values.end()) {
        report.outcomes.push_back(
            {suite, name, false, "metric " + check.metric + " missing from a run"});
        continue;
      }
      const bool ok = std::abs(b->second) < std::abs(w->second);
      report.outcomes.push_back({suite, name, ok,
                                 check.better + " " + number(b->second) + (ok ? " < " : " ≥ ") +
                                     check.worse + " " + number(w->second)});
      continue;
    }
    bool any = false;
    for (const RunRecord& r : results.runs) {
      if (r.request.caseName != suite || !matches(check.engines, r.request.engine) ||
          !matches(check.methods, r.request.method) || r.status != RunStatus::Ok)
        continue;
      any = true;
      const auto it = r.metrics.values.find(check.metric);
      if (it == r.metrics.values.end()) {
        report.outcomes.push_back(
            {suite, runLabel(r.request) + " " + name, false, "metric missing from the run"});
        continue;
      }
      const double v = it->second;
      const bool ok =
          (!check.max || v <= *check.max) && (!check.min || v >= *check.min) && std::isfinite(v);
      std::string bounds;
      if (check.min) bounds += "≥ " + number(*check.min);
      if (check.max)
        bounds += std::string(bounds.empty() ? "" : " and ") + "≤ " + number(*check.max);
      report.outcomes.push_back(
          {suite, runLabel(r.request) + " " + name, ok, number(v) + " (required " + bounds + ")"});
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

bool GateReport::passed() const {
  return failures() == 0;
}

std::size_t GateReport::failures() const {
  std::size_t n = 0;
  for (const GateOutcome& o : outcomes)
    n += o.passed ? 0 : 1;
  return n;
}

std::vector<GateOutcome> evaluateCaseChecks(const ResultsFile& results) {
  GateReport report;
  for (const auto& [suite, data] : results.cases)
    evaluateChecks(suite, data, results, report);
  return report.outcomes;
}

GateReport evaluateGate(const Baseline& baseline, const ResultsFile& results,
                        const GateOptions& options) {
  GateReport report;
  // Fail closed: a run listed twice, or a run whose case has no gate data (its checks would be
  // skipped), fails; so does a gate that checks nothing at all.
  std::map<std::string, int> seen;
  for (const RunRecord& now : results.runs) {
    std::string id = key(now.request);
    for (const std::string& assignment : now.request.assignments)
      id += " " + assignment;
    if (++seen[id] == 2)
      report.outcomes.push_back({now.request.caseName, runLabel(now.request) + " unique", false,
                                 "run " + id + " appears more than once in the results"});
    if (!results.cases.count(now.request.caseName))
      report.outcomes.push_back({now.request.caseName, runLabel(now.request) + " case data", false,
                                 "the results have no \"cases\" entry for case " +
                                     now.request.caseName + " (its checks cannot be evaluated)"});
  }
  for (const RunRecord& base : baseline.runs)
    compareWithBaseline(base, findRun(results.runs, base.request), results, report);
  for (const RunRecord& now : results.runs)
    if (!findRun(baseline.runs, now.request))
      report.notes.push_back("new run (not in the baseline): " + key(now.request));
  for (GateOutcome& check : evaluateCaseChecks(results)) {
    const bool known = std::find(baseline.knownFailures.begin(), baseline.knownFailures.end(),
                                 check.id()) != baseline.knownFailures.end();
    if (!check.passed && known && !options.knownFailuresFail) {
      check.passed = true;
      check.knownFailure = true;
      report.notes.push_back("known failure (in the baseline): " + check.id() + ": " +
                             check.message);
    }
    report.outcomes.push_back(std::move(check));
  }
  if (report.outcomes.empty())
    report.outcomes.push_back({"gate", "anything checked", false,
                               "nothing to check: the baseline has no runs and the results have "
                               "no case checks"});
  return report;
}

Baseline baselineFromResults(const ResultsFile& results) {
  Baseline b;
  b.source = results.metadata;
  b.runs = results.runs;
  for (const GateOutcome& check : evaluateCaseChecks(results))
    if (!check.passed) b.knownFailures.push_back(check.id());
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
    runs.push_back({{"case", r.request.caseName},
                    {"engine", r.request.engine},
                    {"method", r.request.method},
                    {"assignments", r.request.assignments},
                    {"status", runStatusName(r.status)},
                    {"metrics", metrics}});
  }
  const Json document = {{"schema", "pbdval-baseline"},
                         {"schemaVersion", kBaselineSchemaVersion},
                         {"source",
                          {{"created", baseline.source.created},
                           {"commit", baseline.source.commit},
                           {"compiler", baseline.source.compiler},
                           {"machine", baseline.source.cpu}}},
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
  if (root.at("schemaVersion").number() != kBaselineSchemaVersion)
    throw std::invalid_argument(path + ": schemaVersion: expected " +
                                std::to_string(kBaselineSchemaVersion));
  Baseline b;
  if (root.has("source")) {
    const JsonField source = root.at("source").expectObject();
    b.source.created = source.stringOr("created", "");
    b.source.commit = source.stringOr("commit", "");
    b.source.compiler = source.stringOr("compiler", "");
    b.source.cpu = source.stringOr("machine", "");
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
    if (findRun(b.runs, record.request))
      throw std::invalid_argument(path + ": " + r.path() + ": duplicate run " +
                                  key(record.request) + " (a baseline lists every run once)");
    b.runs.push_back(record);
  }
  return b;
}

}  // namespace

void writeJUnit(std::ostream& out, const GateReport& report) {
  std::map<std::string, std::vector<const GateOutcome*>> suites;
  for (const GateOutcome& o : report.outcomes)
    suites[o.suite].push_back(&o);
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  out << "<testsuites name=\"pbdval gate\" tests=\"" << report.outcomes.size() << "\" failures=\""
      << report.failures() << "\">\n";
  for (const auto& [suite, outcomes] : suites) {
    std::size_t failures = 0;
    for (const GateOutcome* o : outcomes)
      failures += o->passed ? 0 : 1;
    out << "  <testsuite name=\"" << escapeXml(suite) << "\" tests=\"" << outcomes.size()
        << "\" failures=\"" << failures << "\">\n";
    for (const GateOutcome* o : outcomes) {
      out << "    <testcase classname=\"" << escapeXml(suite) << "\" name=\"" << escapeXml(o->name)
          << "\"";
      if (o->knownFailure) {
        out << ">\n      <skipped message=\"known failure: " << escapeXml(o->message)
            << "\"/>\n    </testcase>\n";
      } else if (o->passed) {
        out << "/>\n";
      } else {
        out << ">\n      <failure message=\"" << escapeXml(o->message) << "\"/>\n    </testcase>\n";
      }
    }
    out << "  </testsuite>\n";
  }
  out << "</testsuites>\n";
}

void writeMarkdown(std::ostream& out, const GateReport& report, const ResultsFile& results) {
  out << "# pbdval gate: " << (report.passed() ? "passed" : "FAILED") << "\n\n";
  out << report.outcomes.size() << " checks, " << report.failures()
      << " failed. Results from commit `" << results.metadata.commit << "` ("
      << results.metadata.created << ", " << results.metadata.compiler << ").\n\n";
  if (report.failures()) {
    out << "| case | check | result |\n|---|---|---|\n";
    for (const GateOutcome& o : report.outcomes)
      if (!o.passed) out << "| " << o.suite << " | " << o.name << " | " << o.message << " |\n";
    out << "\n";
  }
  if (!report.notes.empty()) {
    out << "Notes:\n\n";
    for (const std::string& n : report.notes)
      out << "- " << n << "\n";
  }
}

void pairMethods(const std::vector<MethodPairing>& pairs, Baseline& baseline, ResultsFile& results) {
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
  for (auto& [name, entry] : results.cases) {
    std::vector<CheckSpec>& checks = entry.checks;
    checks.erase(std::remove_if(checks.begin(), checks.end(),
                                [&](const CheckSpec& c) {
                                  return !c.better.empty() && !(kept(c.better) && kept(c.worse));
                                }),
                 checks.end());
  }
  results.runs.erase(std::remove_if(results.runs.begin(), results.runs.end(),
                                    [&](const RunRecord& r) {
                                      return std::none_of(pairs.begin(), pairs.end(),
                                                          [&](const MethodPairing& p) {
                                                            return p.resultsMethod == r.request.method;
                                                          });
                                    }),
                     results.runs.end());
}

}  // namespace pbdval
