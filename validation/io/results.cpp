#include "validation/io/results.h"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <ctime>
#include <exception>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "pbd/math/types.h"
#include "pbdval/build_info.h"
#include "validation/io/atomic_file.h"
#include "validation/io/json_input.h"
#include "validation/io/json_text.h"

namespace pbdval {
namespace {

using Json = nlohmann::json;

std::string cpuModel() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0 && line.find(':') != std::string::npos)
      return line.substr(line.find(':') + 2);
  return "unknown";
}

std::string utcNow() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

Json metadataJson(const RunMetadata& m) {
  Json j = {{"created", m.created},
            {"command", m.command},
            {"pbdval",
             {{"version", m.version},
              {"commit", m.commit},
              {"commitState", m.commitState},
              {"buildType", m.buildType},
              {"compiler", m.compiler},
              {"flags", m.flags},
              {"precision", m.precision}}},
            {"machine", {{"hostname", m.hostname}, {"cpu", m.cpu}, {"cores", m.cores}}}};
  if (!m.planDigest.empty()) j["planDigest"] = m.planDigest;
  if (m.shard)
    j["shard"] = {{"index", m.shard->index},
                  {"count", m.shard->count},
                  {"planSize", m.shard->planSize},
                  {"planDigest", m.shard->planDigest}};
  return j;
}

RunMetadata metadataFrom(const JsonField& j) {
  RunMetadata m;
  m.created = j.stringOr("created", "");
  m.command = j.stringOr("command", "");
  if (j.has("pbdval")) {
    const JsonField p = j.at("pbdval").expectObject();
    m.version = p.stringOr("version", "");
    m.commit = p.stringOr("commit", "");
    m.commitState = p.stringOr("commitState", "");
    m.buildType = p.stringOr("buildType", "");
    m.compiler = p.stringOr("compiler", "");
    m.flags = p.stringOr("flags", "");
    m.precision = p.stringOr("precision", "");
  }
  if (j.has("machine")) {
    const JsonField h = j.at("machine").expectObject();
    m.hostname = h.stringOr("hostname", "");
    m.cpu = h.stringOr("cpu", "");
    if (h.has("cores")) m.cores = static_cast<int>(h.at("cores").integer(0, 1 << 20));
  }
  m.planDigest = j.stringOr("planDigest", "");
  if (j.has("shard")) {
    const JsonField s = j.at("shard").expectObject();
    ShardInfo shard;
    shard.count = static_cast<int>(s.at("count").integer(1, 1 << 30));
    shard.index = static_cast<int>(s.at("index").integer(1, shard.count));
    shard.planSize = static_cast<std::size_t>(s.at("planSize").integer(0, 1LL << 40));
    shard.planDigest = s.at("planDigest").string();
    m.shard = shard;
  }
  return m;
}

Json checkJson(const CheckSpec& c) {
  Json j = {{"jsonPath", c.jsonPath}, {"metric", c.metric}};
  if (c.max) j["max"] = *c.max;
  if (c.min) j["min"] = *c.min;
  if (!c.engines.empty()) j["engines"] = c.engines;
  if (!c.methods.empty()) j["methods"] = c.methods;
  if (!c.better.empty()) j["better"] = c.better;
  if (!c.worse.empty()) j["worse"] = c.worse;
  if (!c.description.empty()) j["description"] = c.description;
  return j;
}

CheckSpec checkFrom(const JsonField& j) {
  CheckSpec c;
  c.jsonPath = j.stringOr("jsonPath", "");
  c.metric = j.at("metric").string();
  if (j.has("max")) c.max = j.at("max").number();
  if (j.has("min")) c.min = j.at("min").number();
  if (j.has("engines")) c.engines = j.at("engines").strings();
  if (j.has("methods")) c.methods = j.at("methods").strings();
  c.better = j.stringOr("better", "");
  c.worse = j.stringOr("worse", "");
  c.description = j.stringOr("description", "");
  return c;
}

