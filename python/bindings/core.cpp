// pbdval._core: the C++ side of `import pbdval` (docs/python.md#import-pbdval). It exposes the
// same scene loader, engine registry, stepping loop (validation/run/simulation.h) and measurement
// path (validation/run/run_execution.h measureSamples) that the pbdval command uses; nothing here
// computes a metric or interprets a scene of its own. The pure-Python parts (python/pbdval/)
// wrap these functions in typed classes; this module's names start with an underscore where
// only they are meant to call them.
//
// Arrays: positions (N,3) m, quaternions (N,4) in (w, x, y, z) order (the body's scene frame →
// world), velocities (N,3) m/s and angular velocities (N,3) rad/s, all in the world frame,
// bodies in scene order; trajectories stack them over samples: (T,N,3), (T,N,4).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "adapters/registry.h"
#include "pbd/io/scene_loader.h"
#include "pbd/io/suggestion.h"
#include "pbdval/build_info.h"
#include "python/bindings/mujoco_model.h"
#include "validation/external/resolved_scene.h"
#include "validation/external/standard_engines.h"
#include "validation/io/results.h"
#include "validation/io/trajectory.h"
#include "validation/measure/measure_trajectory.h"
#include "validation/measure/mechanics.h"
#include "validation/measure/metrics.h"
#include "validation/measure/references/reference.h"
#include "validation/run/case_spec.h"
#include "validation/run/interrupts.h"
#include "validation/run/overrides.h"
#include "validation/run/run_execution.h"
#include "validation/run/simulation.h"
#include "validation/verdict/gate.h"

namespace py = pybind11;

