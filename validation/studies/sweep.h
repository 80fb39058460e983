// Convergence studies (`pbdval sweep`, docs/cli.md#sweep): one case run for every value of one
// or more parameters (a grid), for every method; per method the error metric and the cost
// against the parameters, the fitted convergence order, and the Pareto front of error against
// wall time.
//
// Fit: over the ok points of a method with a positive metric, least squares on
//   log e = c + Σ_i s_i log x_i          (x_i the parameters that vary; R² reported)
// The order is s_i for step-like parameters (timeStepSize: e ∝ h^p) and −s_i for count-like
// ones (subSteps, iterations: e ∝ n^−p). With one parameter varying, the local order between
// every two successive refinements is reported too, and only the asymptotic range is fitted:
// once the error stops falling (a local order below half the first one, or ≤ 0: round-off, a
// solver tolerance, a modelling error the parameter cannot remove), that point and the finer
// ones are left out and named. A fit with R² < 0.99 or fewer than three points is flagged.
//
// The power law plus a floor (`--fit floor`, FitModel::PowerPlusFloor), for a method known to
// converge to a nearby model instead of the scene's (penalty joints: the floor is set by their
// compliance, not by the step): e = F + C·x^s. With one parameter refined by a constant ratio,
// successive differences remove the floor, e_k − e_{k+1} = C·x_k^s·(1 − ρ^s) (ρ = x_{k+1}/x_k),
// so s is the least-squares slope of log|e_k − e_{k+1}| on log x_k (the observed order from
// successive refinements, Roache 1998, "Verification and Validation in Computational Science
// and Engineering", ch. 5), its R² the fit's, and F the mean of e_k − C·x_k^s. Needs four or
// more points (three differences) of one sign; flagged otherwise, and when F ≤ 0 (no floor).
//
// Parameters varied together (`--together A,B,...`, SweepOptions::together): the i-th value of
// each at the i-th point, one path instead of a grid (a penalty stiffness k raised as the step
// h falls, k·h² held: the convergence path of an explicit penalty scheme). The first named is
// the path's coordinate: the fit is in it alone, the others being functions of it.
#pragma once

#include <cmath>
#include <functional>
#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

#include "adapters/registry.h"
#include "validation/io/results.h"