// ---- results.json's runs, written straight to text ------------------------------------------
// A record's text is exactly what jsonText(recordJson(record)) gives at the runs array's depth
// (tests/validation/test_runner.cpp and the results fuzz target compare them byte for byte):
// the keys in nlohmann's order (its objects are std::maps: byte-wise), its number and string
// forms. Written directly, 10,000 records cost a fraction of building and dumping their JSON
// values (docs/cluster.md#measured).

/// A JSON string as nlohmann dumps it (ensure_ascii off, bad UTF-8 replaced by U+FFFD).
void appendString(std::string& out, const std::string& text) {
  const bool plain = std::all_of(text.begin(), text.end(), [](char c) {
    return c >= 0x20 && c < 0x7f && c != '"' && c != '\\';
  });
  if (!plain) {
    out += jsonText(Json(text), -1);
    return;
  }
  out += '"';
  out += text;
  out += '"';
}

/// A double as nlohmann dumps it: its shortest round-trip form (nlohmann's own to_chars, the
/// function its serializer calls), null when not finite (recordJson's number()).
void appendNumber(std::string& out, double value) {
  if (!std::isfinite(value)) {
    out += "null";
    return;
  }
  std::array<char, 64> buffer{};
  const char* end = nlohmann::detail::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  out.append(buffer.data(), std::size_t(end - buffer.data()));
}

/// An object's members, one line each at `indent`, its braces at `indent` − 2; `members` append
/// each member's value after its key (empty: "{}", as nlohmann writes it).
class ObjectText {
 public:
  ObjectText(std::string& out, std::string indent) : out_(out), indent_(std::move(indent)) {
    out_ += '{';
  }
  /// Starts the member `key`; its value is appended next.
  std::string& key(const std::string& name) {
    out_ += first_ ? "\n" : ",\n";
    first_ = false;
    out_ += indent_;
    appendString(out_, name);
    out_ += ": ";
    return out_;
  }
  void close() {
    if (!first_) {
      out_ += '\n';
      out_.append(indent_, 0, indent_.size() - 2);
    }
    out_ += '}';
  }
  const std::string& indent() const { return indent_; }

 private:
  std::string& out_;
  std::string indent_;
  bool first_ = true;
};

void appendStrings(std::string& out, const std::vector<std::string>& items,
                   const std::string& indent) {
  if (items.empty()) {
    out += "[]";
    return;
  }
  out += '[';
  for (std::size_t i = 0; i < items.size(); ++i) {
    out += i == 0 ? "\n" : ",\n";
    out += indent;
    appendString(out, items[i]);
  }
  out += '\n';
  out.append(indent, 0, indent.size() - 2);
  out += ']';
}

void appendStringMap(std::string& out, const std::map<std::string, std::string>& items,
                     const std::string& indent) {
  ObjectText object(out, indent);
  for (const auto& [name, value] : items)
    appendString(object.key(name), value);
  object.close();
}

