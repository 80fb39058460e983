// The Engine interface: every simulator (the PBD library, Bullet, ODE, MuJoCo) loads the same
// Scene with a Method, advances one timeStepSize per step(), and reads back its state in the
// Scene's frames. Metrics are never taken from an engine: validation/ computes them from the
// states read back and the Scene.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "adapters/features.h"
#include "adapters/parameters.h"
#include "pbd/model/scene.h"

namespace pbdval {

using pbd::Quaternion;
using pbd::Real;
using pbd::Vector3;

/// A rigid body's state in the Scene's world frame.
struct BodyState {
  int id = 0;                                    ///< the body's scene id
  Vector3 position = Vector3::Zero();            ///< centre of mass
  Quaternion rotation = Quaternion::Identity();  ///< the body's scene frame → world
  Vector3 velocity = Vector3::Zero();            ///< of the centre of mass
  Vector3 angularVelocity = Vector3::Zero();
};

struct ParticleState {
  Vector3 position = Vector3::Zero();
  Vector3 velocity = Vector3::Zero();
};

/// A Cosserat-rod segment's orientation (pbd/constraints/cosserat_rod.h).
struct SegmentState {
  Quaternion rotation = Quaternion::Identity();  ///< director frame → world (d₃ along the segment)
  Vector3 angularVelocity = Vector3::Zero();     ///< world
};

/// One sample of a run: bodies in Scene::rigidBodies order, particles in Scene order, rod
/// segments in the order of World::bodies.segments (line models in scene order, each model's
/// segments from its first point). Engines without rods (or that read none back) leave
/// `segments` empty.
struct State {
  double time = 0;
  std::vector<BodyState> bodies;
  std::vector<ParticleState> particles;
  std::vector<SegmentState> segments;
};

/// A named solver configuration of one engine ("ode.quickstep") and its typed parameters.
struct MethodInfo {
  std::string name;
  std::string engine;
  std::string description;
  std::vector<ParameterSpec> parameters;

  /// The declaration of `parameter`, or nullptr.
  const ParameterSpec* find(const std::string& parameter) const;
};

/// A method with every parameter value resolved (defaults filled in, overrides applied) and
/// checked against its declaration. Engines read values through the typed accessors; each
/// throws std::invalid_argument naming the parameter when it is missing or of another kind.
struct Method {
  std::string name;
  std::map<std::string, ParameterValue> values;
  std::vector<ParameterSpec> declarations;  ///< of the method's parameters (for durations)

  double real(const std::string& parameter) const;
  std::int64_t integer(const std::string& parameter) const;
  bool flag(const std::string& parameter) const;
  const std::string& choice(const std::string& parameter) const;
  /// A Duration in seconds, "4h" resolved with the scene's `stepSize`.
  double seconds(const std::string& parameter, double stepSize) const;
  /// Every value as canonical text, for results and tables.
  std::map<std::string, std::string> textValues() const;