namespace pbdval {

/// The default passes of a sweep (`pbdval sweep --repeat`).
inline constexpr int kSweepRepetitions = 3;

/// What a sweep fits to each method's errors (header comment).
enum class FitModel { Power, PowerPlusFloor };

/// "power" or "power_plus_floor" (sweep.json's fits[].model).
const char* fitModelName(FitModel model);

struct SweepOptions {
  std::string caseFile;
  std::vector<std::pair<std::string, std::vector<std::string>>> parameters;  ///< name → values
  std::vector<std::string> methods;  ///< empty: the case's, else every engine's default
  std::string metric;  ///< empty: trajectory_error_max with a reference, else energy_drift_max
  std::string referenceMode;  ///< "" the case's reference; "fine": same method at a tiny step;
                              ///< else METHOD[:KEY=VALUE,...], an engine reference
  int fineDivisor = 16;
  int jobs = 1;
  double timeout = 600;
  std::string scratchFolder = "out/.scratch";
  /// Passes over the sweep's runs: a point's wall time is the median of its passes (one wall
  /// time is one noisy sample: a Pareto front on single samples moves between sweeps).
  int repetitions = kSweepRepetitions;
  FitModel fitModel = FitModel::Power;  ///< `--fit`
  /// `--together`: parameters of `parameters` varied together (header comment), the first the
  /// coordinate of the fit; empty: every parameter spans the grid.
  std::vector<std::string> together;
};

struct SweepPoint {
  std::string method;
  std::vector<std::pair<std::string, std::string>> values;
  RunRecord record;
  double metric = 0;              ///< NaN when the run failed or lacks the metric
  double wallTime = 0;            ///< s, the median of wallTimes
  std::vector<double> wallTimes;  ///< s, of every pass over the run (the first: its record's)
  bool pareto = false;            ///< on the error/wall-time Pareto front (over all methods)
};

/// The order between two successive refinements of one parameter: log(e₁/e₂) / log(x₁/x₂)
/// (sign as the fitted order's).
struct LocalOrder {
  double from = 0, to = 0;  ///< the parameter's values, coarse → fine
  double order = 0;
};

/// A point left out of the fit, and why.
struct ExcludedPoint {
  double value = 0;  ///< the swept parameter's value
  std::string reason;
};

struct SweepFit {
  std::string method;
  std::vector<std::string> parameters;  ///< the parameters that vary
  std::vector<double> slopes;           ///< d log e / d log x_i
  std::vector<double> orders;           ///< see the header comment
  double rSquared = 0;
  int points = 0;       ///< points in the fit
  std::string note;     ///< why no fit, when there is none
  std::string warning;  ///< what a reader must know before trusting the order
  /// One parameter varying: the local order of every successive pair of refinements, the
  /// points left out as on a floor, and the flags ("floor", "r_squared_below_0.99",
  /// "too_few_points"; the names sweep.json and the report use).
  std::vector<LocalOrder> localOrders;
  std::vector<ExcludedPoint> excluded;
  std::vector<std::string> flags;
  FitModel model = FitModel::Power;
  double floor = std::nan("");  ///< F of the power law plus a floor (NaN for a power law)
  /// The order in the work, for an error-controlled integrator whose runs record the steps they
  /// took (settings "integrator.stepsTaken", Drake's continuous methods): e ∝ N^−p over the same
  /// points, N the steps, fitted as a count (NaN when the runs do not record it). With the
  /// duration fixed, N ∝ 1/h̄ and p is the integrator's order in its mean step.
  double workOrder = std::nan("");
  double workRSquared = std::nan("");
  std::vector<std::string> workFlags;
};

/// The setting in which an error-controlled integrator's run records its steps.
inline constexpr const char* kStepsTakenSetting = "integrator.stepsTaken";

/// A fit whose R² is below this is flagged: the points do not follow one power law.
inline constexpr double kMinimumRSquared = 0.99;

struct SweepResult {
  std::string caseName, metric;
  std::vector<SweepPoint> points;
  std::vector<SweepFit> fits;
  std::vector<std::string> notes;     ///< skipped combinations (parameter not applicable, ...)
  std::vector<std::string> together;  ///< the parameters varied together, the coordinate first
};

/// The runs of a sweep, before they run: the case's declared sweep filling what the options
/// leave open, the grid of parameter values per method, one request (and one point) per run.
struct SweepPlan {
  std::string caseName, metric;
  std::vector<std::pair<std::string, std::vector<std::string>>> parameters;
  std::vector<std::string> methods;
  std::vector<RunRequest> requests;
  std::vector<SweepPoint> points;  ///< one per request, in the same order, without records yet
  std::vector<std::string> notes;  ///< methods skipped (a parameter has no effect on them)
  FitModel fitModel = FitModel::Power;
  std::vector<std::string> together;  ///< SweepOptions::together, checked
};

/// The assignments of every point of a sweep, each in the order of `parameters`: the Cartesian
/// grid, except that the parameters of `together` take their i-th values together (one axis
/// of the grid). Throws OptionError (naming --together) when `together` names fewer than two
/// parameters, one that is not among `parameters` or one twice, or lists of unequal lengths.
std::vector<std::vector<std::pair<std::string, std::string>>> sweepPoints(
    const std::vector<std::pair<std::string, std::vector<std::string>>>& parameters,
    const std::vector<std::string>& together);

/// Plans the sweep. Throws std::invalid_argument for bad options (unknown method, no
/// parameters, non-positive step sizes, ...).
SweepPlan planSweep(const SweepOptions& options, const EngineRegistry& registry);

/// The plan's points with their records (`records[k]` of `plan.requests[k]`), the Pareto front
/// and one fit per method. `repeats` are further passes over the same requests (each as long as
/// `records`): each point's wall time is the median over `records` and `repeats`; its metric
/// and record are the first pass's.
SweepResult collectSweep(const SweepPlan& plan, const std::vector<RunRecord>& records,
                         const std::vector<std::vector<RunRecord>>& repeats = {});

/// planSweep, the runs (isolated, `options.jobs` at a time), collectSweep.
SweepResult runSweep(
    const SweepOptions& options, const EngineRegistry& registry,
    const std::function<void(const RunRecord&, std::size_t, std::size_t)>& onFinished = {});

/// Least-squares fit of log e on log x (exposed for tests).
SweepFit fitConvergence(const std::string& method, const std::vector<std::string>& parameterNames,
                        const std::vector<std::vector<double>>& parameterValues,
                        const std::vector<double>& errors, FitModel model = FitModel::Power);

/// Marks the points on the Pareto front of (wall time, metric), both minimised.
void markParetoFront(std::vector<SweepPoint>& points);

void printSweepTable(std::ostream& out, const SweepResult& result);
void writeSweepJson(const std::string& path, const SweepResult& result,
                    const RunMetadata& metadata);

}  // namespace pbdval
