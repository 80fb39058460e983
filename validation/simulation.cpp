#include "validation/simulation.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "validation/interrupts.h"
#include "validation/sanity.h"

namespace pbdval {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace

StepPlan planSteps(const RunLength& length, double stepSize) {
  if (!(length.duration > 0) || !std::isfinite(length.duration))
    throw std::invalid_argument("duration must be a positive number of seconds");
  if (!(length.sampleInterval >= 0) || !std::isfinite(length.sampleInterval))
    throw std::invalid_argument("sample interval must be a non-negative number of seconds");
  if (!(stepSize > 0) || !std::isfinite(stepSize))
    throw std::invalid_argument("timeStepSize must be a positive number of seconds");
  const double steps = std::round(length.duration / stepSize);
  if (!(steps <= kMaxStepsPerRun)) {
    std::ostringstream message;
    message << "a duration of " << length.duration << " s at a step of " << stepSize
            << " s is " << steps << " steps, more than the " << kMaxStepsPerRun
            << " one run may take: shorten the duration or enlarge the step";
    throw std::invalid_argument(message.str());
  }
  StepPlan plan;
  plan.steps = std::max(1L, static_cast<long>(steps));
  if (std::abs(plan.steps * stepSize - length.duration) > 1e-9 * length.duration) {
    std::ostringstream note;
    note << "duration " << length.duration << " s is not a multiple of the step " << stepSize
         << " s: running " << plan.steps << " steps (" << plan.steps * stepSize << " s)";
    plan.notes.push_back(note.str());
  }
  if (length.sampleInterval > 0) {
    plan.stride = std::max(1L, std::lround(length.sampleInterval / stepSize));
    if (std::abs(plan.stride * stepSize - length.sampleInterval) > 1e-9 * length.sampleInterval) {
      std::ostringstream note;
      note << "sample interval " << length.sampleInterval << " s rounded to " << plan.stride
           << " steps (" << plan.stride * stepSize << " s)";
      plan.notes.push_back(note.str());
    }
  }
  return plan;
}

std::string divergenceReason(const State& state) {
  // Checked after every step: nothing is built unless something is wrong.
  for (const BodyState& b : state.bodies) {
    const bool finite = b.position.allFinite() && b.rotation.coeffs().allFinite() &&
                        b.velocity.allFinite() && b.angularVelocity.allFinite();
    if (finite && b.position.norm() <= kDivergenceLimit && b.velocity.norm() <= kDivergenceLimit)
      continue;
    std::ostringstream reason;
    if (!finite)
      reason << "non-finite state of body " << b.id << " at t = " << state.time << " s";
    else
      reason << "body " << b.id << " blew up at t = " << state.time
             << " s (|x| = " << b.position.norm() << " m, |v| = " << b.velocity.norm() << " m/s)";
    return reason.str();
  }
  for (std::size_t i = 0; i < state.particles.size(); ++i)
  {
    const ParticleState& p = state.particles[i];
    if (!p.position.allFinite() || !p.velocity.allFinite()) {
      std::ostringstream reason;
      reason << "non-finite state of particle " << i << " at t = " << state.time << " s";
      return reason.str();
    }
    if (p.position.norm() > kDivergenceLimit || p.velocity.norm() > kDivergenceLimit) {
      std::ostringstream reason;
      reason << "particle " << i << " blew up at t = " << state.time << " s (|x| = "
             << p.position.norm() << " m, |v| = " << p.velocity.norm() << " m/s)";
      return reason.str();
    }
  }
  for (std::size_t i = 0; i < state.segments.size(); ++i) {
    const SegmentState& q = state.segments[i];
    if (!q.rotation.coeffs().allFinite() || !q.angularVelocity.allFinite()) {
      std::ostringstream reason;
      reason << "non-finite state of rod segment " << i << " at t = " << state.time << " s";
      return reason.str();
    }
  }
  return {};
}

namespace {

/// The status a boundary violation gives a completed run (docs/metrics.md §Boundary checks):
/// a velocity mismatch between states `integratorSteps` integrator steps apart may be an
/// oscillation faster than that interval which the states alias, not a wrong velocity, so it
/// makes the run suspect; over one integrator step, and for every other check, it is an error.
void applyBoundaryViolation(const CheckViolation& violation, long integratorSteps,
                            RunOutcome& outcome) {
  if (violation.aboutVelocities && integratorSteps > 1) {
    outcome.status = RunStatus::Suspect;
    outcome.reason = violation.message + " (the states are " + std::to_string(integratorSteps) +
                     " integrator steps apart: an oscillation faster than that aliases like this)";
  } else {
    outcome.status = RunStatus::Error;
    outcome.reason = violation.message;
  }
}

/// A whole run from an engine in another process, checked like a stepped run: its samples go
/// through the same divergence test and callbacks.
void runWhole(Engine& engine, const pbd::Scene& scene, const Method& method,
              const RunLength& length, const StepPlan& plan, const RunCallbacks& callbacks,
              double wallTimeLimit, RunOutcome& outcome) {
  const Clock::time_point start = Clock::now();
  WholeRun whole = engine.runWhole(scene, method, length, wallTimeLimit);
  outcome.wallTime = secondsSince(start);
  outcome.settings = std::move(whole.settings);
  outcome.facts = std::move(whole.facts);
  outcome.status = whole.status;
  outcome.reason = std::move(whole.reason);
  outcome.steps = whole.status == RunStatus::Ok ? plan.steps : whole.steps;
  BoundaryChecker boundary(scene, outcome.facts);
  for (const State& state : whole.samples) {
    outcome.simulatedTime = state.time;
    const std::string diverged = divergenceReason(state);
    if (callbacks.onStep) callbacks.onStep(state);
    if (callbacks.onSample) callbacks.onSample(state);
    if (!diverged.empty()) {
      outcome.status = RunStatus::Diverged;
      outcome.reason = diverged;
      break;
    }
    boundary.add(state);
  }
  if (outcome.status == RunStatus::Ok && boundary.finish())
    applyBoundaryViolation(*boundary.violation(),
                           plan.stride * std::max(1, outcome.facts.integratorStepsPerSceneStep),
                           outcome);
}

}  // namespace

RunOutcome runSimulation(Engine& engine, const pbd::Scene& scene, const Method& method,
                         const RunLength& length, const RunCallbacks& callbacks,
                         double wallTimeLimit) {
  RunOutcome outcome;
  try {
    const std::vector<std::string> missing = engine.unsupported(scene, method);
    if (!missing.empty()) {
      outcome.status = RunStatus::Unsupported;
      for (const std::string& m : missing)
        outcome.reason += (outcome.reason.empty() ? "" : "; ") + m;
      return outcome;
    }
    const StepPlan plan = planSteps(length, double(scene.simulation.timeStepSize));
    if (engine.runsWhole()) {
      runWhole(engine, scene, method, length, plan, callbacks, wallTimeLimit, outcome);
      return outcome;
    }
    double busy = 0;  // wall time in load + step, without sampling
    const Clock::time_point start = Clock::now();
    Clock::time_point lastProgress = start;

    Clock::time_point t0 = Clock::now();
    engine.load(scene, method);
    busy += secondsSince(t0);
    outcome.settings = engine.effectiveSettings();
    outcome.facts = engine.runFacts();

    // What the engine reads back is checked against the protocol's definitions at every
    // step (validation/sanity.h): a violation ends the run as an error (a velocity mismatch
    // across internal substeps: suspect). The samples are checked too when they are several
    // steps apart: velocities that do not describe the sampled motion (an oscillation at the
    // step frequency that the samples alias) make a completed run suspect.
    BoundaryChecker boundary(scene, outcome.facts);
    BoundaryChecker sampled(scene, outcome.facts);
    const long stepsPerStep = std::max(1, outcome.facts.integratorStepsPerSceneStep);
    auto boundaryFailed = [&](const State& sample) {
      if (!boundary.add(sample)) return false;
      applyBoundaryViolation(*boundary.violation(), stepsPerStep, outcome);
      return outcome.status == RunStatus::Error;
    };
    State state;
    engine.read(state);
    if (callbacks.onStep) callbacks.onStep(state);
    if (callbacks.onSample) callbacks.onSample(state);
    if (boundaryFailed(state)) return outcome;
    if (plan.stride > 1) sampled.add(state);
    for (long n = 1; n <= plan.steps; ++n) {
      t0 = Clock::now();
      engine.step();
      busy += secondsSince(t0);
      outcome.steps = n;
      engine.read(state);
      outcome.simulatedTime = state.time;
      const std::string diverged = divergenceReason(state);
      if (diverged.empty() && callbacks.onStep) callbacks.onStep(state);
      if (diverged.empty() && outcome.status == RunStatus::Ok && boundaryFailed(state)) break;
      if (!diverged.empty()) {
        outcome.status = RunStatus::Diverged;
        outcome.reason = diverged;
        if (callbacks.onSample) callbacks.onSample(state);
        break;
      }
      if (n % plan.stride == 0 || n == plan.steps) {
        if (callbacks.onSample) callbacks.onSample(state);
        if (plan.stride > 1) sampled.add(state);
      }
      if (wallTimeLimit > 0 && secondsSince(start) > wallTimeLimit) {
        outcome.status = RunStatus::Timeout;
        std::ostringstream reason;
        reason << "stopped after " << wallTimeLimit << " s of wall time at t = " << state.time
               << " s (" << n << " of " << plan.steps << " steps)";
        outcome.reason = reason.str();
        break;
      }
      if (callbacks.onProgress &&
          std::chrono::duration<double>(Clock::now() - lastProgress).count() > 0.2) {
        lastProgress = Clock::now();
        callbacks.onProgress(double(n) / double(plan.steps), secondsSince(start));
      }
    }
    outcome.wallTime = busy;
    if (outcome.status == RunStatus::Ok && boundary.finish())
      applyBoundaryViolation(*boundary.violation(), stepsPerStep, outcome);
    if (outcome.status == RunStatus::Ok && plan.stride > 1 && sampled.finish() &&
        sampled.violation()->aboutVelocities)
      applyBoundaryViolation(*sampled.violation(), plan.stride * stepsPerStep, outcome);
    if (auto hash = engine.stateHash()) outcome.stateHash = *hash;
  } catch (const SignalInterrupt&) {
    throw;  // not the engine's failure: the command stops (validation/interrupts.h)
  } catch (const EngineDivergence& e) {
    outcome.status = RunStatus::Diverged;
    outcome.reason = e.what();
  } catch (const EngineError& e) {
    outcome.status = RunStatus::Error;
    outcome.reason = e.what();
  } catch (const std::exception& e) {
    outcome.status = RunStatus::Error;
    outcome.reason = e.what();
  }
  return outcome;
}

}  // namespace pbdval
