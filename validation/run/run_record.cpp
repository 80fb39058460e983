// RunRecord <-> JSON: one entry of results.json's "runs" (docs/results.md), also the message a
// child process sends back to the scheduler.
#include "validation/run/run_record.h"

#include <cmath>
#include <nlohmann/json.hpp>

#include "validation/io/json_text.h"

namespace pbdval {

namespace {

using Json = nlohmann::json;

Json requestJson(const RunRequest& r) {
  return {{"case", r.caseName},
          {"caseFile", r.caseFile},
          {"engine", r.engine},
          {"method", r.method},
          {"assignments", r.assignments},
          {"trajectory", r.trajectoryPath},
          {"referenceMode", r.referenceMode},
          {"fineDivisor", r.fineDivisor},
          {"referenceStepSize", r.referenceStepSize},
          {"sampleInterval", r.sampleInterval}};
}

RunStatus statusFromName(const std::string& name, const std::string& where) {
  if (const std::optional<RunStatus> status = runStatusNamed(name)) return *status;
  throw std::invalid_argument(where + ": status: unknown status '" + name + "' (expected one of " +
                              runStatusNameList() + ")");
}

/// Non-finite numbers have no JSON form: they are written as null and read back as NaN.
Json number(double v) {
  return std::isfinite(v) ? Json(v) : Json(nullptr);
}
double numberFrom(const Json& j) {
  return j.is_null() ? std::nan("") : j.get<double>();
}

}  // namespace

std::string toJsonText(const RunRecord& record) {
  return jsonText(recordJson(record));
}

Json recordJson(const RunRecord& record) {
  Json metrics = Json::object();
  for (const auto& [name, value] : record.metrics.values)
    metrics[name] = number(value);
  Json byType = Json::object();
  for (const auto& [type, s] : record.metrics.jointErrorByType) {
    byType[type] = {{"joint_error_linear_max", number(s.linearMax)},
                    {"joint_error_linear_rms", number(s.linearRms)},
                    {"joints", s.joints}};
    if (s.hasAngular) {
      byType[type]["joint_error_angular_max"] = number(s.angularMax);
      byType[type]["joint_error_angular_rms"] = number(s.angularRms);
    }
    if (!s.trackingQuantity.empty()) {
      byType[type]["motor_tracking_quantity"] = s.trackingQuantity;
      byType[type]["motor_tracking_max"] = number(s.trackingMax);
      byType[type]["motor_tracking_rms"] = number(s.trackingRms);
    }
  }
  Json j = requestJson(record.request);
  j["status"] = runStatusName(record.status);
  j["reason"] = record.reason;
  j["parameters"] = record.methodParameters;
  j["settings"] = record.settings;
  j["facts"] = {{"engineVersion", record.facts.engineVersion},
                {"integratorStepsPerSceneStep", record.facts.integratorStepsPerSceneStep},
                {"contactMargin", record.facts.contactMargin}};
  j["metrics"] = metrics;
  j["joint_error_by_type"] = byType;
  j["notes"] = record.metrics.notes;
  j["state_hash"] = record.stateHash;
  j["reference"] = record.reference;
  return j;
}

RunRecord recordFromJsonText(const std::string& text, const std::string& where) {
  Json j;
  try {
    j = Json::parse(text);
  } catch (const Json::exception& e) {
    throw std::invalid_argument(where + ": " + e.what());
  }
  return recordFromJson(j, where);
}

RunRecord recordFromJson(const Json& j, const std::string& where) {
  try {
    RunRecord r;
    r.request.caseName = j.at("case").get<std::string>();
    r.request.caseFile = j.at("caseFile").get<std::string>();
    r.request.engine = j.at("engine").get<std::string>();
    r.request.method = j.at("method").get<std::string>();
    r.request.assignments = j.value("assignments", std::vector<std::string>{});
    r.request.trajectoryPath = j.value("trajectory", std::string());
    r.request.referenceMode = j.value("referenceMode", std::string());
    r.request.fineDivisor = j.value("fineDivisor", 16);
    r.request.referenceStepSize = j.value("referenceStepSize", 0.0);
    r.request.sampleInterval = j.value("sampleInterval", 0.0);
    r.status = statusFromName(j.at("status").get<std::string>(), where);
    r.reason = j.value("reason", std::string());
    r.methodParameters = j.value("parameters", std::map<std::string, std::string>{});
    r.settings = j.value("settings", std::map<std::string, std::string>{});
    if (j.contains("facts")) {
      const Json& facts = j.at("facts");
      r.facts.engineVersion = facts.value("engineVersion", std::string());
      r.facts.integratorStepsPerSceneStep = facts.value("integratorStepsPerSceneStep", 1);
      r.facts.contactMargin = facts.value("contactMargin", 0.0);
    }
    for (const auto& item : j.at("metrics").items())
      r.metrics.values[item.key()] = numberFrom(item.value());
    if (j.contains("joint_error_by_type"))
      for (const auto& item : j.at("joint_error_by_type").items()) {
        JointErrorSummary s;
        s.linearMax = numberFrom(item.value().at("joint_error_linear_max"));
        s.linearRms = numberFrom(item.value().at("joint_error_linear_rms"));
        s.hasAngular = item.value().contains("joint_error_angular_max");
        if (s.hasAngular) {
          s.angularMax = numberFrom(item.value().at("joint_error_angular_max"));
          s.angularRms = numberFrom(item.value().at("joint_error_angular_rms"));
        }
        s.trackingQuantity = item.value().value("motor_tracking_quantity", std::string());
        if (!s.trackingQuantity.empty()) {
          s.trackingMax = numberFrom(item.value().at("motor_tracking_max"));
          s.trackingRms = numberFrom(item.value().at("motor_tracking_rms"));
        }
        s.joints = item.value().value("joints", 0);
        r.metrics.jointErrorByType[item.key()] = s;
      }
    r.metrics.notes = j.value("notes", std::vector<std::string>{});
    r.stateHash = j.value("state_hash", std::string());
    r.reference = j.value("reference", std::string());
    return r;
  } catch (const Json::exception& e) {
    throw std::invalid_argument(where + ": " + e.what());
  }
}

}  // namespace pbdval
