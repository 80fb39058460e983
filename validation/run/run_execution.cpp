// Runs one request in this process: loads the case, resolves the method and the `--set`
// assignments, runs the engine, builds the reference, computes the metrics
// (validation/measure/metrics.h, the one measurement path) and writes the trajectory.
#include "validation/run/run_execution.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>

#include "pbd/io/scene_loader.h"
#include "validation/io/atomic_file.h"
#include "validation/io/trajectory.h"
#include "validation/measure/oracle/distance_oracle.h"
#include "validation/measure/references/reference.h"
#include "validation/measure/sanity.h"
#include "validation/run/case_spec.h"
#include "validation/run/overrides.h"
#include "validation/run/run_plan.h"
#include "validation/run/simulation.h"

namespace pbdval {
namespace {

struct LoadedCase {
  pbd::Scene scene;
  CaseSpec spec;
  Method method;
};

LoadedCase loadCase(const RunRequest& request, const EngineRegistry& registry) {
  pbd::LoadOptions options;
  options.strict = request.strictScene;
  LoadedCase c;
  c.scene = pbd::loadScene(request.caseFile, options).scene;
  c.spec = parseCaseSpec(c.scene, registry);
  const MethodInfo& info = registry.method(request.method);
  if (info.engine != request.engine)
    throw std::invalid_argument("method " + request.method + " belongs to engine " + info.engine +
                                ", not " + request.engine);
  c.method = resolveMethod(info, applyAssignments(request.assignments, info, c.scene));
  return c;
}

}  // namespace

std::string referenceEngineOf(const RunRequest& request, const EngineRegistry& registry) {
  if (isEngineReference(request.referenceMode))
    return registry.method(parseEngineReference(request.referenceMode, registry).method).engine;
  if (!request.referenceMode.empty()) return "";  // "fine", "none"
  // Cheap first: a case whose Validation.reference is no engine's (nearly all) is not loaded
  // (a scene's meshes take 0.1-0.3 s); the others are read the one way executeRun reads them.
  std::ifstream file(request.caseFile);
  const nlohmann::json root = nlohmann::json::parse(file, nullptr, false);
  if (!root.is_discarded()) {
    const nlohmann::json* type = nullptr;
    if (root.is_object() && root.contains("Validation") && root["Validation"].is_object() &&
        root["Validation"].contains("reference") && root["Validation"]["reference"].is_object() &&
        root["Validation"]["reference"].contains("type"))
      type = &root["Validation"]["reference"]["type"];
    if (!type || *type != "engine") return "";
  }
  pbd::LoadOptions options;
  options.strict = request.strictScene;
  const CaseSpec spec = parseCaseSpec(pbd::loadScene(request.caseFile, options).scene, registry);
  return spec.reference.kind == ReferenceSpec::Kind::Engine ? spec.reference.engine : "";
}

namespace {

RunLength lengthOf(const LoadedCase& c, const RunRequest& request) {
  return {defaultDuration(c.scene, c.spec),
          request.sampleInterval > 0 ? request.sampleInterval : c.spec.sampleInterval.value_or(0)};
}

/// A run of `engineName`/`method` on `scene` at step `fineStep`, sampled at the same times as
/// the run being measured (whose step is `coarseStep`).
std::optional<ReferenceTrajectory> referenceRun(const LoadedCase& c, const EngineRegistry& registry,
                                                const std::string& engineName, const Method& method,
                                                double fineStep, const RunLength& length,
                                                double coarseStep,
                                                std::vector<std::string>& notes) {
  pbd::Scene fine = c.scene;
  fine.simulation.timeStepSize = pbd::Real(fineStep);
  RunLength fineLength = length;
  if (fineLength.sampleInterval <= 0) fineLength.sampleInterval = coarseStep;
  ReferenceTrajectory reference;
  reference.description =
      engineName + "/" + method.name + " at h = " + formatNumber(fineStep) + " s";
  const std::unique_ptr<Engine> engine = registry.make(engineName);
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

std::optional<ReferenceTrajectory> buildReference(
    const LoadedCase& c, const EngineRegistry& registry, const RunRequest& request,
    const RunRecord& record, const std::vector<State>& samples, std::vector<std::string>& notes) {
  const double h = double(c.scene.simulation.timeStepSize);
  const RunLength length = lengthOf(c, request);
  if (request.referenceMode == "none") return std::nullopt;
  if (isEngineReference(request.referenceMode)) {
    const EngineReference reference = parseEngineReference(request.referenceMode, registry);
    const MethodInfo& info = registry.method(reference.method);
    LoadedCase referenceCase = c;
    const Method method =
        resolveMethod(info, applyAssignments(reference.assignments, info, referenceCase.scene));
    std::optional<ReferenceTrajectory> trajectory =
        referenceRun(referenceCase, registry, info.engine, method, h, length, h, notes);
    if (trajectory && !reference.assignments.empty())
      trajectory->description +=
          " (" + request.referenceMode.substr(reference.method.size() + 1) + ")";
    return trajectory;
  }
  if (request.referenceMode == "fine")
    return referenceRun(
        c, registry, request.engine, c.method,
        request.referenceStepSize > 0 ? request.referenceStepSize : h / request.fineDivisor, length,
        h, notes);
  const ReferenceSpec& spec = c.spec.reference;
  switch (spec.kind) {
    case ReferenceSpec::Kind::None:
      return std::nullopt;
    case ReferenceSpec::Kind::Fine:
      return referenceRun(c, registry, request.engine, c.method, h / spec.stepDivisor, length, h,
                          notes);
    case ReferenceSpec::Kind::Engine:
      return referenceRun(c, registry, spec.engine, registry.resolve(spec.method),
                          h / spec.stepDivisor, length, h, notes);
    case ReferenceSpec::Kind::Analytic: {
      std::vector<double> times;
      for (const State& s : samples)
        times.push_back(s.time);
      return buildAnalyticReference(c.scene, spec, times,
                                    h / std::max(1, record.facts.integratorStepsPerSceneStep));
    }
  }
  return std::nullopt;
}

/// Penetration depths from the FCL oracle, margins subtracted; empty when the scene has fewer
/// than two bodies with collision objects.
PenetrationQuery penetrationQuery(const pbd::Scene& scene, std::optional<DistanceOracle>& oracle,
                                  double contactMargin, std::vector<std::string>& notes) {
  int colliding = 0;
  for (const pbd::RigidBodyDesc& b : scene.rigidBodies)
    colliding += b.collision.type != pbd::CollisionObjectType::None ? 1 : 0;
  if (colliding < 2) return {};
  oracle.emplace(scene);
  for (const UnsupportedBody& u : oracle->unsupported())
    notes.push_back("penetration: " + u.message() + " (its pairs are not measured)");
  PenetrationOptions options;
  options.margins.global = contactMargin;
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

void checkContactMargin(double margin) {
  if (!(std::abs(margin) <= kMaxContactMargin))
    throw std::invalid_argument("contact_margin: expected a number of metres in [-" +
                                formatNumber(kMaxContactMargin) + ", " +
                                formatNumber(kMaxContactMargin) +
                                "] (an engine's contact margin), got " + formatNumber(margin));
}

MetricSet measureSamples(const pbd::Scene& scene, const CaseSpec& spec,
                         const std::vector<State>& samples, const ReferenceTrajectory* reference,
                         double contactMargin, MetricSeries* series) {
  checkContactMargin(contactMargin);
  // A diverged trajectory has no metrics (the runner measures ok runs only): its first
  // non-finite sample is named instead of handing NaN to the energy sums and the FCL oracle.
  for (std::size_t k = 0; k < samples.size(); ++k) {
    std::string problem = divergenceReason(samples[k]);
    if (problem.empty() && !std::isfinite(samples[k].time)) problem = "its time is not finite";
    if (!problem.empty())
      throw EngineDivergence("sample " + std::to_string(k) + ": " + problem +
                             "; a diverged trajectory is not measured");
  }
  std::vector<std::string> notes;
  std::optional<DistanceOracle> oracle;
  MetricInputs inputs;
  inputs.scene = &scene;
  inputs.spec = &spec;
  inputs.samples = &samples;
  inputs.reference = reference;
  inputs.penetration = penetrationQuery(scene, oracle, contactMargin, notes);
  inputs.series = series;
  MetricSet metrics = computeMetrics(inputs);
  for (std::string& note : notes)
    metrics.notes.push_back(std::move(note));
  return metrics;
}

RunRecord executeRun(const RunRequest& request, const EngineRegistry& registry) {
  RunRecord record;
  record.request = request;
  try {
    const LoadedCase c = loadCase(request, registry);
    record.methodParameters = c.method.textValues();
    const std::unique_ptr<Engine> engine = registry.make(request.engine);

    std::vector<State> samples;
    // The trajectory file, by its extension: CSV rows as samples come, or NPY (the samples
    // kept for the metrics, written at once: no text conversion).
    const std::string& path = request.trajectoryPath;
    const bool npy = hasNpyExtension(path);
    std::optional<AtomicFileWriter> trajectory;
    if (!path.empty()) {
      trajectory.emplace(path);
      if (!npy) writeCsvHeader(trajectory->stream());
    }
    RunCallbacks callbacks;
    CsvRowWriter rows;
    callbacks.onSample = [&](const State& s) {
      samples.push_back(s);
      if (trajectory && !npy) rows.write(trajectory->stream(), s);
    };
    const RunOutcome outcome =
        runSimulation(*engine, c.scene, c.method, lengthOf(c, request), callbacks);
    if (trajectory) {
      if (npy) writeTrajectoryNpy(trajectory->stream(), samples);
      trajectory->commit();
      // The particles and the rod segments beside it, in the same format, when the engine
      // read any back.
      const TrajectoryFormat format = npy ? TrajectoryFormat::Npy : TrajectoryFormat::Csv;
      if (!samples.empty() && !samples.front().particles.empty()) {
        AtomicFileWriter particles(particlePathFor(path));
        writeParticleTrajectory(particles.stream(), samples, format);
        particles.commit();
      }
      if (!samples.empty() && !samples.front().segments.empty()) {
        AtomicFileWriter segments(segmentPathFor(path));
        writeSegmentTrajectory(segments.stream(), samples, format);
        segments.commit();
      }
    }

    record.status = outcome.status;
    record.reason = outcome.reason;
    record.settings = outcome.settings;
    record.facts = outcome.facts;
    record.stateHash = outcome.stateHash;
    record.metrics.values["wall_time_s"] = outcome.wallTime;
    record.metrics.values["steps"] = double(outcome.steps);
    if (outcome.wallTime > 0)
      record.metrics.values["real_time_factor"] = outcome.simulatedTime / outcome.wallTime;
    // (runSimulation has held the states to the boundary checks: a violation is an error, or
    // suspect for velocities between states several integrator steps apart.)
    if (!isMeasured(outcome.status)) return record;

    std::vector<std::string> notes;
    std::optional<ReferenceTrajectory> reference;
    try {
      reference = buildReference(c, registry, request, record, samples, notes);
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
    mergeMetrics(record.metrics,
                 measureSamples(c.scene, c.spec, samples, reference ? &*reference : nullptr,
                                record.facts.contactMargin));
    for (std::string& note : notes)
      record.metrics.notes.push_back(std::move(note));
    // Physics sanity, whatever the case declares: an ok run that breaks a bound the scene
    // implies is suspect (its metrics are kept).
    if (const std::optional<CheckViolation> violation = sanityViolation(c.scene, c.spec, samples)) {
      record.reason = record.status == RunStatus::Suspect
                          ? record.reason + "; " + violation->message
                          : violation->message;
      record.status = RunStatus::Suspect;
    }
  } catch (const std::exception& e) {
    record.status = RunStatus::Error;
    record.reason = e.what();
  }
  return record;
}

}  // namespace pbdval