/// One record (recordJson's members) with its opening brace at `indent` − 2 spaces.
void appendRecordText(std::string& out, const RunRecord& record, const std::string& indent) {
  const RunRequest& r = record.request;
  const std::string inner = indent + "  ";
  ObjectText j(out, indent);
  appendStrings(j.key("assignments"), r.assignments, inner);
  appendString(j.key("case"), r.caseName);
  appendString(j.key("caseFile"), r.caseFile);
  appendString(j.key("engine"), r.engine);
  {
    ObjectText facts(j.key("facts"), inner);
    appendNumber(facts.key("contactMargin"), record.facts.contactMargin);
    appendString(facts.key("engineVersion"), record.facts.engineVersion);
    facts.key("integratorStepsPerSceneStep") +=
        std::to_string(record.facts.integratorStepsPerSceneStep);
    facts.close();
  }
  j.key("fineDivisor") += std::to_string(r.fineDivisor);
  {
    ObjectText byType(j.key("joint_error_by_type"), inner);
    for (const auto& [type, summary] : record.metrics.jointErrorByType) {
      ObjectText s(byType.key(type), inner + "  ");
      if (summary.hasAngular) {
        appendNumber(s.key("joint_error_angular_max"), summary.angularMax);
        appendNumber(s.key("joint_error_angular_rms"), summary.angularRms);
      }
      appendNumber(s.key("joint_error_linear_max"), summary.linearMax);
      appendNumber(s.key("joint_error_linear_rms"), summary.linearRms);
      s.key("joints") += std::to_string(summary.joints);
      if (!summary.trackingQuantity.empty()) {
        appendNumber(s.key("motor_tracking_max"), summary.trackingMax);
        appendString(s.key("motor_tracking_quantity"), summary.trackingQuantity);
        appendNumber(s.key("motor_tracking_rms"), summary.trackingRms);
      }
      s.close();
    }
    byType.close();
  }
  appendString(j.key("method"), r.method);
  {
    ObjectText metrics(j.key("metrics"), inner);
    for (const auto& [name, value] : record.metrics.values)
      appendNumber(metrics.key(name), value);
    metrics.close();
  }
  appendStrings(j.key("notes"), record.metrics.notes, inner);
  appendStringMap(j.key("parameters"), record.methodParameters, inner);
  appendString(j.key("reason"), record.reason);
  appendString(j.key("reference"), record.reference);
  appendString(j.key("referenceMode"), r.referenceMode);
  appendNumber(j.key("referenceStepSize"), r.referenceStepSize);
  appendNumber(j.key("sampleInterval"), r.sampleInterval);
  appendStringMap(j.key("settings"), record.settings, inner);
  appendString(j.key("state_hash"), record.stateHash);
  appendString(j.key("status"), runStatusName(record.status));
  appendString(j.key("trajectory"), r.trajectoryPath);
  j.close();
}

}  // namespace

Json caseGateDataJson(const CaseGateData& data) {
  Json checks = Json::array();
  for (const CheckSpec& c : data.checks)
    checks.push_back(checkJson(c));
  Json j = {{"file", data.file},
            {"description", data.description},
            {"checks", checks},
            {"tolerances", data.tolerances}};
  if (!data.fileSha256.empty()) j["sha256"] = data.fileSha256;
  return j;
}

CaseGateData caseGateDataFrom(const JsonField& entry) {
  CaseGateData data;
  data.file = entry.stringOr("file", "");
  data.description = entry.stringOr("description", "");
  data.fileSha256 = entry.stringOr("sha256", "");
  if (entry.has("checks")) {
    const JsonField checks = entry.at("checks").expectArray();
    for (std::size_t i = 0; i < checks.size(); ++i)
      data.checks.push_back(checkFrom(checks.at(i).expectObject()));
  }
  if (entry.has("tolerances")) {
    const JsonField tolerances = entry.at("tolerances").expectObject();
    for (const std::string& metric : tolerances.keys())
      data.tolerances[metric] = tolerances.at(metric).number();
  }
  return data;
}

RunMetadata currentMetadata(const std::string& command) {
  RunMetadata m;
  m.created = utcNow();
  m.command = command;
  m.version = PBDVAL_VERSION;
  m.commit = PBDVAL_GIT_COMMIT;
  m.commitState = PBDVAL_GIT_DIRTY;
  m.buildType = PBDVAL_BUILD_TYPE;
  m.compiler = PBDVAL_CXX_COMPILER;
  m.flags = PBDVAL_CXX_FLAGS;
  m.precision = sizeof(pbd::Real) == 8 ? "double" : "float";
  char host[256] = {};
  ::gethostname(host, sizeof host - 1);
  m.hostname = host;
  m.cpu = cpuModel();
  m.cores = static_cast<int>(std::thread::hardware_concurrency());
  return m;
}

std::string metadataJsonText(const RunMetadata& metadata) {
  return jsonText(metadataJson(metadata), -1);
}

