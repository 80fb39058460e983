#include "validation/run_record.h"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <thread>

#include "adapters/fcl/distance_oracle.h"
#include "pbd/io/scene_loader.h"
#include "validation/atomic_file.h"
#include "validation/case_spec.h"
#include "validation/overrides.h"
#include "validation/references/reference.h"
#include "validation/trajectory.h"

namespace pbdval {
namespace {

using Json = nlohmann::json;

struct LoadedCase {
  pbd::Scene scene;
  CaseSpec spec;
  Method method;
};

LoadedCase loadCase(const RunRequest& request) {
  pbd::LoadOptions options;
  options.strict = request.strictScene;
  LoadedCase c;
  c.scene = pbd::loadScene(request.caseFile, options).scene;
  c.spec = parseCaseSpec(c.scene);
  const MethodInfo& info = findMethod(request.method);
  if (info.engine != request.engine)
    throw std::invalid_argument("method " + request.method + " belongs to engine " + info.engine +
                                ", not " + request.engine);
  std::vector<std::string> parameterNames;
  for (const MethodParameter& p : info.parameters)
    parameterNames.push_back(p.name);
  c.method =
      resolveMethod(request.method, applyAssignments(request.assignments, parameterNames, c.scene));
  return c;
}

RunLength lengthOf(const LoadedCase& c, const RunRequest& request) {
  return {defaultDuration(c.scene, c.spec),
          request.sampleInterval > 0 ? request.sampleInterval : c.spec.sampleInterval.value_or(0)};
}

/// A run of `engineName`/`method` on `scene` at step `fineStep`, sampled at the same times as
/// the run being measured (whose step is `coarseStep`).
std::optional<ReferenceTrajectory> referenceRun(const LoadedCase& c, const std::string& engineName,
                                                const Method& method, double fineStep,
                                                const RunLength& length, double coarseStep,
                                                std::vector<std::string>& notes) {
  pbd::Scene fine = c.scene;
  fine.simulation.timeStepSize = pbd::Real(fineStep);
  RunLength fineLength = length;
  if (fineLength.sampleInterval <= 0) fineLength.sampleInterval = coarseStep;
  ReferenceTrajectory reference;
  reference.description =
      engineName + "/" + method.name + " at h = " + formatNumber(fineStep) + " s";
  const std::unique_ptr<Engine> engine = makeEngine(engineName);
  RunCallbacks callbacks;
  callbacks.onSample = [&](const State& s) { reference.samples.push_back(s); };
  const RunOutcome outcome = runSimulation(*engine, fine, method, fineLength, callbacks);
  if (outcome.status != RunStatus::Ok) {
    notes.push_back("reference run " + reference.description + " " + runStatusName(outcome.status) +
                    ": " + outcome.reason);
    return std::nullopt;
  }
  return reference;
}

double integrationStep(const std::map<std::string, std::string>& settings, double stepSize) {
  const auto it = settings.find("subSteps");
  return it == settings.end() ? stepSize : stepSize / std::stod(it->second);
}

std::optional<ReferenceTrajectory> buildReference(const LoadedCase& c, const RunRequest& request,
                                                  const RunRecord& record,
                                                  const std::vector<State>& samples,
                                                  std::vector<std::string>& notes) {
  const double h = double(c.scene.simulation.timeStepSize);
  const RunLength length = lengthOf(c, request);
  if (request.referenceMode == "none") return std::nullopt;
  if (request.referenceMode == "fine")
    return referenceRun(
        c, request.engine, c.method,
        request.referenceStepSize > 0 ? request.referenceStepSize : h / request.fineDivisor, length,
        h, notes);
  const ReferenceSpec& spec = c.spec.reference;
  switch (spec.kind) {
    case ReferenceSpec::Kind::None:
      return std::nullopt;
    case ReferenceSpec::Kind::Fine:
      return referenceRun(c, request.engine, c.method, h / spec.stepDivisor, length, h, notes);
    case ReferenceSpec::Kind::Engine:
      return referenceRun(c, spec.engine, resolveMethod(spec.method, {}), h / spec.stepDivisor,
                          length, h, notes);
    case ReferenceSpec::Kind::Analytic: {
      std::vector<double> times;
      for (const State& s : samples)
        times.push_back(s.time);
      return buildAnalyticReference(c.scene, spec, times, integrationStep(record.settings, h));
    }
  }
  return std::nullopt;
}

/// The contact margin an engine reports it lets bodies overlap by (settings "contactMargin", m);
/// 0 when it reports none.
double contactMarginOf(const std::map<std::string, std::string>& settings) {
  const auto it = settings.find("contactMargin");
  return it == settings.end() ? 0.0 : std::stod(it->second);
}

/// Penetration depths from the FCL oracle, margins subtracted; empty when the scene has fewer
/// than two bodies with collision objects.
PenetrationQuery penetrationQuery(const pbd::Scene& scene, std::optional<DistanceOracle>& oracle,
                                  const std::map<std::string, std::string>& settings,
                                  std::vector<std::string>& notes) {
  int colliding = 0;
  for (const pbd::RigidBodyDesc& b : scene.rigidBodies)
    colliding += b.collision.type != pbd::CollisionObjectType::None ? 1 : 0;
  if (colliding < 2) return {};
  oracle.emplace(scene);
  for (const UnsupportedBody& u : oracle->unsupported())
    notes.push_back("penetration: " + u.message() + " (its pairs are not measured)");
  PenetrationOptions options;
  options.margins.global = contactMarginOf(settings);
  return [&oracle, options, &notes](const State& state) {
    const PenetrationReport report = oracle->penetrations(state, options);
    std::vector<double> depths;
    for (const PairPenetration& c : report.contacts)
      depths.push_back(c.depth);
    if (!report.failures.empty() && notes.size() < 50)
      notes.push_back("penetration query failed at t = " + formatNumber(state.time) + ": " +
                      report.failures.front().message);
    return depths;
  };
}

void mergeMetrics(MetricSet& into, MetricSet&& from) {
  for (auto& [name, value] : from.values)
    into.values[name] = value;
  for (auto& [type, summary] : from.jointErrorByType)
    into.jointErrorByType[type] = summary;
  for (std::string& note : from.notes)
    into.notes.push_back(std::move(note));
}

}  // namespace

RunRecord executeRun(const RunRequest& request) {
  RunRecord record;
  record.request = request;
  try {
    const LoadedCase c = loadCase(request);
    record.methodParameters = c.method.parameters;
    const std::unique_ptr<Engine> engine = makeEngine(request.engine);

    std::vector<State> samples;
    std::optional<AtomicFileWriter> csv;
    if (!request.trajectoryPath.empty()) {
      csv.emplace(request.trajectoryPath);
      writeCsvHeader(csv->stream());
    }
    RunCallbacks callbacks;
    callbacks.onSample = [&](const State& s) {
      samples.push_back(s);
      if (csv) writeCsvRows(csv->stream(), s);
    };
    const RunOutcome outcome =
        runSimulation(*engine, c.scene, c.method, lengthOf(c, request), callbacks);
    if (csv) csv->commit();

    record.status = outcome.status;
    record.reason = outcome.reason;
    record.settings = outcome.settings;
    record.stateHash = outcome.stateHash;
    record.metrics.values["wall_time_s"] = outcome.wallTime;
    record.metrics.values["steps"] = double(outcome.steps);
    if (outcome.wallTime > 0)
      record.metrics.values["real_time_factor"] = outcome.simulatedTime / outcome.wallTime;
    if (outcome.status != RunStatus::Ok) return record;

    std::vector<std::string> notes;
    std::optional<ReferenceTrajectory> reference;
    try {
      reference = buildReference(c, request, record, samples, notes);
    } catch (const std::exception& e) {
      notes.push_back(std::string("reference not available: ") + e.what());
    }
    if (reference && c.spec.reference.kind != ReferenceSpec::Kind::Analytic) {
      std::vector<double> times;
      for (const State& s : samples)
        times.push_back(s.time);
      reference = resampleReference(*reference, times);
    }
    if (reference) record.reference = reference->description;
    std::optional<DistanceOracle> oracle;
    MetricInputs inputs;
    inputs.scene = &c.scene;
    inputs.spec = &c.spec;
    inputs.samples = &samples;
    inputs.reference = reference ? &*reference : nullptr;
    inputs.penetration = penetrationQuery(c.scene, oracle, record.settings, notes);
    mergeMetrics(record.metrics, computeMetrics(inputs));
    for (std::string& note : notes)
      record.metrics.notes.push_back(std::move(note));
  } catch (const std::exception& e) {
    record.status = RunStatus::Error;
    record.reason = e.what();
  }
  return record;
}

// --- JSON ---------------------------------------------------------------------------------------

namespace {

Json requestJson(const RunRequest& r) {
  return {{"case", r.caseName},
          {"caseFile", r.caseFile},
          {"engine", r.engine},
          {"method", r.method},
          {"assignments", r.assignments},
          {"trajectory", r.trajectoryPath},
          {"referenceMode", r.referenceMode},
          {"fineDivisor", r.fineDivisor}};
}

RunStatus statusFromName(const std::string& name, const std::string& where) {
  for (RunStatus s : {RunStatus::Ok, RunStatus::Diverged, RunStatus::Timeout,
                      RunStatus::Unsupported, RunStatus::Error})
    if (name == runStatusName(s)) return s;
  throw std::invalid_argument(where + ": status: unknown status '" + name + "'");
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
  j["metrics"] = metrics;
  j["joint_error_by_type"] = byType;
  j["notes"] = record.metrics.notes;
  j["state_hash"] = record.stateHash;
  j["reference"] = record.reference;
  return j.dump(2);
}

RunRecord recordFromJsonText(const std::string& text, const std::string& where) {
  try {
    const Json j = Json::parse(text);
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

// --- Isolation
// ------------------------------------------------------------------------------------

namespace {

using Clock = std::chrono::steady_clock;

struct Child {
  pid_t pid = -1;
  std::size_t index = 0;
  Clock::time_point start;
  bool killedForTimeout = false;
};

std::string resultFile(const std::string& folder, std::size_t index) {
  return folder + "/run-" + std::to_string(::getpid()) + "-" + std::to_string(index) + ".json";
}

RunRecord collect(const Child& child, int waitStatus, const RunRequest& request,
                  const std::string& file, double timeout) {
  RunRecord record;
  record.request = request;
  if (child.killedForTimeout) {
    record.status = RunStatus::Timeout;
    std::ostringstream reason;
    reason << "exceeded the wall-time limit of " << timeout << " s and was stopped";
    record.reason = reason.str();
  } else if (WIFSIGNALED(waitStatus)) {
    const int signal = WTERMSIG(waitStatus);
    record.status = RunStatus::Error;
    record.reason = "engine process crashed with signal " + std::to_string(signal) + " (" +
                    ::strsignal(signal) + ")";
  } else if (WIFEXITED(waitStatus) && WEXITSTATUS(waitStatus) == 0) {
    std::ifstream in(file);
    std::stringstream text;
    text << in.rdbuf();
    try {
      record = recordFromJsonText(text.str(), file);
    } catch (const std::exception& e) {
      record.status = RunStatus::Error;
      record.reason = std::string("unreadable result from the engine process: ") + e.what();
    }
  } else {
    record.status = RunStatus::Error;
    record.reason = "engine process exited with status " + std::to_string(WEXITSTATUS(waitStatus)) +
                    " without a result";
  }
  std::remove(file.c_str());
  // A child that died mid-write leaves its temporary trajectory file behind.
  if (!request.trajectoryPath.empty()) {
    const std::string temporary = request.trajectoryPath + ".tmp-" + std::to_string(child.pid);
    std::remove(temporary.c_str());
  }
  return record;
}

}  // namespace

RunScheduler::RunScheduler(int jobs, double timeout, std::string scratchFolder)
    : jobs_(std::max(1, jobs)), timeout_(timeout), scratchFolder_(std::move(scratchFolder)) {}

std::vector<RunRecord> RunScheduler::runAll(
    const std::vector<RunRequest>& requests,
    const std::function<void(const RunRecord&, std::size_t, std::size_t)>& onFinished,
    const std::function<void(const std::vector<const RunRequest*>&)>& onTick) {
  createFolders(scratchFolder_);
  std::vector<RunRecord> records(requests.size());
  std::vector<Child> running;
  std::size_t next = 0, done = 0;
  while (done < requests.size()) {
    while (static_cast<int>(running.size()) < jobs_ && next < requests.size()) {
      std::fflush(nullptr);  // nothing buffered may be written twice
      const std::string file = resultFile(scratchFolder_, next);
      const pid_t pid = ::fork();
      if (pid < 0) throw std::runtime_error(std::string("fork failed: ") + std::strerror(errno));
      if (pid == 0) {
        const RunRecord record = executeRun(requests[next]);
        try {
          writeFileAtomically(file, toJsonText(record));
        } catch (...) {
          ::_exit(3);
        }
        ::_exit(0);
      }
      running.push_back({pid, next, Clock::now(), false});
      ++next;
    }
    int status = 0;
    const pid_t finished = ::waitpid(-1, &status, WNOHANG);
    if (finished > 0) {
      for (std::size_t k = 0; k < running.size(); ++k) {
        if (running[k].pid != finished) continue;
        const Child child = running[k];
        running.erase(running.begin() + static_cast<long>(k));
        records[child.index] = collect(child, status, requests[child.index],
                                       resultFile(scratchFolder_, child.index), timeout_);
        ++done;
        if (onFinished) onFinished(records[child.index], done, requests.size());
        break;
      }
      continue;
    }
    for (Child& child : running) {
      const double elapsed = std::chrono::duration<double>(Clock::now() - child.start).count();
      if (timeout_ > 0 && elapsed > timeout_ && !child.killedForTimeout) {
        ::kill(child.pid, SIGKILL);
        child.killedForTimeout = true;
      }
    }
    if (onTick) {
      std::vector<const RunRequest*> active;
      for (const Child& child : running)
        active.push_back(&requests[child.index]);
      onTick(active);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return records;
}

}  // namespace pbdval