namespace pbdval::python {
namespace {

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

/// A new C-contiguous array of `shape` (a braced single extent would pick another constructor).
Array newArray(std::vector<py::ssize_t> shape) {
  return Array(std::move(shape));
}

/// A trajectory file that cannot be read: pbdval.ResultsError.
struct ResultsFileError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// A loaded scene and the file it came from (relative mesh paths are already resolved).
struct SceneHandle {
  std::shared_ptr<const pbd::Scene> scene;
  std::string file;
  std::vector<std::string> warnings;
};

/// The engines of the pbdval command: built in + the catalogue (read when created).
struct Registry {
  EngineRegistry engines = standardEngines([](const char* name) { return std::getenv(name); });
};

py::object jsonToPython(const nlohmann::json& value) {
  return py::module_::import("json").attr("loads")(value.dump());
}

py::dict parameterDict(const ParameterSpec& spec) {
  py::dict d;
  d["name"] = spec.name;
  d["kind"] = std::string(parameterKindName(spec.kind));
  d["default"] = spec.defaultValue;
  d["expected"] = spec.expectation();
  d["unit"] = spec.unit;
  d["description"] = spec.description;
  if (spec.kind == ParameterKind::Choice) d["choices"] = spec.choices;
  if (std::isfinite(spec.minimum)) d["minimum"] = spec.minimum;
  if (std::isfinite(spec.maximum)) d["maximum"] = spec.maximum;
  return d;
}

py::dict methodDict(const MethodInfo& info, const EngineEntry& engine) {
  py::dict d;
  d["name"] = info.name;
  d["engine"] = info.engine;
  d["description"] = info.description;
  d["default"] = engine.defaultMethod == info.name;
  py::list parameters;
  for (const ParameterSpec& spec : info.parameters)
    parameters.append(parameterDict(spec));
  d["parameters"] = parameters;
  return d;
}

/// Python parameter values as the text `--set` would give (bool → true/false, numbers in the
/// shortest form that reads back exactly).
std::string parameterText(const py::handle& value) {
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>() ? "true" : "false";
  if (py::isinstance<py::int_>(value)) return py::str(value).cast<std::string>();
  if (py::isinstance<py::float_>(value)) return formatNumber(value.cast<double>());
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
    std::string text;
    for (const py::handle& item : value) {
      if (!text.empty()) text += ",";
      text += parameterText(item);
    }
    return text;
  }
  throw std::invalid_argument(  // pbdval.ArgumentError
      "parameter values must be bool, int, float, str or a list of numbers, got " +
      py::str(py::type::of(value)).cast<std::string>());
}

std::vector<std::string> assignmentsOf(const py::dict& values) {
  std::vector<std::string> assignments;
  for (const auto& [key, value] : values)
    assignments.push_back(py::str(key).cast<std::string>() + "=" + parameterText(value));
  return assignments;
}

/// The run configuration: the method, the scene with the Simulation settings applied.
struct Configured {
  pbd::Scene scene;
  const EngineEntry* engine = nullptr;
  Method method;
};

Configured configure(const Registry& registry, const SceneHandle& scene, const std::string& method,
                     const py::dict& parameters) {
  Configured c;
  c.scene = *scene.scene;
  const MethodInfo& info = registry.engines.method(method);
  c.engine = &registry.engines.engine(info.engine);
  // A parameter the engine ignores (subSteps for ODE) is refused, as `--set` is.
  checkAssignments(assignmentsOf(parameters), {info.name}, registry.engines, "parameter");
  c.method = resolveMethod(info, applyAssignments(assignmentsOf(parameters), info, c.scene));
  return c;
}

py::dict statesDict(const std::vector<State>& samples, std::size_t bodies) {
  const py::ssize_t t = py::ssize_t(samples.size());
  const py::ssize_t n = py::ssize_t(bodies);
  Array times = newArray({t});
  Array positions = newArray({t, n, 3}), quaternions = newArray({t, n, 4});
  Array velocities = newArray({t, n, 3}), angular = newArray({t, n, 3});
  py::array_t<long> ids(std::vector<py::ssize_t>{n});
  auto T = times.mutable_unchecked<1>();
  auto P = positions.mutable_unchecked<3>();
  auto Q = quaternions.mutable_unchecked<3>();
  auto V = velocities.mutable_unchecked<3>();
  auto W = angular.mutable_unchecked<3>();
  auto I = ids.mutable_unchecked<1>();
  for (py::ssize_t k = 0; k < t; ++k) {
    const State& s = samples[std::size_t(k)];
    if (s.bodies.size() != bodies)
      throw std::invalid_argument("sample " + std::to_string(k) + " holds " +
                                  std::to_string(s.bodies.size()) + " bodies, expected " +
                                  std::to_string(bodies));
    T(k) = s.time;
    for (py::ssize_t b = 0; b < n; ++b) {
      const BodyState& body = s.bodies[std::size_t(b)];
      if (k == 0) I(b) = body.id;
      for (int a = 0; a < 3; ++a) {
        P(k, b, a) = double(body.position[a]);
        V(k, b, a) = double(body.velocity[a]);
        W(k, b, a) = double(body.angularVelocity[a]);
      }
      Q(k, b, 0) = double(body.rotation.w());
      Q(k, b, 1) = double(body.rotation.x());
      Q(k, b, 2) = double(body.rotation.y());
      Q(k, b, 3) = double(body.rotation.z());
    }
  }
  py::dict d;
  d["times"] = times;
  d["ids"] = ids;
  d["positions"] = positions;
  d["quaternions"] = quaternions;
  d["velocities"] = velocities;
  d["angular_velocities"] = angular;
  // Particles (cloth and solid vertices) when the engine reads them back: (T, P, 3) each.
  if (!samples.empty() && !samples.front().particles.empty()) {
    const py::ssize_t p = py::ssize_t(samples.front().particles.size());
    Array particlePositions = newArray({t, p, 3}), particleVelocities = newArray({t, p, 3});
    auto X = particlePositions.mutable_unchecked<3>();
    auto U = particleVelocities.mutable_unchecked<3>();
    for (py::ssize_t k = 0; k < t; ++k) {
      const State& s = samples[std::size_t(k)];
      if (py::ssize_t(s.particles.size()) != p)
        throw std::invalid_argument("sample " + std::to_string(k) + " holds " +
                                    std::to_string(s.particles.size()) + " particles, expected " +
                                    std::to_string(p));
      for (py::ssize_t i = 0; i < p; ++i)
        for (int a = 0; a < 3; ++a) {
          X(k, i, a) = double(s.particles[std::size_t(i)].position[a]);
          U(k, i, a) = double(s.particles[std::size_t(i)].velocity[a]);
        }
    }
    d["particle_positions"] = particlePositions;
    d["particle_velocities"] = particleVelocities;
  }
  // Cosserat-rod segments when the engine reads them back: rotations (T, S, 4) as (w, x, y, z),
  // angular velocities (T, S, 3).
  if (!samples.empty() && !samples.front().segments.empty()) {
    const py::ssize_t segments = py::ssize_t(samples.front().segments.size());
    Array rotations = newArray({t, segments, 4}), angularVelocities = newArray({t, segments, 3});
    auto R = rotations.mutable_unchecked<3>();
    auto Omega = angularVelocities.mutable_unchecked<3>();
    for (py::ssize_t k = 0; k < t; ++k) {
      const State& s = samples[std::size_t(k)];
      if (py::ssize_t(s.segments.size()) != segments)
        throw std::invalid_argument("sample " + std::to_string(k) + " holds " +
                                    std::to_string(s.segments.size()) + " rod segments, expected " +
                                    std::to_string(segments));
      for (py::ssize_t i = 0; i < segments; ++i) {
        const SegmentState& g = s.segments[std::size_t(i)];
        R(k, i, 0) = double(g.rotation.w());
        R(k, i, 1) = double(g.rotation.x());
        R(k, i, 2) = double(g.rotation.y());
        R(k, i, 3) = double(g.rotation.z());
        for (int a = 0; a < 3; ++a)
          Omega(k, i, a) = double(g.angularVelocity[a]);
      }
    }
    d["segment_rotations"] = rotations;
    d["segment_angular_velocities"] = angularVelocities;
  }
  return d;
}

void requireShape(const Array& a, const char* name, py::ssize_t t, py::ssize_t n, py::ssize_t w) {
  if (a.ndim() != 3 || a.shape(0) != t || a.shape(1) != n || a.shape(2) != w)
    throw std::invalid_argument(std::string(name) + ": expected an array of shape (" +
                                std::to_string(t) + ", " + std::to_string(n) + ", " +
                                std::to_string(w) + ")");
}

/// Samples from trajectory arrays (the inverse of statesDict); ids from the scene.
/// `particlePositions` and `particleVelocities`: None (no particles) or both (T, P, 3), P the
/// scene's particle count; `segmentRotations` (T, S, 4) (w, x, y, z) and
/// `segmentAngularVelocities` (T, S, 3): None or both, S the scene's rod segment count.
std::vector<State> samplesOf(const pbd::Scene& scene, const Array& times, const Array& positions,
                             const Array& quaternions, const Array& velocities,
                             const Array& angularVelocities,
                             const py::object& particlePositions = py::none(),
                             const py::object& particleVelocities = py::none(),
                             const py::object& segmentRotations = py::none(),
                             const py::object& segmentAngularVelocities = py::none()) {
  if (times.ndim() != 1) throw std::invalid_argument("times: expected a 1-D array");
  const py::ssize_t t = times.shape(0);
  const py::ssize_t n = py::ssize_t(scene.rigidBodies.size());
  requireShape(positions, "positions", t, n, 3);
  requireShape(quaternions, "quaternions", t, n, 4);
  requireShape(velocities, "velocities", t, n, 3);
  requireShape(angularVelocities, "angular_velocities", t, n, 3);
  auto T = times.unchecked<1>();
  auto P = positions.unchecked<3>();
  auto Q = quaternions.unchecked<3>();
  auto V = velocities.unchecked<3>();
  auto W = angularVelocities.unchecked<3>();
  std::vector<State> samples(static_cast<std::size_t>(t));
  for (py::ssize_t k = 0; k < t; ++k) {
    State& s = samples[std::size_t(k)];
    s.time = T(k);
    s.bodies.resize(std::size_t(n));
    for (py::ssize_t b = 0; b < n; ++b) {
      BodyState& body = s.bodies[std::size_t(b)];
      body.id = scene.rigidBodies[std::size_t(b)].id;
      body.position = Vector3(Real(P(k, b, 0)), Real(P(k, b, 1)), Real(P(k, b, 2)));
      body.velocity = Vector3(Real(V(k, b, 0)), Real(V(k, b, 1)), Real(V(k, b, 2)));
      body.angularVelocity = Vector3(Real(W(k, b, 0)), Real(W(k, b, 1)), Real(W(k, b, 2)));
      body.rotation =
          Quaternion(Real(Q(k, b, 0)), Real(Q(k, b, 1)), Real(Q(k, b, 2)), Real(Q(k, b, 3)));
    }
  }
  if (particlePositions.is_none() != particleVelocities.is_none())
    throw std::invalid_argument(
        "particle_positions and particle_velocities: give both (T, P, 3) arrays or neither");
  if (!particlePositions.is_none()) {
    const py::ssize_t p = py::ssize_t(scene.particles.size());
    const Array x = particlePositions.cast<Array>(), u = particleVelocities.cast<Array>();
    requireShape(x, "particle_positions", t, p, 3);
    requireShape(u, "particle_velocities", t, p, 3);
    auto X = x.unchecked<3>();
    auto U = u.unchecked<3>();
    for (py::ssize_t k = 0; k < t; ++k) {
      std::vector<ParticleState>& particles = samples[std::size_t(k)].particles;
      particles.resize(std::size_t(p));
      for (py::ssize_t i = 0; i < p; ++i) {
        particles[std::size_t(i)].position =
            Vector3(Real(X(k, i, 0)), Real(X(k, i, 1)), Real(X(k, i, 2)));
        particles[std::size_t(i)].velocity =
            Vector3(Real(U(k, i, 0)), Real(U(k, i, 1)), Real(U(k, i, 2)));
      }
    }
  }
  if (segmentRotations.is_none() != segmentAngularVelocities.is_none())
    throw std::invalid_argument(
        "segment_rotations and segment_angular_velocities: give both ((T, S, 4) and (T, S, 3) "
        "arrays) or neither");
  if (!segmentRotations.is_none()) {
    py::ssize_t count = 0;
    for (const pbd::LineModelDesc& model : scene.lineModels)
      count += py::ssize_t(model.segmentCount());
    const Array r = segmentRotations.cast<Array>(), w = segmentAngularVelocities.cast<Array>();
    requireShape(r, "segment_rotations", t, count, 4);
    requireShape(w, "segment_angular_velocities", t, count, 3);
    auto R = r.unchecked<3>();
    auto Omega = w.unchecked<3>();
    for (py::ssize_t k = 0; k < t; ++k) {
      std::vector<SegmentState>& segments = samples[std::size_t(k)].segments;
      segments.resize(std::size_t(count));
      for (py::ssize_t i = 0; i < count; ++i) {
        segments[std::size_t(i)].rotation =
            Quaternion(Real(R(k, i, 0)), Real(R(k, i, 1)), Real(R(k, i, 2)), Real(R(k, i, 3)));
        segments[std::size_t(i)].angularVelocity =
            Vector3(Real(Omega(k, i, 0)), Real(Omega(k, i, 1)), Real(Omega(k, i, 2)));
      }
    }
  }
  return samples;
}

py::dict metricsDict(const MetricSet& metrics) {
  py::dict values;
  for (const auto& [name, value] : metrics.values)
    values[py::str(name)] = value;
  py::dict byType;
  for (const auto& [type, s] : metrics.jointErrorByType) {
    py::dict d;
    d["joints"] = s.joints;
    d["joint_error_linear_max"] = s.linearMax;
    d["joint_error_linear_rms"] = s.linearRms;
    if (s.hasAngular) {
      d["joint_error_angular_max"] = s.angularMax;
      d["joint_error_angular_rms"] = s.angularRms;
    }
    if (!s.trackingQuantity.empty()) {
      d["tracking_quantity"] = s.trackingQuantity;
      d["tracking_max"] = s.trackingMax;
      d["tracking_rms"] = s.trackingRms;
    }
    byType[py::str(type)] = d;
  }
  py::dict d;
  d["values"] = values;
  d["joint_error_by_type"] = byType;
  d["notes"] = metrics.notes;
  return d;
}

/// A scene loaded into one engine with one method, stepped from Python.
class Stepper {
 public:
  Stepper(const Registry& registry, const SceneHandle& scene, const std::string& method,
          const py::dict& parameters)
      : configured_(configure(registry, scene, method, parameters)) {
    engine_ = registry.engines.makeStepping(configured_.engine->name);
    const std::vector<std::string> missing =
        engine_->unsupported(configured_.scene, configured_.method);
    if (!missing.empty()) {
      std::string text;
      for (const std::string& m : missing)
        text += (text.empty() ? "" : "; ") + m;
      throw UnsupportedScene(configured_.method.name + " cannot run this scene: " + text);
    }
    engine_->load(configured_.scene, configured_.method);
    engine_->read(state_);
  }

