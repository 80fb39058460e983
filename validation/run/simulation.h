// Drives one engine through a scene: steps, samples, and detects failures. Shared by
// `pbdval simulate` and the validation runner, so every engine is driven the same way.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "adapters/engine.h"

namespace pbdval {

/// The most steps one run may take: a run is refused before it starts rather than left to
/// run for days (10^8 steps of the cheapest engine take minutes; of a 100-link chain, hours).
inline constexpr double kMaxStepsPerRun = 1e8;

/// The wall-time limit of one run when none is given, in seconds: `pbdval run --timeout`,
/// `pbdval simulate --timeout` and pbdval.simulate's wall_time_limit default to it.
inline constexpr double kDefaultWallTimeLimit = 600;

/// The number of steps and the sampling stride (StepPlan, adapters/engine.h) for a scene with
/// step size h: steps = round(duration/h), stride = max(1, round(sampleInterval/h)). Throws
/// std::invalid_argument for a non-positive or non-finite duration or step, a negative
/// interval, or more than kMaxStepsPerRun steps (naming the count and how to reduce it).
StepPlan planSteps(const RunLength& length, double stepSize);

struct RunOutcome {
  RunStatus status = RunStatus::Ok;
  std::string reason;                           ///< empty when ok
  long steps = 0;                               ///< steps taken
  double simulatedTime = 0;                     ///< s
  double wallTime = 0;                          ///< s, load + stepping (reading samples excluded)
  std::map<std::string, std::string> settings;  ///< Engine::effectiveSettings()
  RunFacts facts;                               ///< Engine::runFacts()
  std::string stateHash;                        ///< of the final state, for deterministic engines
};

struct RunCallbacks {
  /// Every sample (t = 0 included); may throw to abort.
  std::function<void(const State&)> onSample;
  /// Every state the engine reports, t = 0 and after every step, before the sample test
  /// (engines in another process report their samples only); for outputs with their own rate
  /// (mesh export).
  std::function<void(const State&)> onStep;
  /// Called about every 0.2 s of wall time with the fraction done.
  std::function<void(double fraction, double elapsedSeconds)> onProgress;
};

/// Positions beyond this many metres, or speeds beyond this many m/s, count as a blow-up.
inline constexpr double kDivergenceLimit = 1e6;

/// Runs `scene` in `engine` with `method` (Engine::run, the same for every engine), checking
/// every state it reports: divergence, the boundary checks (validation/measure/sanity.h). Never
/// throws for engine failures: unsupported features, EngineError and other exceptions, NaN/inf or
/// blow-ups, and `wallTimeLimit` (seconds, 0 = none) become the outcome's status and reason. Only a
/// SignalInterrupt (validation/run/interrupts.h: an external engine's run or a callback took
/// SIGINT, SIGTERM or SIGHUP) passes through: the command is being stopped.
RunOutcome runSimulation(Engine& engine, const pbd::Scene& scene, const Method& method,
                         const RunLength& length, const RunCallbacks& callbacks,
                         double wallTimeLimit = 0);

/// Checks a state for NaN/inf and blow-ups; returns a reason, or empty when fine.
std::string divergenceReason(const State& state);

}  // namespace pbdval