void writeResultsText(std::ostream& out, const ResultsFile& results) {
  Json cases = Json::object();
  for (const auto& [name, data] : results.cases)
    cases[name] = caseGateDataJson(data);
  // The document without its runs, then each run's record written into it in place of the
  // empty array: the bytes of the whole document dumped at once (nlohmann orders the keys, so
  // "runs" lies between "metadata" and "schema"), without holding every record as JSON.
  const Json document = {{"schema", "pbdval-results"},
                         {"schemaVersion", results.schemaVersion},
                         {"metadata", metadataJson(results.metadata)},
                         {"cases", cases},
                         {"runs", Json::array()}};
  const std::string frame = jsonText(document);
  const std::string emptyRuns = "\n  \"runs\": []";  // a top-level key: indented by 2
  const std::size_t at = frame.find(emptyRuns);
  if (at == std::string::npos) throw std::logic_error("results.json: no top-level runs key");
  out.write(frame.data(), std::streamsize(at + emptyRuns.size() - 1));
  std::string record;
  for (std::size_t i = 0; i < results.runs.size(); ++i) {
    record = i == 0 ? "\n    " : ",\n    ";
    appendRecordText(record, results.runs[i], "      ");
    out.write(record.data(), std::streamsize(record.size()));
  }
  if (!results.runs.empty()) out << "\n  ";
  out << ']';
  out.write(frame.data() + at + emptyRuns.size(),
            std::streamsize(frame.size() - at - emptyRuns.size()));
  out << '\n';
}

void writeResults(const std::string& path, const ResultsFile& results) {
  OutputFile file(path);
  writeResultsText(file.stream(), results);
  file.commit();
}

namespace {

/// The runs of a results document, converted as the parser hands them over; the first record
/// that cannot be converted is kept to be thrown in its turn, after the checks of the document
/// around the runs (a file that is not a results file is reported as such, whatever its runs).
struct StreamedRuns {
  std::vector<RunRecord> records;
  std::exception_ptr firstError;  ///< of the record at index records.size()
};

ResultsFile parseResults(const nlohmann::json& document, StreamedRuns& streamed,
                         const std::string& path);

ResultsFile parseResultsStreaming(const std::string& text, const std::string& path) {
  StreamedRuns streamed;
  const Json document = parseJsonTextStreaming(
      text, path, {"runs"}, [&](const std::string&) { streamed = {}; },
      [&](const std::string&, std::size_t index, Json& run) {
        if (streamed.firstError) return;
        try {
          streamed.records.push_back(
              recordFromJson(run, path + ": runs[" + std::to_string(index) + "]"));
        } catch (const std::invalid_argument&) {
          streamed.firstError = std::current_exception();
        }
      });
  return parseResults(document, streamed, path);
}

}  // namespace

ResultsFile readResults(const std::string& path) {
  return parseResultsStreaming(readJsonFileText(path, "results"), path);
}

ResultsFile parseResultsText(const std::string& text, const std::string& sourceName) {
  return parseResultsStreaming(text, sourceName);
}

namespace {
ResultsFile parseResults(const nlohmann::json& document, StreamedRuns& streamed,
                         const std::string& path) {
  JsonField root(document, path);
  if (!document.is_object() || !document.contains("schema") || !document.at("schema").is_string() ||
      document.at("schema").get<std::string>() != "pbdval-results")
    throw std::invalid_argument(
        path + ": expected a pbdval results file (\"schema\": \"pbdval-results\")");
  ResultsFile results;
  const double version = root.at("schemaVersion").number();
  if (version != kResultsSchemaVersion)
    throw std::invalid_argument(path + ": schemaVersion " + Json(version).dump() +
                                " is not supported (expected " +
                                std::to_string(kResultsSchemaVersion) + ")");
  if (root.has("metadata")) results.metadata = metadataFrom(root.at("metadata").expectObject());
  // The cases block carries every case's checks: without it the gate would skip them silently.
  const JsonField cases = root.at("cases").expectObject();
  for (const std::string& name : cases.keys()) {
    results.cases[name] = caseGateDataFrom(cases.at(name).expectObject());
  }
  root.at("runs").expectArray();  // its elements were streamed
  results.runs = std::move(streamed.records);
  for (std::size_t i = 0; i < results.runs.size(); ++i) {
    const std::string& caseName = results.runs[i].request.caseName;
    if (!results.cases.count(caseName))
      throw std::invalid_argument(path + ": runs[" + std::to_string(i) + "]: case \"" + caseName +
                                  "\" has no entry in \"cases\" (its checks would be skipped)");
  }
  if (streamed.firstError) std::rethrow_exception(streamed.firstError);
  return results;
}

}  // namespace

}  // namespace pbdval