  struct UnsupportedScene : std::invalid_argument {
    using std::invalid_argument::invalid_argument;
  };

  void step(long count) {
    if (count < 0)
      throw std::invalid_argument("step: count must be >= 0, got " + std::to_string(count));
    if (double(count) > kMaxStepsPerRun)
      throw std::invalid_argument(
          "step: count must be at most " + formatNumber(kMaxStepsPerRun) +
          " (the most steps of one run, validation/run/simulation.h), got " +
          std::to_string(count));
    bool interrupted = false;
    {
      py::gil_scoped_release release;
      // Ctrl-C: Python's signal handlers run only with the GIL, so it is taken about every
      // 50 ms of stepping to run them (PyErr_CheckSignals); an exception they raise
      // (KeyboardInterrupt) ends the call after the step under way.
      using Clock = std::chrono::steady_clock;
      Clock::time_point lastCheck = Clock::now();
      for (long i = 0; i < count; ++i) {
        engine_->step();
        if ((i & 15) == 15 && Clock::now() - lastCheck > std::chrono::milliseconds(50)) {
          lastCheck = Clock::now();
          py::gil_scoped_acquire acquire;
          if (PyErr_CheckSignals() != 0) {
            interrupted = true;
            break;
          }
        }
      }
    }
    engine_->read(state_);
    if (interrupted) throw py::error_already_set();
    const std::string reason = divergenceReason(state_);
    if (!reason.empty())
      throw EngineDivergence("diverged at t = " + formatNumber(state_.time) + ": " + reason);
  }