 private:
  const ParameterValue& value(const std::string& parameter, ParameterKind kind) const;
};

/// `info` resolved: defaults, then `overrides` (parameter → text), each parsed and checked
/// against its declaration. Throws std::invalid_argument for an unknown parameter (naming the
/// valid ones) or a value out of range (naming the range).
Method resolveMethod(const MethodInfo& info,
                     const std::map<std::string, std::string>& overrides = {});

/// What the runner needs to know about a loaded run, typed. effectiveSettings() is for the
/// parity record only; nothing is parsed out of it.
struct RunFacts {
  std::string engineVersion;            ///< "Bullet 3.24", "MuJoCo 2.2.2", ...
  int integratorStepsPerSceneStep = 1;  ///< PBD: subSteps; the reference engines: 1
  /// Overlap (m) the engine lets resting contacts keep by design (Bullet's linear slop); the
  /// penetration metric subtracts it. 0 when contacts are meant to close exactly.
  double contactMargin = 0;
  /// Relative tolerance of the first sample against the Scene's initial state (the boundary
  /// check of validation/measure/sanity.h): 1e-9 unless the engine states why its read-back
  /// differs.
  double initialStateTolerance = 1e-9;
  /// The engine's generalised coordinates cannot hold a velocity that violates a joint: it
  /// starts from the scene's velocities projected onto the joints' free motions (MuJoCo), so
  /// the first sample's velocities are not compared with the scene's (positions still are).
  bool initialVelocitiesProjected = false;
  /// The largest speed (m/s) the method reports for a body that holds still, with its reason:
  /// a velocity pass that changes velocities after the positions are set (the seed's PBD step)
  /// leaves a body resting in contact with a velocity its positions do not show. 0: a body at
  /// rest reports rest (validation/measure/sanity.h, check velocity_at_rest).
  double restVelocityAllowance = 0;
  std::string restVelocityReason;
  /// Bodies (indices into Scene::rigidBodies) whose reported velocities the method sets apart
  /// from their motion by design, with the reason: the PBD steps' motor joints (a position
  /// motor's target moves once per scene step, so a driven body's velocity is its last
  /// substep's; a velocity motor sets the velocity in the velocity pass). The velocity checks
  /// skip them; every other check applies.
  std::vector<int> velocityDrivenBodies;
  std::string velocityDrivenReason;
};

/// How long to run and how often to sample (both in seconds of simulated time).
struct RunLength {
  double duration = 5;
  double sampleInterval = 0;  ///< 0: every step
};

/// A run's status. `Suspect`: the run completed, but its states break a physics sanity bound
/// that the scene implies (energy created in a passive scene, momentum changed without an
/// external force, a speed the scene's energy cannot reach; validation/measure/sanity.h) or a check
/// at the engine's boundary (initial state, unit quaternions, velocities consistent with the
/// motion). Its metrics are kept; the gate fails it unless the baseline knows it.
enum class RunStatus { Ok, Suspect, Diverged, Timeout, Unsupported, Error };
/// Every status, in the order summaries list them (the one declaration the parsers use).
inline constexpr RunStatus kRunStatuses[] = {RunStatus::Ok,          RunStatus::Suspect,
                                             RunStatus::Unsupported, RunStatus::Diverged,
                                             RunStatus::Timeout,     RunStatus::Error};
const char* runStatusName(RunStatus status);
/// Whether a run of this status completed and was measured (its metrics are data): ok and
/// suspect. Summaries, sweeps and reports show the metrics of exactly these.
inline bool isMeasured(RunStatus status) {
  return status == RunStatus::Ok || status == RunStatus::Suspect;
}
/// The status named `name` ("ok", "suspect", ...), or nullopt.
std::optional<RunStatus> runStatusNamed(std::string_view name);
/// "\"ok\", \"suspect\", ..." for error messages.
std::string runStatusNameList();

/// The steps of one run and when it is sampled: `steps` scene steps, a sample at step 0, every
/// `stride`-th step and the last (validation/run/simulation.h planSteps derives it from a
/// RunLength).
struct StepPlan {
  long steps = 0;
  long stride = 1;
  std::vector<std::string> notes;  ///< e.g. "sample interval 0.0123 s rounded to 0.0125 s"
};

/// Which of its states an engine's run reports.
enum class StateCadence {
  EveryStep,   ///< every step's state (an engine stepped in this process)
  SamplesOnly  ///< the plan's samples only (an engine in another process)
};

/// Receives a run's states as the engine produces them: the runner's checks and outputs
/// (validation/run/simulation.h). An engine never judges its own states.
class RunObserver {
 public:
  virtual ~RunObserver() = default;
  /// The run's facts and settings, before its first state: after the model is built (stepped
  /// engines) or once the run has ended (engines in another process).
  virtual void begin(const RunFacts& facts, const std::map<std::string, std::string>& settings,
                     StateCadence cadence) = 0;
  /// The state after `step` scene steps (0: the initial state). Returns false to end the run
  /// (the observer found a divergence or a failed check, and keeps the reason).
  virtual bool state(const State& state, long step) = 0;
};

/// How a run ended as far as the engine can tell (the observer adds what it found).
struct EngineRunResult {
  RunStatus status = RunStatus::Ok;
  std::string reason;
  long steps = 0;                        ///< scene steps taken
  double busySeconds = 0;                ///< wall time of the engine's own work
  std::optional<std::string> stateHash;  ///< of the final state, for deterministic engines
};

/// An engine failure with a message (an engine's error callback, a rejected model, ...). The
/// runner turns it into the run status `error`.
class EngineError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The engine detected that its own integration became unstable (MuJoCo's bad qacc, ...). The
/// runner reports the run `diverged`, like a NaN or a blow-up it detects itself.
class EngineDivergence : public EngineError {
 public:
  using EngineError::EngineError;
};

/// Every engine: what it cannot represent, and a whole run. The runner calls run() for every
/// engine alike; how the states come about (stepping in this process, another process) is the
/// engine's business.
class Engine {
 public:
  virtual ~Engine() = default;
  virtual std::string_view name() const = 0;
  /// Features of the scene this engine cannot represent with this method, by name
  /// ("joint TargetVelocityMotorSliderJoints[0]: no native equivalent"). Empty when all is
  /// supported (or when, as for external engines, the engine itself says so during the run);
  /// the runner then reports the run `unsupported`.
  virtual std::vector<std::string> unsupported(const pbd::Scene& scene,
                                               const Method& method) const = 0;
  /// Runs `scene` with `method` for `plan`, handing every state to `observer` (facts first).
  /// `wallTimeLimit` (s, 0 = none) bounds the run: past it the result is `timeout`. Throws
  /// EngineError (EngineDivergence for an instability the engine detects itself).
  virtual EngineRunResult run(const pbd::Scene& scene, const Method& method,
                              const RunLength& length, const StepPlan& plan, double wallTimeLimit,
                              RunObserver& observer) = 0;
};

/// An engine stepped in this process (the built-in ones): run() loads the scene, reads the
/// initial state, then steps and reads `plan.steps` times, every state to the observer; also
/// steppable one step at a time (pbdval.Simulation, the adapter tests).
class SteppingEngine : public Engine {
 public:
  /// Builds the engine's model. Throws EngineError.
  virtual void load(const pbd::Scene& scene, const Method& method) = 0;
  /// Advances by one Scene timeStepSize. Throws EngineError.
  virtual void step() = 0;
  /// Poses and velocities in the Scene's frames (time included).
  virtual void read(State& state) const = 0;
  /// The facts the runner needs (integrator steps per step, contact margin, version); valid
  /// after a successful load().
  virtual RunFacts runFacts() const = 0;
  /// The settings actually used (solver, iterations, margins, contact softness, ...), recorded
  /// with every run for the parity record; never parsed.
  virtual std::map<std::string, std::string> effectiveSettings() const { return {}; }
  /// A hash of the complete final state, for engines that guarantee bitwise determinism
  /// (the PBD library); empty otherwise.
  virtual std::optional<std::string> stateHash() const { return std::nullopt; }

  EngineRunResult run(const pbd::Scene& scene, const Method& method, const RunLength& length,
                      const StepPlan& plan, double wallTimeLimit, RunObserver& observer) final;
};

/// A process an engine keeps for many runs (an external engine's server,
/// docs/external-engines.md#persistent-engines), started once by `pbdval run` for all its
/// workers and ended (its process group killed and reaped) when this is destroyed.
class EngineServer {
 public:
  virtual ~EngineServer() = default;
  /// False once the process has ended (or never started listening).
  virtual bool running() const = 0;
  /// Returns once the process listens, or has failed (running() is then false); at once when
  /// it listened before. Servers are started without waiting, so that a pool's servers start
  /// side by side (EngineEntry::startServer).
  virtual void awaitListening() {}
};

/// What an engine is given when it is created (chosen by the command, never read from the
/// environment by an engine).
struct EngineOptions {
  std::string gridCacheFolder;  ///< the PBD library's grid SDF cache; empty: none
  /// The folder where the command's engine servers listen (EngineEntry::startServer); empty:
  /// every run of an external engine starts its own process.
  std::string serverFolder;
};

/// One engine of a registry: its methods with their parameters, the Simulation settings of the
/// scene it honours, and how to create it.
struct EngineEntry {
  std::string name;           ///< "pbd", "bullet", "ode", "mujoco"
  std::string defaultMethod;  ///< used when a run names the engine only
  /// The methods `pbdval run` uses for this engine when neither --methods nor the case's
  /// Validation.methods name one of them; empty: defaultMethod alone.
  std::vector<std::string> runMethods;
  std::vector<MethodInfo> methods;
  /// Keys of the scene's Simulation block this engine uses (timeStepSize, gravitation, and for
  /// the PBD library its solver settings); `--set` of another key has no effect in it.
  std::vector<std::string> honouredSettings;
  /// How the engine maps every scene feature (adapters/features.h): declared once, used by its
  /// unsupported() and by the parity pages.
  FeatureTable features;
  std::function<std::unique_ptr<Engine>(const EngineOptions&)> make;
  /// For an engine that can serve many runs from one process (an external engine with a
  /// `serve` command): starts that process, to listen in `serverFolder` (EngineOptions), and
  /// returns at once; EngineServer::awaitListening() waits until it listens, or has failed
  /// (then running() is false and the runs say why). Empty for the others.
  std::function<std::unique_ptr<EngineServer>(const std::string& serverFolder)> startServer;
  /// Run when no engine is named (`pbdval run` without --engines); false for example engines,
  /// which run only by name.
  bool runByDefault = true;
};

}  // namespace pbdval
