#include "adapters/engine.h"

#include <chrono>
#include <sstream>
#include <stdexcept>

#include "pbd/io/suggestion.h"

namespace pbdval {

const char* runStatusName(RunStatus status) {
  switch (status) {
    case RunStatus::Ok:
      return "ok";
    case RunStatus::Suspect:
      return "suspect";
    case RunStatus::Diverged:
      return "diverged";
    case RunStatus::Timeout:
      return "timeout";
    case RunStatus::Unsupported:
      return "unsupported";
    case RunStatus::Error:
      return "error";
  }
  return "error";
}

std::optional<RunStatus> runStatusNamed(std::string_view name) {
  for (RunStatus s : kRunStatuses)
    if (name == runStatusName(s)) return s;
  return std::nullopt;
}

std::string runStatusNameList() {
  std::string list;
  for (RunStatus s : kRunStatuses)
    list += (list.empty() ? "\"" : ", \"") + std::string(runStatusName(s)) + "\"";
  return list;
}

EngineRunResult SteppingEngine::run(const pbd::Scene& scene, const Method& method,
                                    const RunLength& /*length*/, const StepPlan& plan,
                                    double wallTimeLimit, RunObserver& observer) {
  using Clock = std::chrono::steady_clock;
  const auto secondsSince = [](Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
  };
  EngineRunResult result;
  const Clock::time_point start = Clock::now();
  Clock::time_point t0 = Clock::now();
  load(scene, method);
  result.busySeconds += secondsSince(t0);
  observer.begin(runFacts(), effectiveSettings(), StateCadence::EveryStep);
  State state;
  read(state);
  if (!observer.state(state, 0)) return result;
  for (long n = 1; n <= plan.steps; ++n) {
    t0 = Clock::now();
    step();
    result.busySeconds += secondsSince(t0);
    result.steps = n;
    read(state);
    if (!observer.state(state, n)) break;
    if (wallTimeLimit > 0 && secondsSince(start) > wallTimeLimit) {
      result.status = RunStatus::Timeout;
      std::ostringstream reason;
      reason << "stopped after " << wallTimeLimit << " s of wall time at t = " << state.time
             << " s (" << n << " of " << plan.steps << " steps)";
      result.reason = reason.str();
      break;
    }
  }
  result.stateHash = stateHash();
  return result;
}

const ParameterSpec* MethodInfo::find(const std::string& parameter) const {
  for (const ParameterSpec& p : parameters)
    if (p.name == parameter) return &p;
  return nullptr;
}

const ParameterValue& Method::value(const std::string& parameter, ParameterKind kind) const {
  const auto it = values.find(parameter);
  if (it == values.end())
    throw std::invalid_argument("method " + name + " has no parameter '" + parameter + "'");
  if (it->second.kind != kind)
    throw std::invalid_argument("method " + name + ": parameter " + parameter + " is a " +
                                parameterKindName(it->second.kind) + ", not a " +
                                parameterKindName(kind));
  return it->second;
}

double Method::real(const std::string& parameter) const {
  return value(parameter, ParameterKind::Real).number;
}

std::int64_t Method::integer(const std::string& parameter) const {
  return static_cast<std::int64_t>(value(parameter, ParameterKind::Integer).number);
}

bool Method::flag(const std::string& parameter) const {
  return value(parameter, ParameterKind::Bool).number != 0;
}

const std::string& Method::choice(const std::string& parameter) const {
  return value(parameter, ParameterKind::Choice).choice;
}

double Method::seconds(const std::string& parameter, double stepSize) const {
  const ParameterValue& v = value(parameter, ParameterKind::Duration);
  for (const ParameterSpec& spec : declarations)
    if (spec.name == parameter) return durationSeconds(spec, v, stepSize, name);
  throw std::invalid_argument("method " + name + ": parameter " + parameter + " is not declared");
}

std::map<std::string, std::string> Method::textValues() const {
  std::map<std::string, std::string> text;
  for (const auto& [key, v] : values)
    text[key] = v.text();
  return text;
}

Method resolveMethod(const MethodInfo& info, const std::map<std::string, std::string>& overrides) {
  Method resolved;
  resolved.name = info.name;
  resolved.declarations = info.parameters;
  for (const ParameterSpec& p : info.parameters)
    resolved.values[p.name] = parseParameter(p, p.defaultValue, info.name);
  for (const auto& [key, text] : overrides) {
    const ParameterSpec* spec = info.find(key);
    if (!spec) {
      std::vector<std::string> valid;
      for (const ParameterSpec& p : info.parameters)
        valid.push_back(p.name);
      throw std::invalid_argument("method " + info.name + " has no parameter '" + key +
                                  "' (parameters: " + pbd::nameList(valid) + ")" +
                                  pbd::didYouMean(key, valid));
    }
    resolved.values[key] = parseParameter(*spec, text, info.name);
  }
  return resolved;
}

}  // namespace pbdval