  double time() const { return state_.time; }
  std::size_t bodyCount() const { return configured_.scene.rigidBodies.size(); }

  /// The bodies' states into `packed` (N, 14): id, x y z, qw qx qy qz, vx vy vz, wx wy wz.
  /// `packed` is written in place: an array that is not C-contiguous float64 and writeable
  /// is refused (converting it would fill a copy the caller never sees).
  double readInto(const py::array& packed) {
    engine_->read(state_);
    const py::ssize_t n = py::ssize_t(state_.bodies.size());
    const bool layout = py::isinstance<py::array_t<double>>(packed) &&
                        (packed.flags() & py::array::c_style) != 0 && packed.writeable();
    if (!layout || packed.ndim() != 2 || packed.shape(0) != n || packed.shape(1) != 14)
      throw std::invalid_argument(
          "read: expected a writeable C-contiguous float64 array of shape (" + std::to_string(n) +
          ", 14), got " + py::str(packed.dtype()).cast<std::string>() + " of shape " +
          py::str(py::tuple(py::cast(
                      std::vector<py::ssize_t>(packed.shape(), packed.shape() + packed.ndim()))))
              .cast<std::string>() +
          ((packed.flags() & py::array::c_style) != 0 ? "" : ", not C-contiguous") +
          (packed.writeable() ? "" : ", read-only"));
    double* out = static_cast<double*>(packed.request(true).ptr);
    for (const BodyState& b : state_.bodies) {
      out[0] = double(b.id);
      out[1] = double(b.position.x());
      out[2] = double(b.position.y());
      out[3] = double(b.position.z());
      out[4] = double(b.rotation.w());
      out[5] = double(b.rotation.x());
      out[6] = double(b.rotation.y());
      out[7] = double(b.rotation.z());
      out[8] = double(b.velocity.x());
      out[9] = double(b.velocity.y());
      out[10] = double(b.velocity.z());
      out[11] = double(b.angularVelocity.x());
      out[12] = double(b.angularVelocity.y());
      out[13] = double(b.angularVelocity.z());
      out += 14;
    }
    return state_.time;
  }

