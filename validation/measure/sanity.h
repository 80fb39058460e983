// Checks every run's states must pass, whatever the case declares (docs/metrics.md §Sanity and
// §Boundary checks). Both are computed from the Scene and the states read back, the same code
// for every engine, built-in or external.
//
// Boundary checks (a violation makes the run `error`): what an engine hands back must be the
// quantities the protocol defines — the first sample is the Scene's initial state, quaternions
// are unit, and the reported velocities are the time derivatives of the reported positions and
// orientations. They catch an engine that writes quaternions x,y,z,w, positions in mm, ω in
// body axes or the body origin instead of the centre of mass.
//
// Sanity bounds (a violation makes an `ok` run `suspect`): energy created in a passive scene
// beyond the first-order truncation estimate of the scene's fastest time scale, linear and
// angular momentum changed in an isolated scene beyond the same estimate, a body faster than
// the energy the scene makes available allows.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "adapters/engine.h"
#include "validation/run/case_spec.h"

namespace pbdval {

/// A failed check: its name ("initial_state", "unit_quaternion", "velocity_consistency",
/// "angular_velocity_consistency", "velocity_at_rest", "energy_created", "speed",
/// "linear_momentum", "angular_momentum") and one sentence naming the body, the sample, the value
/// and the bound.
struct CheckViolation {
  std::string check;
  std::string message;
  /// One of the velocity checks (velocity_at_rest, velocity_consistency,
  /// angular_velocity_consistency), which states several integrator steps apart can break by
  /// aliasing an oscillation (runSimulation then makes the run suspect, not an error).
  bool aboutVelocities = false;
};

/// A pair of states in which a body's reported (angular) velocity misses the motion.
struct IntervalMismatch {
  std::size_t body = 0;
  bool angular = false;  ///< ω against the orientations (else v against the positions)
  std::string check;     ///< velocity_at_rest, velocity_consistency or angular_velocity_consistency
  std::string message;
};

/// The boundary checks over a run's samples as they come (runSimulation feeds it every sample,
/// so every engine and every caller — run, simulate, sweep, the Python API — is checked alike).
/// Keeps the last four samples: the velocity check of the interval [k, k+1] needs k−1 … k+2.
/// The scene must outlive the checker.
class BoundaryChecker {
 public:
  /// `initialTolerance`: the relative tolerance of the first sample against
  /// initialState(scene) (1e-9 unless the engine declares another).
  /// `restVelocityAllowance`: RunFacts::restVelocityAllowance of the run.
  /// `velocitiesProjected`: RunFacts::initialVelocitiesProjected (the first sample's
  /// velocities are not compared with the scene's).
  BoundaryChecker(const pbd::Scene& scene, double initialTolerance = 1e-9,
                  double restVelocityAllowance = 0, bool velocitiesProjected = false);
  /// The checker of a run with `facts` (its tolerance, rest allowance, projected initial
  /// velocities and velocity-driven bodies).
  BoundaryChecker(const pbd::Scene& scene, const RunFacts& facts);
  /// The next sample (in time order). Returns the first violation once there is one.
  const std::optional<CheckViolation>& add(const State& sample);
  /// Checks the intervals still open (the last one). Returns the first violation, if any.
  const std::optional<CheckViolation>& finish();
  const std::optional<CheckViolation>& violation() const { return violation_; }

 private:
  void checkInterval(std::size_t first);  ///< window_[first], window_[first + 1]
  const pbd::Scene& scene_;
  double initialTolerance_;
  bool velocitiesProjected_;
  std::vector<State> window_;  ///< the last ≤ 4 samples, oldest first
  std::size_t samplesSeen_ = 0;
  std::size_t nextInterval_ = 0;  ///< the sample index of the next interval's start
  std::optional<CheckViolation> violation_;
  /// Per body, linear then angular: consecutive intervals with a mismatch, and the first one's
  /// message.
  std::vector<int> streaks_;
  std::vector<IntervalMismatch> streakStart_;
  std::vector<char> failing_;  ///< per slot, a mismatch in the interval checked (reused)
  double restVelocityAllowance_;
  std::vector<double> sizes_;  ///< per body, √(tr I / 2m) (m), for the angular rest allowance
  std::vector<bool> skipVelocity_;  ///< per body: RunFacts::velocityDrivenBodies
};

/// Intervals in a row a velocity mismatch must hold to be a violation (docs/metrics.md): an
/// impact, a velocity pass at a contact event, a split-impulse push or a depenetration lasts a
/// few steps; a protocol mistake or a defect holds at every sample.
inline constexpr int kPersistentIntervals = 10;

/// The first violated boundary check of `samples` (in Scene body order, as read back), or
/// nullopt: BoundaryChecker over the whole list.
std::optional<CheckViolation> boundaryViolation(const pbd::Scene& scene,
                                                const std::vector<State>& samples,
                                                double initialTolerance = 1e-9,
                                                double restVelocityAllowance = 0);

/// What the sanity bounds of a scene are, derived from the Scene alone.
struct SanityBounds {
  bool passive = false;         ///< no motors and no energy the measured E leaves out
  std::string notPassive;       ///< why not (empty when passive)
  bool isolated = false;        ///< no static body or particle to push against, no fluid
  std::string notIsolated;      ///< why not (empty when isolated)
  double timeScale = 0;         ///< τ, s: the scene's fastest time scale (∞ when it has none)
  std::string timeScaleSource;  ///< which term set τ ("gravity over RigidBodies[2]'s size", ...)
  double stepSize = 0;          ///< h, s: Simulation.timeStepSize
  /// The relative bound over a run of `duration` seconds: h T / τ² + 1e-6 (docs/metrics.md).
  double relativeBound(double duration) const;
};

SanityBounds sanityBounds(const pbd::Scene& scene);

/// The first violated sanity bound of an `ok` run's samples, or nullopt.
std::optional<CheckViolation> sanityViolation(const pbd::Scene& scene, const CaseSpec& spec,
                                              const std::vector<State>& samples);

}  // namespace pbdval
