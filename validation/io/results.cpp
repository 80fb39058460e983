#include "validation/io/results.h"

#include <unistd.h>

#include <ctime>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
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

void writeResults(const std::string& path, const ResultsFile& results) {
  Json runs = Json::array();
  for (const RunRecord& r : results.runs)
    runs.push_back(recordJson(r));
  Json cases = Json::object();
  for (const auto& [name, data] : results.cases)
    cases[name] = caseGateDataJson(data);
  const Json document = {{"schema", "pbdval-results"},
                         {"schemaVersion", results.schemaVersion},
                         {"metadata", metadataJson(results.metadata)},
                         {"cases", cases},
                         {"runs", runs}};
  writeFileAtomically(path, jsonText(document) + "\n");
}

namespace {
ResultsFile parseResults(const nlohmann::json& document, const std::string& path);
}  // namespace

ResultsFile readResults(const std::string& path) {
  return parseResults(readJsonFile(path, "results"), path);
}

ResultsFile parseResultsText(const std::string& text, const std::string& sourceName) {
  return parseResults(parseJsonText(text, sourceName), sourceName);
}

namespace {
ResultsFile parseResults(const nlohmann::json& document, const std::string& path) {
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
  const JsonField runs = root.at("runs").expectArray();
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const std::string where = path + ": runs[" + std::to_string(i) + "]";
    results.runs.push_back(recordFromJson(runs.at(i).json(), where));
    const std::string& caseName = results.runs.back().request.caseName;
    if (!results.cases.count(caseName))
      throw std::invalid_argument(where + ": case \"" + caseName +
                                  "\" has no entry in \"cases\" (its checks would be skipped)");
  }
  return results;
}

}  // namespace

}  // namespace pbdval