  py::dict facts() const {
    const RunFacts f = engine_->runFacts();
    py::dict d;
    d["engine"] = configured_.engine->name;
    d["method"] = configured_.method.name;
    d["engine_version"] = f.engineVersion;
    d["integrator_steps_per_scene_step"] = f.integratorStepsPerSceneStep;
    d["contact_margin"] = f.contactMargin;
    d["parameters"] = configured_.method.textValues();
    d["settings"] = engine_->effectiveSettings();
    const std::optional<std::string> hash = engine_->stateHash();
    if (hash) d["state_hash"] = *hash;
    return d;
  }

 private:
  Configured configured_;
  std::unique_ptr<SteppingEngine> engine_;
  State state_;
};

SceneHandle loadSceneFile(const std::string& path, bool strict) {
  // A C path ends at the first NUL: "x.json\0junk" would load x.json.
  if (path.find('\0') != std::string::npos)
    throw pbd::SceneError({path.substr(0, path.find('\0')) + "\\0...", "",
                           "a file name cannot contain a NUL character"});
  pbd::LoadOptions options;
  options.strict = strict;
  pbd::LoadedScene loaded = pbd::loadScene(path, options);
  SceneHandle handle;
  handle.file = path;
  for (const pbd::SceneDiagnostic& w : loaded.warnings)
    handle.warnings.push_back(w.text());
  handle.scene = std::make_shared<const pbd::Scene>(std::move(loaded.scene));
  return handle;
}

py::dict sceneSummary(const SceneHandle& h) {
  const pbd::Scene& s = *h.scene;
  py::dict d;
  d["file"] = h.file;
  std::vector<int> ids;
  std::vector<std::string> names;
  for (const pbd::RigidBodyDesc& b : s.rigidBodies)
    ids.push_back(b.id);
  d["body_ids"] = ids;
  d["time_step"] = double(s.simulation.timeStepSize);
  d["gravity"] = std::vector<double>{double(s.simulation.gravitation.x()),
                                     double(s.simulation.gravitation.y()),
                                     double(s.simulation.gravitation.z())};
  d["warnings"] = h.warnings;
  return d;
}

py::tuple simulate(const Registry& registry, const SceneHandle& scene, const std::string& method,
                   const py::dict& parameters, double duration, double sampleInterval,
                   double wallTimeLimit) {
  Configured c = configure(registry, scene, method, parameters);
  RunLength length = caseRunLength(c.scene, registry.engines);
  if (duration > 0) length.duration = duration;
  if (sampleInterval >= 0) length.sampleInterval = sampleInterval;
  const std::unique_ptr<Engine> engine = c.engine->make(registry.engines.options());
  std::vector<State> samples;
  RunOutcome outcome;
  {
    py::gil_scoped_release release;
    RunCallbacks callbacks;
    callbacks.onSample = [&samples](const State& s) { samples.push_back(s); };
    outcome = runSimulation(*engine, c.scene, c.method, length, callbacks, wallTimeLimit);
  }
  py::dict run;
  run["engine"] = c.engine->name;
  run["method"] = c.method.name;
  run["status"] = std::string(runStatusName(outcome.status));
  run["reason"] = outcome.reason;
  run["steps"] = outcome.steps;
  run["wall_time_s"] = outcome.wallTime;
  run["engine_version"] = outcome.facts.engineVersion;
  run["integrator_steps_per_scene_step"] = outcome.facts.integratorStepsPerSceneStep;
  run["contact_margin"] = outcome.facts.contactMargin;
  run["parameters"] = c.method.textValues();
  run["settings"] = outcome.settings;
  if (!outcome.stateHash.empty()) run["state_hash"] = outcome.stateHash;
  return py::make_tuple(run, statesDict(samples, c.scene.rigidBodies.size()));
}

/// The metrics of a trajectory: the runner's measurement path. `reference`: None (the case's
/// analytic reference when it has one, else none), False (none), or reference arrays.
py::dict measure(const Registry& registry, const SceneHandle& handle, const Array& times,
                 const Array& positions, const Array& quaternions, const Array& velocities,
                 const Array& angularVelocities, const py::object& particlePositions,
                 const py::object& particleVelocities, const py::object& segmentRotations,
                 const py::object& segmentAngularVelocities, const py::object& reference,
                 double contactMargin, double integrationStep) {
  const pbd::Scene& scene = *handle.scene;
  const CaseSpec spec = parseCaseSpec(scene, registry.engines);
  const std::vector<State> samples =
      samplesOf(scene, times, positions, quaternions, velocities, angularVelocities,
                particlePositions, particleVelocities, segmentRotations, segmentAngularVelocities);
  ReferenceChoice choice = ReferenceChoice::CaseDefault;
  ReferenceTrajectory given;
  if (py::isinstance<py::bool_>(reference) && !reference.cast<bool>()) {
    choice = ReferenceChoice::None;
  } else if (!reference.is_none()) {
    choice = ReferenceChoice::Given;
    const py::dict r = reference.cast<py::dict>();
    given.description = r.contains("description") ? r["description"].cast<std::string>()
                                                  : std::string("reference trajectory");
    given.samples = samplesOf(
        scene, r["times"].cast<Array>(), r["positions"].cast<Array>(),
        r["quaternions"].cast<Array>(), r["velocities"].cast<Array>(),
        r["angular_velocities"].cast<Array>(),
        r.contains("particle_positions") ? py::object(r["particle_positions"])
                                         : py::object(py::none()),
        r.contains("particle_velocities") ? py::object(r["particle_velocities"])
                                          : py::object(py::none()),
        r.contains("segment_rotations") ? py::object(r["segment_rotations"])
                                        : py::object(py::none()),
        r.contains("segment_angular_velocities") ? py::object(r["segment_angular_velocities"])
                                                 : py::object(py::none()));
  }
  MeasuredTrajectory measured;
  MetricSeries series;
  {
    py::gil_scoped_release release;
    // The same checks and measurement path as the `measure` fuzz target (tests/fuzz).
    measured = measureTrajectory(scene, spec, samples, choice, &given, contactMargin,
                                 integrationStep, &series);
  }
  py::dict d = metricsDict(measured.metrics);
  d["reference"] = measured.referenceDescription;
  // The series behind the metrics, by name: "energy_drift", "joint_error_linear/<type>",
  // "joint_error_angular/<type>", "motor_tracking/<quantity>", "penetration",
  // "trajectory_error", "rotation_error" (absent when the metric is).
  auto vector = [](const std::vector<double>& values) {
    Array a = newArray({py::ssize_t(values.size())});
    for (std::size_t k = 0; k < values.size(); ++k)
      a.mutable_at(py::ssize_t(k)) = values[k];
    return a;
  };
  py::dict s;
  s["times"] = vector(series.times);
  if (!series.energyDrift.empty()) s["energy_drift"] = vector(series.energyDrift);
  for (const auto& [type, values] : series.jointErrorLinear)
    s[py::str("joint_error_linear/" + type)] = vector(values);
  for (const auto& [type, values] : series.jointErrorAngular)
    s[py::str("joint_error_angular/" + type)] = vector(values);
  for (const auto& [quantity, values] : series.motorTracking)
    s[py::str("motor_tracking/" + quantity)] = vector(values);
  if (!series.penetration.empty()) s["penetration"] = vector(series.penetration);
  if (!series.trajectoryError.empty()) s["trajectory_error"] = vector(series.trajectoryError);
  if (!series.rotationError.empty()) s["rotation_error"] = vector(series.rotationError);
  d["series"] = s;
  return d;
}

py::dict energy(const Registry& registry, const SceneHandle& handle, const Array& times,
                const Array& positions, const Array& quaternions, const Array& velocities,
                const Array& angularVelocities, const py::object& particlePositions,
                const py::object& particleVelocities, const py::object& segmentRotations,
                const py::object& segmentAngularVelocities) {
  const pbd::Scene& scene = *handle.scene;
  const std::vector<State> samples =
      samplesOf(scene, times, positions, quaternions, velocities, angularVelocities,
                particlePositions, particleVelocities, segmentRotations, segmentAngularVelocities);
  const py::ssize_t t = py::ssize_t(samples.size());
  Array translational = newArray({t}), rotational = newArray({t}), gravitational = newArray({t}),
        spring = newArray({t}), elastic = newArray({t}), total = newArray({t});
  const ElasticEnergy elasticModel(scene);
  for (py::ssize_t k = 0; k < t; ++k) {
    const EnergyTerms e = energyOf(scene, samples[std::size_t(k)], elasticModel);
    translational.mutable_at(k) = e.translational;
    rotational.mutable_at(k) = e.rotational;
    gravitational.mutable_at(k) = e.gravitational;
    spring.mutable_at(k) = e.spring;
    elastic.mutable_at(k) = e.elastic;
    total.mutable_at(k) = e.total();
  }
  py::dict d;
  d["translational"] = translational;
  d["rotational"] = rotational;
  d["gravitational"] = gravitational;
  d["spring"] = spring;
  d["elastic"] = elastic;
  d["total"] = total;
  d["scale"] = energyScale(scene, parseCaseSpec(scene, registry.engines));
  return d;
}

void translateSceneError(const pbd::SceneError& e) {
  const py::object cls = py::module_::import("pbdval.errors").attr("SceneError");
  const pbd::SceneDiagnostic& d = e.diagnostic();
  const py::object error = cls(d.file, d.jsonPath, d.message);
  PyErr_SetObject(cls.ptr(), error.ptr());
}

void raiseAs(const char* name, const std::exception& e) {
  const py::object cls = py::module_::import("pbdval.errors").attr(name);
  PyErr_SetObject(cls.ptr(), cls(std::string(e.what())).ptr());
}

/// An external engine's run took SIGINT, SIGTERM or SIGHUP (validation/run/interrupts.h) and
/// stopped the engine. SIGINT is Python's KeyboardInterrupt; the others are raised again, now
/// that the engine is gone, so that they do what they would have done (end the interpreter,
/// or run the handler Python code installed).
void raiseInterrupt(const pbdval::SignalInterrupt& e) {
  if (e.signal() != SIGINT) {
    ::raise(e.signal());
    if (PyErr_CheckSignals() != 0) return;  // a Python handler raised
  }
  PyErr_SetString(PyExc_KeyboardInterrupt, e.what());
}

}  // namespace
}  // namespace pbdval::python

