#include "validation/results.h"

#include <unistd.h>

#include <ctime>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "pbd/math/types.h"
#include "pbdval/build_info.h"
#include "validation/atomic_file.h"
#include "validation/json_text.h"

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
  return {{"created", m.created},
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
}

RunMetadata metadataFrom(const Json& j) {
  RunMetadata m;
  m.created = j.value("created", "");
  m.command = j.value("command", "");
  if (j.contains("pbdval")) {
    const Json& p = j.at("pbdval");
    m.version = p.value("version", "");
    m.commit = p.value("commit", "");
    m.commitState = p.value("commitState", "");
    m.buildType = p.value("buildType", "");
    m.compiler = p.value("compiler", "");
    m.flags = p.value("flags", "");
    m.precision = p.value("precision", "");
  }
  if (j.contains("machine")) {
    const Json& h = j.at("machine");
    m.hostname = h.value("hostname", "");
    m.cpu = h.value("cpu", "");
    m.cores = h.value("cores", 0);
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

CheckSpec checkFrom(const Json& j) {
  CheckSpec c;
  c.jsonPath = j.value("jsonPath", "");
  c.metric = j.at("metric").get<std::string>();
  if (j.contains("max")) c.max = j.at("max").get<double>();
  if (j.contains("min")) c.min = j.at("min").get<double>();
  c.engines = j.value("engines", std::vector<std::string>{});
  c.methods = j.value("methods", std::vector<std::string>{});
  c.better = j.value("better", "");
  c.worse = j.value("worse", "");
  c.description = j.value("description", "");
  return c;
}

}  // namespace

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
    runs.push_back(Json::parse(toJsonText(r)));
  Json cases = Json::object();
  for (const auto& [name, data] : results.cases) {
    Json checks = Json::array();
    for (const CheckSpec& c : data.checks)
      checks.push_back(checkJson(c));
    cases[name] = {{"file", data.file},
                   {"description", data.description},
                   {"checks", checks},
                   {"tolerances", data.tolerances}};
  }
  const Json document = {{"schema", "pbdval-results"},
                         {"schemaVersion", results.schemaVersion},
                         {"metadata", metadataJson(results.metadata)},
                         {"cases", cases},
                         {"runs", runs}};
  writeFileAtomically(path, jsonText(document) + "\n");
}

ResultsFile readResults(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::invalid_argument(path + ": cannot read");
  std::stringstream text;
  text << in.rdbuf();
  Json document;
  try {
    document = Json::parse(text.str());
  } catch (const Json::exception& e) {
    throw std::invalid_argument(path + ": not JSON: " + e.what());
  }
  if (!document.is_object() || document.value("schema", "") != "pbdval-results")
    throw std::invalid_argument(
        path + ": expected a pbdval results file (\"schema\": \"pbdval-results\")");
  ResultsFile results;
  results.schemaVersion = document.value("schemaVersion", 0);
  if (results.schemaVersion != kResultsSchemaVersion)
    throw std::invalid_argument(path + ": schemaVersion " + std::to_string(results.schemaVersion) +
                                " is not supported (expected " +
                                std::to_string(kResultsSchemaVersion) + ")");
  results.metadata = metadataFrom(document.value("metadata", Json::object()));
  try {
    // Named copies: items() and range-for refer to them, a temporary would dangle.
    const Json cases = document.value("cases", Json::object());
    for (const auto& item : cases.items()) {
      CaseGateData data;
      data.file = item.value().value("file", "");
      data.description = item.value().value("description", "");
      const Json checks = item.value().value("checks", Json::array());
      for (const Json& c : checks)
        data.checks.push_back(checkFrom(c));
      data.tolerances = item.value().value("tolerances", std::map<std::string, double>{});
      results.cases[item.key()] = data;
    }
  } catch (const Json::exception& e) {
    throw std::invalid_argument(path + ": cases: " + e.what());
  }
  if (!document.contains("runs") || !document.at("runs").is_array())
    throw std::invalid_argument(path + ": runs: expected an array");
  const Json& runs = document.at("runs");
  for (std::size_t i = 0; i < runs.size(); ++i)
    results.runs.push_back(
        recordFromJsonText(runs[i].dump(), path + ": runs[" + std::to_string(i) + "]"));
  return results;
}

}  // namespace pbdval
