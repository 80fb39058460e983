#include "validation/run/simulation.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "validation/measure/sanity.h"
#include "validation/run/interrupts.h"

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
    message << "a duration of " << length.duration << " s at a step of " << stepSize << " s is "
            << steps << " steps, more than the " << kMaxStepsPerRun
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
  for (std::size_t i = 0; i < state.particles.size(); ++i) {
    const ParticleState& p = state.particles[i];
    if (!p.position.allFinite() || !p.velocity.allFinite()) {
      std::ostringstream reason;
      reason << "non-finite state of particle " << i << " at t = " << state.time << " s";
      return reason.str();
    }
    if (p.position.norm() > kDivergenceLimit || p.velocity.norm() > kDivergenceLimit) {
      std::ostringstream reason;
      reason << "particle " << i << " blew up at t = " << state.time
             << " s (|x| = " << p.position.norm() << " m, |v| = " << p.velocity.norm() << " m/s)";
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

/// The runner's side of a run: every state the engine reports is checked for divergence and
/// against the boundary checks, and handed to the callbacks.
///
/// States of every step (EveryStep): a boundary violation ends the run as an error at once (a
/// velocity mismatch across internal substeps: suspect, and the run goes on); when the samples
/// are several steps apart they are checked again, for velocities that do not describe the
/// sampled motion (an oscillation at the step frequency the samples alias): suspect.
/// Samples only (SamplesOnly, an engine in another process): the samples are checked once the
/// run is complete, a velocity mismatch over `stride` steps making it suspect.
class RunChecks final : public RunObserver {
 public:
  RunChecks(const pbd::Scene& scene, const StepPlan& plan, const RunCallbacks& callbacks,
            RunOutcome& outcome)
      : scene_(scene), plan_(plan), callbacks_(callbacks), outcome_(outcome) {}

  void begin(const RunFacts& facts, const std::map<std::string, std::string>& settings,
             StateCadence cadence) override {
    outcome_.facts = facts;
    outcome_.settings = settings;
    cadence_ = cadence;
    boundary_.emplace(scene_, outcome_.facts);
    sampled_.emplace(scene_, outcome_.facts);
    stepsPerStep_ = std::max(1, outcome_.facts.integratorStepsPerSceneStep);
  }

  bool state(const State& state, long step) override {
    if (!boundary_) throw EngineError("the engine reported a state before its facts");
    outcome_.simulatedTime = state.time;
    if (cadence_ == StateCadence::SamplesOnly) return sampleOnly(state);
    if (step == 0) {
      if (callbacks_.onStep) callbacks_.onStep(state);
      if (callbacks_.onSample) callbacks_.onSample(state);
      if (boundaryFailed(state)) return false;
      if (plan_.stride > 1) sampled_->add(state);
      return true;
    }
    const std::string diverged = divergenceReason(state);
    if (diverged.empty() && callbacks_.onStep) callbacks_.onStep(state);
    if (diverged.empty() && outcome_.status == RunStatus::Ok && boundaryFailed(state)) return false;
    if (!diverged.empty()) {
      outcome_.status = RunStatus::Diverged;
      outcome_.reason = diverged;
      if (callbacks_.onSample) callbacks_.onSample(state);
      return false;
    }
    if (step % plan_.stride == 0 || step == plan_.steps) {
      if (callbacks_.onSample) callbacks_.onSample(state);
      if (plan_.stride > 1) sampled_->add(state);
    }
    if (callbacks_.onProgress &&
        std::chrono::duration<double>(Clock::now() - lastProgress_).count() > 0.2) {
      lastProgress_ = Clock::now();
      callbacks_.onProgress(double(step) / double(plan_.steps), secondsSince(start_));
    }
    return true;
  }

  /// After the engine's run: the checks that need the whole run.
  void finish() {
    if (!boundary_ || outcome_.status != RunStatus::Ok) return;
    if (cadence_ == StateCadence::SamplesOnly) {
      if (boundary_->finish())
        applyBoundaryViolation(*boundary_->violation(), plan_.stride * stepsPerStep_, outcome_);
      return;
    }
    if (boundary_->finish())
      applyBoundaryViolation(*boundary_->violation(), stepsPerStep_, outcome_);
    if (outcome_.status == RunStatus::Ok && plan_.stride > 1 && sampled_->finish() &&
        sampled_->violation()->aboutVelocities)
      applyBoundaryViolation(*sampled_->violation(), plan_.stride * stepsPerStep_, outcome_);
  }

 private:
  bool boundaryFailed(const State& state) {
    if (!boundary_->add(state)) return false;
    applyBoundaryViolation(*boundary_->violation(), stepsPerStep_, outcome_);
    return outcome_.status == RunStatus::Error;
  }

  bool sampleOnly(const State& state) {
    const std::string diverged = divergenceReason(state);
    if (callbacks_.onStep) callbacks_.onStep(state);
    if (callbacks_.onSample) callbacks_.onSample(state);
    if (!diverged.empty()) {
      outcome_.status = RunStatus::Diverged;
      outcome_.reason = diverged;
      return false;
    }
    boundary_->add(state);
    return true;
  }

  const pbd::Scene& scene_;
  const StepPlan& plan_;
  const RunCallbacks& callbacks_;
  RunOutcome& outcome_;
  StateCadence cadence_ = StateCadence::EveryStep;
  std::optional<BoundaryChecker> boundary_;  ///< every state reported
  std::optional<BoundaryChecker> sampled_;   ///< the samples, when they are several steps apart
  long stepsPerStep_ = 1;
  Clock::time_point start_ = Clock::now();
  Clock::time_point lastProgress_ = start_;
};

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
    RunChecks checks(scene, plan, callbacks, outcome);
    const EngineRunResult result = engine.run(scene, method, length, plan, wallTimeLimit, checks);
    outcome.wallTime = result.busySeconds;
    outcome.steps = result.steps;
    // What the checks found (a divergence, a failed boundary check) stands; otherwise the
    // engine's own word (its status, a timeout).
    if (outcome.status == RunStatus::Ok && result.status != RunStatus::Ok) {
      outcome.status = result.status;
      outcome.reason = result.reason;
    }
    checks.finish();
    if (result.stateHash) outcome.stateHash = *result.stateHash;
  } catch (const SignalInterrupt&) {
    throw;  // not the engine's failure: the command stops (validation/run/interrupts.h)
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
