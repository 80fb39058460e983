// The `Validation` block of a case (docs/validation-block.md, schema 1): how long to run and
// sample, which engines and methods, the reference to compare against, what is conserved, the
// energy scale, the checks the gate applies, tolerance overrides, and sweeps.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "adapters/registry.h"
#include "pbd/model/scene.h"

namespace pbdval {

inline constexpr int kValidationSchemaVersion = 1;

/// What a run is compared against for the trajectory metrics.
struct ReferenceSpec {
  enum class Kind { None, Analytic, Fine, Engine };
  Kind kind = Kind::None;
  /// Analytic: the model name ("projectile", "pendulum", ...; validation/measure/references/) and
  /// its parameters as JSON object text (the model parses and validates them).
  std::string model;
  std::string parametersJson = "{}";
  /// Analytic: the scene ids of the bodies the model describes (empty: all dynamic bodies).
  std::vector<int> bodyIds;
  /// Fine: the same engine and method at timeStepSize / stepDivisor (Erez et al. 2015).
  int stepDivisor = 16;
  /// Engine: another engine/method (optionally at a finer step) as the reference.
  std::string engine, method;
};

/// A check the gate applies to this case's runs.
///  - bound:    metric ≤ max and/or ≥ min, for the runs matching `engines`/`methods`
///  - ordering: metric(run of method `better`) < metric(run of method `worse`)
struct CheckSpec {
  std::string jsonPath;  ///< "Validation.checks[2]", for messages
  std::string metric;
  std::optional<double> max, min;
  std::vector<std::string> engines;  ///< empty: every engine
  std::vector<std::string> methods;  ///< empty: every method
  std::string better, worse;         ///< ordering check when both are set
  std::string description;
};

/// A static displacement to measure (`Validation.staticDisplacement`): the displacement of a
/// group of particles along a direction, averaged over the particles and over the samples from
/// `from` on, against the value `expected` of a closed form or an independent solve. An
/// undamped oscillation about the static state averages to it: the mean of cos ωt over a window
/// T differs from 0 by at most 1/(ωT).
struct StaticDisplacementSpec {
  std::string jsonPath;               ///< "Validation.staticDisplacement"
  pbd::Vector3 regionMin, regionMax;  ///< the particles initially inside this box (inclusive)
  std::vector<int> particles;         ///< resolved from the region, in scene order, ≥ 1
  pbd::Vector3 direction;             ///< unit
  double from = 0;                    ///< s
  double expected = 0;                ///< m, non-zero
  std::string description;
};

/// A convergence study declared with the case (pbdval sweep uses it when run without --param).
struct SweepSpec {
  std::map<std::string, std::vector<std::string>> parameters;  ///< name → values
  std::vector<std::string> methods;
  std::string metric;
};

struct CaseSpec {
  int schema = kValidationSchemaVersion;
  std::string description;
  std::optional<double> duration;        ///< s
  std::optional<double> sampleInterval;  ///< s
  /// E_ref of the energy-drift metrics (J). Absent: the default of docs/metrics.md.
  std::optional<double> energyScale;
  bool energyConserved = false;
  bool linearMomentumConserved = false;
  bool angularMomentumConserved = false;
  std::vector<std::string> engines;  ///< engines to run (empty: all)
  std::vector<std::string> methods;  ///< methods to run (empty: each engine's default)
  ReferenceSpec reference;
  std::vector<CheckSpec> checks;
  std::map<std::string, double> tolerances;  ///< gate tolerance overrides, per metric
  std::vector<SweepSpec> sweeps;
  std::optional<StaticDisplacementSpec> staticDisplacement;
};

/// Parses scene.validationJson; throws std::invalid_argument "file: Validation.path: expected
/// ..., got ..." on bad input (unknown keys are errors here: the block is ours).
CaseSpec parseCaseSpec(const pbd::Scene& scene, const EngineRegistry& registry);

/// The run length a case asks for: Validation.duration, else the seed's pauseAt when > 0, else
/// 5 s.
double defaultDuration(const pbd::Scene& scene, const CaseSpec& spec);

}  // namespace pbdval