PYBIND11_MODULE(_core, m) {
  using namespace pbdval::python;
  namespace pv = pbdval;
  m.doc() = "pbdval's C++ core: scene loader, engines, stepping and metrics (docs/python.md)";
  m.attr("version") = PBDVAL_VERSION;
  m.attr("default_wall_time_limit") = pv::kDefaultWallTimeLimit;
  m.attr("max_steps_per_run") = pv::kMaxStepsPerRun;

  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const pbd::SceneError& e) {
      translateSceneError(e);
    } catch (const Stepper::UnsupportedScene& e) {
      raiseAs("UnsupportedError", e);
    } catch (const pv::EngineDivergence& e) {
      raiseAs("DivergenceError", e);
    } catch (const pv::EngineError& e) {
      raiseAs("EngineError", e);
    } catch (const ResultsFileError& e) {
      raiseAs("ResultsError", e);
    } catch (const pv::SignalInterrupt& e) {
      raiseInterrupt(e);
    } catch (const std::invalid_argument& e) {
      // Bad arguments (parameters, run lengths, array shapes): pbdval.ArgumentError, a
      // ValueError.
      raiseAs("ArgumentError", e);
    }
  });

  py::class_<SceneHandle>(m, "_Scene");
  py::class_<Registry>(m, "_Registry").def(py::init<>());
  py::class_<Stepper>(m, "_Stepper")
      .def(py::init<const Registry&, const SceneHandle&, const std::string&, const py::dict&>())
      .def("step", &Stepper::step, py::arg("count"))
      .def("time", &Stepper::time)
      .def("body_count", &Stepper::bodyCount)
      .def("read_into", &Stepper::readInto, py::arg("packed").noconvert())
      .def("facts", &Stepper::facts);

  bindMujocoModel(m);
  m.def("_load_scene", &loadSceneFile, py::arg("path"), py::arg("strict"));
  m.def("_scene_summary", &sceneSummary);
  // The command line's "did you mean" (pbd/io/suggestion.h), for the Python API's messages.
  m.def("_did_you_mean", &pbd::didYouMean, py::arg("name"), py::arg("candidates"));
  m.def("_run_length", [](const Registry& r, const SceneHandle& h) {
    const pv::RunLength length = pv::caseRunLength(*h.scene, r.engines);
    return py::make_tuple(length.duration, length.sampleInterval);
  });
  m.def("_resolved_scene", [](const Registry& r, const SceneHandle& h, const std::string& method,
                              const py::dict& parameters, double duration, double interval) {
    Configured c = configure(r, h, method, parameters);
    pv::RunLength length = pv::caseRunLength(c.scene, r.engines);
    if (duration > 0) length.duration = duration;
    if (interval >= 0) length.sampleInterval = interval;
    return jsonToPython(
        pv::resolvedSceneJson(c.scene, c.method.name, pv::methodParametersJson(c.method), length));
  });
  m.def("_engines", [](const Registry& r) {
    py::list engines;
    for (const pv::EngineEntry& e : r.engines.entries()) {
      py::dict d;
      d["name"] = e.name;
      d["default_method"] = e.defaultMethod;
      d["run_by_default"] = e.runByDefault;
      d["honoured_settings"] = e.honouredSettings;
      py::list methods;
      for (const pv::MethodInfo& info : e.methods)
        methods.append(methodDict(info, e));
      d["methods"] = methods;
      py::list features;
      for (const pv::FeatureSupport& f : e.features.entries) {
        py::dict entry;
        entry["feature"] = f.key;
        entry["support"] = pv::supportName(f.support);
        entry["text"] = f.text;
        entry["methods"] = f.methods;
        features.append(entry);
      }
      d["features"] = features;
      engines.append(d);
    }
    return engines;
  });
  m.def("_scene_features", []() {
    py::list features;
    for (const pv::FeatureInfo& f : pv::sceneFeatures()) {
      py::dict d;
      d["key"] = f.key;
      d["description"] = f.description;
      d["from_scene"] = f.fromScene;
      features.append(d);
    }
    return features;
  });
  // What decides a run `unsupported` before it starts, without running it: the features the
  // scene uses, those the engine's table declares unsupported for the method (the generic
  // function), and what the engine's unsupported() returns (the table's verdict, plus the uses
  // only the engine can see, such as MuJoCo's loop closures).
  m.def("_feature_support", [](const Registry& r, const SceneHandle& h, const std::string& method) {
    const pv::MethodInfo& info = r.engines.method(method);
    const pv::EngineEntry& entry = r.engines.engine(info.engine);
    const pv::Method resolved = pv::resolveMethod(info);
    const std::vector<pv::FeatureUse> uses = pv::sceneFeatureUses(*h.scene);
    py::dict d;
    py::list used;
    for (const pv::FeatureUse& u : uses) {
      py::dict item;
      item["feature"] = u.key;
      item["json_path"] = u.jsonPath;
      const pv::FeatureSupport* decided = entry.features.resolve(u.key, info.name);
      item["support"] = decided ? pv::supportName(decided->support) : "undeclared";
      used.append(item);
    }
    d["uses"] = used;
    py::list unsupported;
    for (const pv::UnsupportedUse& u : pv::unsupportedUses(entry.features, uses, info.name)) {
      py::dict item;
      item["feature"] = u.key;
      item["json_path"] = u.jsonPath;
      item["message"] = u.message;
      unsupported.append(item);
    }
    d["table_unsupported"] = unsupported;
    d["engine_unsupported"] = r.engines.make(info.engine)->unsupported(*h.scene, resolved);
    d["declares_features"] = !entry.features.entries.empty();
    return d;
  });
  m.def("_simulate", &simulate);
  m.def("_measure", &measure);
  m.def("_energy", &energy);
  // Every metric's unit (validation/measure/metrics.h, metric::declared()): the report's headers.
  m.def("_metric_units", [] {
    py::dict units;
    for (const pv::metric::Declared& d : pv::metric::declared())
      units[py::str(d.name)] = d.unit;
    return units;
  });
  // The cases' own checks (Validation.checks) on a results.json, judged without a baseline by
  // the gate's own function (validation/verdict/gate.h evaluateCaseChecks): the report's bounds.
  m.def("_case_checks", [](const std::string& path) {
    if (path.find('\0') != std::string::npos)
      throw ResultsFileError("a file name cannot contain a NUL character");
    pv::ResultsFile results;
    try {
      results = pv::readResults(path);
    } catch (const std::exception& e) {
      throw ResultsFileError(e.what());
    }
    auto optional = [](const std::optional<double>& v) -> py::object {
      return v ? py::object(py::float_(*v)) : py::object(py::none());
    };
    py::list checks;
    for (const pv::GateOutcome& o : pv::evaluateCaseChecks(results.cases, results)) {
      py::dict d;
      d["case"] = o.suite;
      d["name"] = o.name;
      d["run"] = o.run;
      d["metric"] = o.metric;
      d["present"] = o.finding.present;
      d["holds"] = o.finding.holds;
      d["message"] = o.message;
      d["now"] = optional(o.value);
      d["allowed"] = optional(o.allowed);
      checks.append(d);
    }
    return checks;
  });
  m.def("_read_trajectory", [](const std::string& path) {
    if (path.find('\0') != std::string::npos)
      throw ResultsFileError("a file name cannot contain a NUL character");
    pv::Trajectory t;
    try {
      t = pv::readTrajectory(path);  // .npy or CSV
    } catch (const std::exception& e) {
      throw ResultsFileError(e.what());
    }
    const std::size_t n = t.samples.empty() ? 0 : t.samples.front().bodies.size();
    return statesDict(t.samples, n);
  });
}
