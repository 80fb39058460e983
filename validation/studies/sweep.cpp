#include "validation/studies/sweep.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>

#include "pbd/io/number_text.h"
#include "pbd/io/scene_loader.h"
#include "pbd/io/suggestion.h"
#include "validation/io/atomic_file.h"
#include "validation/io/json_text.h"
#include "validation/io/results.h"
#include "validation/io/trajectory.h"
#include "validation/measure/metrics.h"
#include "validation/run/case_library.h"
#include "validation/run/overrides.h"
#include "validation/run/run_scheduler.h"

namespace pbdval {
namespace {

/// Step-like parameters improve as they shrink; the others as they grow. An error-controlled
/// integrator's target accuracy (Drake's continuous plant) is refined by shrinking it.
bool isStepLike(const std::string& parameter) {
  return parameter == "timeStepSize" || parameter == "tolerance" || parameter == "targetAccuracy";
}

std::vector<std::string> defaultMethods(const CaseSpec& spec, const EngineRegistry& registry) {
  if (!spec.methods.empty()) return spec.methods;
  std::vector<std::string> methods;
  for (const std::string& engine : registry.defaultEngineNames())
    methods.push_back(registry.defaultMethod(engine));
  return methods;
}

/// The numeric values of each parameter of a grid point; nullopt when one that varies is not a
/// number. A parameter given one value (a setting held for the whole sweep, e.g.
/// stepControl=fixed) does not vary, and any text will do: it counts as 1.
std::optional<std::vector<double>> numericValues(
    const std::vector<std::pair<std::string, std::string>>& values,
    const std::vector<std::pair<std::string, std::vector<std::string>>>& parameters) {
  std::vector<double> row;
  for (const auto& [name, value] : values) {
    const std::optional<double> v = pbd::parseReal(value);
    bool held = false;
    for (const auto& [declared, list] : parameters)
      held = held || (declared == name && list.size() == 1);
    if (!v && !held) return std::nullopt;
    row.push_back(v ? *v : 1.0);
  }
  return row;
}

/// The smallest sample interval ≥ `atLeast` that is a whole number of every step (within 1e-9
/// relative), among the first 10⁴ multiples of the largest step; 0 when there is none. Runs at
/// all the steps are then sampled at the same times, and no reference is interpolated.
double commonSampleInterval(const std::vector<double>& steps, double atLeast) {
  const double largest = *std::max_element(steps.begin(), steps.end());
  const double first = std::max(1.0, std::ceil(atLeast / largest * (1 - 1e-12)));
  for (double k = first; k < first + 1e4; ++k) {
    const double interval = k * largest;
    bool whole = true;
    for (double h : steps) {
      const double ratio = interval / h;
      whole = whole && std::abs(ratio - std::round(ratio)) <= 1e-9 * ratio;
    }
    if (whole) return interval;
  }
  return 0;
}

}  // namespace

std::vector<std::vector<std::pair<std::string, std::string>>> sweepPoints(
    const std::vector<std::pair<std::string, std::vector<std::string>>>& parameters,
    const std::vector<std::string>& together) {
  if (together.size() == 1)
    throw OptionError("--together " + together[0] +
                      ": expected two or more parameters varied together, got one");
  std::vector<std::size_t> path;  // indices into `parameters`, the coordinate first
  for (std::size_t i = 0; i < together.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j)
      if (together[j] == together[i])
        throw OptionError("--together: " + together[i] + " is named twice");
    std::size_t index = parameters.size();
    for (std::size_t k = 0; k < parameters.size(); ++k)
      if (parameters[k].first == together[i]) index = k;
    if (index == parameters.size())
      throw OptionError("--together: " + together[i] +
                        " is not a swept parameter (give its values with --param " + together[i] +
                        "=v1,v2,...)");
    const std::size_t count = parameters[index].second.size();
    if (count < 2)
      throw OptionError("--together: --param " + together[i] + " has one value; a path needs " +
                        "two or more");
    if (!path.empty() && count != parameters[path[0]].second.size())
      throw OptionError("--together: --param " + together[i] + " has " + std::to_string(count) +
                        " values and --param " + together[0] + " " +
                        std::to_string(parameters[path[0]].second.size()) +
                        ": the i-th values are taken together, so the lists must be as long");
    path.push_back(index);
  }
  // The axes of the grid: each parameter alone, except the path, one axis at its coordinate.
  std::vector<std::vector<std::size_t>> axes;
  for (std::size_t k = 0; k < parameters.size(); ++k) {
    if (std::find(path.begin(), path.end(), k) == path.end())
      axes.push_back({k});
    else if (k == path[0])
      axes.push_back(path);
  }
  std::vector<std::vector<std::pair<std::string, std::string>>> points{
      std::vector<std::pair<std::string, std::string>>(parameters.size())};
  for (const std::vector<std::size_t>& axis : axes) {
    std::vector<std::vector<std::pair<std::string, std::string>>> next;
    for (const auto& partial : points)
      for (std::size_t v = 0; v < parameters[axis[0]].second.size(); ++v) {
        auto extended = partial;
        for (std::size_t k : axis)
          extended[k] = {parameters[k].first, parameters[k].second[v]};
        next.push_back(extended);
      }
    points = next;
  }
  return points;
}

namespace {

/// Least squares of log e on log x over the points `rows` (the columns `varying`): fills the
/// slopes, orders and R² of `fit`.
void leastSquaresFit(const std::vector<std::string>& parameterNames,
                     const std::vector<std::vector<double>>& parameterValues,
                     const std::vector<double>& errors, const std::vector<std::size_t>& rows,
                     const std::vector<std::size_t>& varying, SweepFit& fit) {
  Eigen::MatrixXd design(rows.size(), varying.size() + 1);
  Eigen::VectorXd logError(rows.size());
  for (std::size_t r = 0; r < rows.size(); ++r) {
    design(Eigen::Index(r), 0) = 1;
    for (std::size_t c = 0; c < varying.size(); ++c)
      design(Eigen::Index(r), Eigen::Index(c + 1)) = std::log(parameterValues[rows[r]][varying[c]]);
    logError(Eigen::Index(r)) = std::log(errors[rows[r]]);
  }
  const Eigen::VectorXd coefficients = design.colPivHouseholderQr().solve(logError);
  const Eigen::VectorXd residual = logError - design * coefficients;
  const double mean = logError.mean();
  const double total = (logError.array() - mean).square().sum();
  fit.rSquared = total > 0 ? 1 - residual.squaredNorm() / total : 1;
  fit.points = static_cast<int>(rows.size());
  fit.parameters.clear();
  fit.slopes.clear();
  fit.orders.clear();
  for (std::size_t c = 0; c < varying.size(); ++c) {
    const std::string& name = parameterNames[varying[c]];
    const double slope = coefficients(Eigen::Index(c + 1));
    fit.parameters.push_back(name);
    fit.slopes.push_back(slope);
    fit.orders.push_back(isStepLike(name) ? slope : -slope);
  }
}

std::string shortNumber(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", value);
  return text;
}

/// One parameter varying: local orders coarse → fine, and the points from the first floor on.
/// Returns the rows to fit.
std::vector<std::size_t> asymptoticRange(const std::string& parameter,
                                         const std::vector<std::vector<double>>& parameterValues,
                                         const std::vector<double>& errors,
                                         std::vector<std::size_t> rows, std::size_t column,
                                         SweepFit& fit) {
  const bool stepLike = isStepLike(parameter);
  // Coarse to fine: decreasing steps, increasing counts.
  std::sort(rows.begin(), rows.end(), [&](std::size_t a, std::size_t b) {
    return stepLike ? parameterValues[a][column] > parameterValues[b][column]
                    : parameterValues[a][column] < parameterValues[b][column];
  });
  for (std::size_t k = 0; k + 1 < rows.size(); ++k) {
    const double x0 = parameterValues[rows[k]][column], x1 = parameterValues[rows[k + 1]][column];
    const double slope = std::log(errors[rows[k + 1]] / errors[rows[k]]) / std::log(x1 / x0);
    fit.localOrders.push_back({x0, x1, stepLike ? slope : -slope});
  }
  // The floor: only once the error has started to fall (a first positive local order) can a
  // later refinement be said to have stopped it.
  if (fit.localOrders.empty() || !(fit.localOrders.front().order > 0)) return rows;
  const double first = fit.localOrders.front().order;
  for (std::size_t k = 1; k < fit.localOrders.size(); ++k) {
    const LocalOrder& local = fit.localOrders[k];
    if (local.order > 0.5 * first) continue;
    for (std::size_t r = k + 1; r < rows.size(); ++r) {
      const double value = parameterValues[rows[r]][column];
      fit.excluded.push_back(
          {value, r == k + 1 ? "on a floor: from " + shortNumber(local.from) + " to " +
                                   shortNumber(local.to) + " the error fell by a factor " +
                                   shortNumber(errors[rows[k]] / errors[rows[k + 1]]) +
                                   " only (local order " + shortNumber(local.order) +
                                   ", under half the first, " + shortNumber(first) + ")"
                             : "finer than the floor at " + shortNumber(local.to)});
    }
    fit.flags.push_back("floor");
    rows.resize(k + 1);
    break;
  }
  return rows;
}

}  // namespace

const char* fitModelName(FitModel model) {
  return model == FitModel::Power ? "power" : "power_plus_floor";
}

namespace {

/// e = F + C·x^s over every usable point (one parameter varying, `column`): see the header
/// comment. Fills the order, R², floor and flags of `fit`.
void powerPlusFloorFit(const std::string& parameter,
                       const std::vector<std::vector<double>>& parameterValues,
                       const std::vector<double>& errors, std::vector<std::size_t> rows,
                       std::size_t column, SweepFit& fit) {
  const bool stepLike = isStepLike(parameter);
  std::sort(rows.begin(), rows.end(), [&](std::size_t a, std::size_t b) {
    return stepLike ? parameterValues[a][column] > parameterValues[b][column]
                    : parameterValues[a][column] < parameterValues[b][column];
  });
  fit.model = FitModel::PowerPlusFloor;
  fit.parameters = {parameter};
  fit.points = static_cast<int>(rows.size());
  const std::size_t differences = rows.size() - 1;
  auto x = [&](std::size_t k) { return parameterValues[rows[k]][column]; };
  auto e = [&](std::size_t k) { return errors[rows[k]]; };
  if (differences < 3) {
    fit.flags.push_back("too_few_points");
    fit.warning = "the power law plus a floor needs four or more points (three differences), " +
                  std::to_string(rows.size()) + " given";
    fit.slopes = {std::nan("")};
    fit.orders = {std::nan("")};
    return;
  }
  const double ratio = x(1) / x(0);
  bool constantRatio = true, oneSign = true;
  for (std::size_t k = 0; k < differences; ++k) {
    constantRatio = constantRatio && std::abs(x(k + 1) / x(k) - ratio) <= 1e-9 * ratio;
    const double d = e(k) - e(k + 1);
    oneSign = oneSign && d != 0 && (d > 0) == (e(0) - e(1) > 0);
  }
  if (!constantRatio || !oneSign) {
    fit.flags.push_back(constantRatio ? "differences_change_sign" : "ratio_not_constant");
    fit.warning = constantRatio
                      ? "the successive differences of the error change sign or vanish: no "
                        "power law approaches a floor"
                      : "the parameter is not refined by a constant ratio: the differences do "
                        "not remove the floor";
    fit.slopes = {std::nan("")};
    fit.orders = {std::nan("")};
    return;
  }
  const auto count = static_cast<Eigen::Index>(differences);
  Eigen::MatrixXd design(count, 2);
  Eigen::VectorXd logDifference(count);
  for (std::size_t k = 0; k < differences; ++k) {
    design(Eigen::Index(k), 0) = 1;
    design(Eigen::Index(k), 1) = std::log(x(k));
    logDifference(Eigen::Index(k)) = std::log(std::abs(e(k) - e(k + 1)));
  }
  const Eigen::VectorXd coefficients = design.colPivHouseholderQr().solve(logDifference);
  const Eigen::VectorXd residual = logDifference - design * coefficients;
  const double total = (logDifference.array() - logDifference.mean()).square().sum();
  fit.rSquared = total > 0 ? 1 - residual.squaredNorm() / total : 1;
  const double slope = coefficients(1);
  const double sign = e(0) - e(1) > 0 ? 1 : -1;
  const double scale = sign * std::exp(coefficients(0)) / (1 - std::pow(ratio, slope));
  double floorSum = 0;
  for (std::size_t k = 0; k < rows.size(); ++k)
    floorSum += e(k) - scale * std::pow(x(k), slope);
  fit.floor = floorSum / double(rows.size());
  fit.slopes = {slope};
  fit.orders = {stepLike ? slope : -slope};
  std::vector<std::string> warnings;
  if (fit.rSquared < kMinimumRSquared) {
    fit.flags.push_back("r_squared_below_0.99");
    warnings.push_back("R^2 " + shortNumber(fit.rSquared) +
                       " < 0.99: the differences do not follow one power law");
  }
  if (!(fit.floor > 0)) {
    fit.flags.push_back("no_floor");
    warnings.push_back("the fitted floor " + shortNumber(fit.floor) +
                       " is not positive: the errors show no floor, fit a power law");
  }
  if (!(fit.orders[0] > 0)) {
    fit.flags.push_back("no_order");
    warnings.push_back("the differences do not fall as " + parameter + " is refined");
  }
  if (warnings.empty())
    warnings.push_back("floor " + shortNumber(fit.floor) + " (" +
                       shortNumber(100 * fit.floor / e(rows.size() - 1)) +
                       "% of the finest error): the error the parameter cannot remove");
  for (const std::string& w : warnings)
    fit.warning += (fit.warning.empty() ? "" : "; ") + w;
}

}  // namespace

SweepFit fitConvergence(const std::string& method, const std::vector<std::string>& parameterNames,
                        const std::vector<std::vector<double>>& parameterValues,
                        const std::vector<double>& errors, FitModel model) {
  SweepFit fit;
  fit.method = method;
  // Keep the parameters that vary and the points with a positive error and positive values.
  std::vector<std::size_t> usable;
  for (std::size_t k = 0; k < errors.size(); ++k) {
    bool ok = std::isfinite(errors[k]) && errors[k] > 0;
    for (double v : parameterValues[k])
      ok = ok && v > 0;
    if (ok) usable.push_back(k);
  }
  std::vector<std::size_t> varying;
  for (std::size_t i = 0; i < parameterNames.size(); ++i) {
    bool differs = false;
    for (std::size_t k : usable)
      differs = differs || parameterValues[k][i] != parameterValues[usable[0]][i];
    if (differs) varying.push_back(i);
  }
  fit.points = static_cast<int>(usable.size());
  if (varying.empty() || usable.size() < varying.size() + 2) {
    fit.note =
        "not enough points with a positive error to fit (" + std::to_string(usable.size()) + ")";
    return fit;
  }
  if (model == FitModel::PowerPlusFloor) {
    if (varying.size() != 1) {
      fit.note = "the power law plus a floor is fitted with one parameter varying, not " +
                 std::to_string(varying.size());
      return fit;
    }
    SweepFit scratch;  // the local orders, as for a power law
    asymptoticRange(parameterNames[varying[0]], parameterValues, errors, usable, varying[0],
                    scratch);
    fit.localOrders = scratch.localOrders;
    powerPlusFloorFit(parameterNames[varying[0]], parameterValues, errors, usable, varying[0], fit);
    return fit;
  }
  std::vector<std::size_t> rows = usable;
  if (varying.size() == 1)
    rows = asymptoticRange(parameterNames[varying[0]], parameterValues, errors, usable, varying[0],
                           fit);
  leastSquaresFit(parameterNames, parameterValues, errors, rows, varying, fit);
  if (rows.size() < varying.size() + 2) fit.flags.push_back("too_few_points");
  if (fit.rSquared < kMinimumRSquared) fit.flags.push_back("r_squared_below_0.99");

  // An order ≤ 0 means the error does not fall as the parameter is refined: the points sit on a
  // floor (round-off, solver tolerance, a modelling error the parameter cannot remove), not in
  // the asymptotic range where an order means anything. Reported, not hidden.
  double largest = 0;
  for (std::size_t k : usable)
    largest = std::max(largest, errors[k]);
  std::vector<std::string> warnings;
  for (std::size_t c = 0; c < fit.orders.size(); ++c)
    if (fit.orders[c] <= 0) {
      char text[200];
      std::snprintf(text, sizeof text,
                    "the error does not fall as %s is refined (largest %.3g): a floor "
                    "(round-off, solver tolerance), not an asymptotic order",
                    fit.parameters[c].c_str(), largest);
      warnings.push_back(text);
    }
  if (!fit.excluded.empty())
    warnings.push_back(std::to_string(fit.excluded.size()) +
                       " finest point(s) on a floor left out of the fit");
  if (std::find(fit.flags.begin(), fit.flags.end(), "r_squared_below_0.99") != fit.flags.end())
    warnings.push_back(
        "R^2 " + shortNumber(fit.rSquared) +
        " < 0.99: the points do not follow one power law, the order is not reliable");
  if (std::find(fit.flags.begin(), fit.flags.end(), "too_few_points") != fit.flags.end())
    warnings.push_back("only " + std::to_string(fit.points) +
                       " points in the fit: add refinements to confirm the order");
  for (const std::string& w : warnings)
    fit.warning += (fit.warning.empty() ? "" : "; ") + w;
  return fit;
}

void markParetoFront(std::vector<SweepPoint>& points) {
  for (SweepPoint& p : points) {
    p.pareto = std::isfinite(p.metric);
    if (!p.pareto) continue;
    for (const SweepPoint& q : points) {
      if (&q == &p || !std::isfinite(q.metric)) continue;
      const bool dominates = q.metric <= p.metric && q.wallTime <= p.wallTime &&
                             (q.metric < p.metric || q.wallTime < p.wallTime);
      if (dominates) {
        p.pareto = false;
        break;
      }
    }
  }
}

namespace {

/// The names a sweep is given, checked before anything runs (an unknown one would otherwise
/// skip every method and write a sweep without a fit): the metric is a metric
/// (metric::names()); no method or parameter is given twice, nor a value of one parameter;
/// every parameter has an effect on at least one method, and on every method named explicitly
/// (`explicitMethods`: --methods; default methods on which it has none are skipped with a note).
void checkSweepNames(const SweepPlan& plan, bool explicitMethods, bool declared,
                     const EngineRegistry& registry) {
  const std::vector<std::string> metrics = metric::names();
  if (std::find(metrics.begin(), metrics.end(), plan.metric) == metrics.end())
    throw OptionError(std::string(declared ? "Validation.sweeps[0].metric" : "--metric") + ": '" +
                      plan.metric + "' is not a metric (metrics: " + pbd::nameList(metrics) + ")" +
                      pbd::didYouMean(plan.metric, metrics));
  for (std::size_t i = 0; i < plan.methods.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (plan.methods[i] == plan.methods[j])
        throw OptionError("method " + plan.methods[i] + " is listed twice");
  for (std::size_t i = 0; i < plan.parameters.size(); ++i) {
    const auto& [name, values] = plan.parameters[i];
    for (std::size_t j = 0; j < i; ++j)
      if (plan.parameters[j].first == name)
        throw OptionError("--param " + name + " is given twice");
    for (std::size_t a = 0; a < values.size(); ++a)
      for (std::size_t b = 0; b < a; ++b)
        if (values[a] == values[b])
          throw OptionError("--param " + name + ": the value " + values[a] +
                            " is listed twice (the same runs again)");
    std::vector<std::string> applies, ignores;
    for (const std::string& method : plan.methods) {
      const MethodInfo& info = registry.method(method);
      (assignmentApplies(name, info, registry.engine(info.engine)) ? applies : ignores)
          .push_back(method);
    }
    const std::vector<std::string> settings = pbd::simulationSettingKeys();
    if (applies.empty() && std::find(settings.begin(), settings.end(), name) == settings.end())
      throw OptionError("--param " + name + ": " +
                        unknownSettingMessage(name, plan.methods, registry));
    if (applies.empty())
      throw OptionError("--param " + name + ": has no effect in any method of the sweep (" +
                        pbd::nameList(ignores) +
                        "; 'pbdval methods' lists what each engine honours)");
    if (explicitMethods && !ignores.empty())
      throw OptionError("--param " + name + ": has no effect in " + pbd::nameList(ignores) +
                        " (it applies to " + pbd::nameList(applies) +
                        "): leave them out of --methods");
  }
}

}  // namespace

SweepPlan planSweep(const SweepOptions& options, const EngineRegistry& registry) {
  const pbd::Scene scene = pbd::loadScene(options.caseFile).scene;
  const CaseSpec spec = parseCaseSpec(scene, registry);
  SweepPlan plan;
  plan.caseName = caseNameOf(options.caseFile);

  plan.parameters = options.parameters;
  plan.methods = options.methods;
  plan.metric = options.metric;
  plan.fitModel = options.fitModel;
  plan.together = options.together;
  if (plan.parameters.empty()) {
    if (spec.sweeps.empty())
      throw OptionError(options.caseFile +
                        ": no --param given and the case declares no Validation.sweeps");
    const SweepSpec& declared = spec.sweeps.front();
    for (const auto& [name, values] : declared.parameters)
      plan.parameters.emplace_back(name, values);
    if (plan.methods.empty()) plan.methods = declared.methods;
    if (plan.metric.empty()) plan.metric = declared.metric;
  }
  if (plan.methods.empty()) plan.methods = defaultMethods(spec, registry);
  const bool hasReference = options.referenceMode == "fine" ||
                            isEngineReference(options.referenceMode) ||
                            spec.reference.kind != ReferenceSpec::Kind::None;
  if (plan.metric.empty()) plan.metric = hasReference ? "trajectory_error_max" : "energy_drift_max";

  // Swept step sizes share one sample interval, a whole number of every step (so that every run
  // is sampled at the same times), and one fine reference step.
  const double caseStep = double(scene.simulation.timeStepSize);
  double largestStep = caseStep, smallestStep = caseStep;
  std::vector<double> steps{caseStep};
  for (const auto& [name, values] : plan.parameters) {
    if (name != "timeStepSize") continue;
    largestStep = 0;
    smallestStep = 1e300;
    steps.clear();
    for (const std::string& v : values) {
      const std::optional<double> h = pbd::parseReal(v);
      if (!h || *h <= 0)
        throw OptionError("timeStepSize: expected positive numbers, got '" + v + "'");
      largestStep = std::max(largestStep, *h);
      smallestStep = std::min(smallestStep, *h);
      steps.push_back(*h);
    }
  }
  const double wanted = std::max(largestStep, spec.sampleInterval.value_or(0));
  const double common = commonSampleInterval(steps, wanted);
  const double sampleInterval = common > 0 ? common : wanted;
  if (common == 0)
    plan.notes.push_back(
        "no sample interval is a whole number of every swept step: runs are "
        "compared with the reference by cubic Hermite interpolation");

  checkSweepNames(plan, !options.methods.empty(), options.metric.empty(), registry);
  const auto points = sweepPoints(plan.parameters, plan.together);  // checks --together
  for (const std::string& method : plan.methods) {
    const MethodInfo& info = registry.method(method);
    const EngineEntry& engine = registry.engine(info.engine);
    std::string notApplicable;
    for (const auto& [name, values] : plan.parameters)
      if (!assignmentApplies(name, info, engine))
        notApplicable += (notApplicable.empty() ? "" : ", ") + name;
    if (!notApplicable.empty()) {
      plan.notes.push_back(method + ": skipped, " + notApplicable + " has no effect on it");
      continue;
    }
    for (const auto& [name, values] : plan.parameters)
      for (const std::string& value : values)
        checkAssignmentValue(name, value, info, "--param " + name + "=" + value);
    for (const auto& values : points) {
      RunRequest r;
      r.caseName = plan.caseName;
      r.caseFile = options.caseFile;
      r.engine = info.engine;
      r.method = method;
      for (const auto& [name, value] : values)
        r.assignments.push_back(name + "=" + value);
      r.referenceMode = options.referenceMode;
      r.fineDivisor = options.fineDivisor;
      if (options.referenceMode == "fine") r.referenceStepSize = smallestStep / options.fineDivisor;
      r.sampleInterval = sampleInterval;
      plan.requests.push_back(r);
      SweepPoint p;
      p.method = method;
      p.values = values;
      plan.points.push_back(p);
    }
  }
  return plan;
}

namespace {
double wallTimeOf(const RunRecord& record) {
  const auto wall = record.metrics.values.find("wall_time_s");
  return wall == record.metrics.values.end() ? 0 : wall->second;
}

/// The median (the mean of the two middle values of an even count); 0 for none.
double median(std::vector<double> values) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}
}  // namespace

SweepResult collectSweep(const SweepPlan& plan, const std::vector<RunRecord>& records,
                         const std::vector<std::vector<RunRecord>>& repeats) {
  for (const std::vector<RunRecord>& pass : repeats)
    if (pass.size() != records.size())
      throw std::invalid_argument("collectSweep: a repeated pass holds " +
                                  std::to_string(pass.size()) + " runs, the first " +
                                  std::to_string(records.size()));
  SweepResult result;
  result.caseName = plan.caseName;
  result.metric = plan.metric;
  result.notes = plan.notes;
  result.points = plan.points;
  result.together = plan.together;
  for (std::size_t k = 0; k < result.points.size(); ++k) {
    SweepPoint& p = result.points[k];
    p.record = records.at(k);
    const auto value = p.record.metrics.values.find(plan.metric);
    const bool measured = isMeasured(p.record.status) && value != p.record.metrics.values.end();
    p.metric = measured ? value->second : std::nan("");
    p.wallTimes = {wallTimeOf(p.record)};
    for (const std::vector<RunRecord>& pass : repeats)
      p.wallTimes.push_back(wallTimeOf(pass.at(k)));
    p.wallTime = median(p.wallTimes);
    if (isMeasured(p.record.status) && !measured)
      result.notes.push_back(
          runLabel(p.record.request) + ": no " + plan.metric + " (" +
          (p.record.metrics.notes.empty() ? "not computed" : p.record.metrics.notes.front()) + ")");
  }
  markParetoFront(result.points);

  // The parameters that follow the path's coordinate (--together) are functions of it: the fit
  // is in the coordinate alone (their columns are left out).
  std::vector<std::string> names;
  std::vector<bool> fitted;
  for (const auto& [name, values] : plan.parameters) {
    const bool follows =
        !plan.together.empty() && name != plan.together[0] &&
        std::find(plan.together.begin(), plan.together.end(), name) != plan.together.end();
    fitted.push_back(!follows);
    if (!follows) names.push_back(name);
  }
  for (const std::string& method : plan.methods) {
    std::vector<std::vector<double>> values;
    std::vector<double> errors;
    bool numeric = true;
    for (const SweepPoint& p : result.points) {
      if (p.method != method) continue;
      const auto row = numericValues(p.values, plan.parameters);
      numeric = numeric && row.has_value();
      std::vector<double> columns;
      for (std::size_t i = 0; row && i < row->size(); ++i)
        if (i >= fitted.size() || fitted[i]) columns.push_back((*row)[i]);
      values.push_back(row ? columns : std::vector<double>(names.size(), 0.0));
      errors.push_back(p.metric);
    }
    if (values.empty()) continue;
    if (!numeric) {
      SweepFit fit;
      fit.method = method;
      fit.note = "parameter values are not all numeric: no fit";
      result.fits.push_back(fit);
      continue;
    }
    SweepFit fit = fitConvergence(method, names, values, errors, plan.fitModel);
    // The order in the work: the steps the integrator took, where every run records them.
    std::vector<std::vector<double>> steps;
    std::vector<double> stepErrors;
    for (const SweepPoint& p : result.points) {
      if (p.method != method || !std::isfinite(p.metric)) continue;
      const auto taken = p.record.settings.find(kStepsTakenSetting);
      const std::optional<double> n =
          taken == p.record.settings.end() ? std::nullopt : pbd::parseReal(taken->second);
      if (!n || !(*n > 0)) {
        steps.clear();
        break;
      }
      steps.push_back({*n});
      stepErrors.push_back(p.metric);
    }
    if (steps.size() >= 3) {
      const SweepFit work = fitConvergence(method, {kStepsTakenSetting}, steps, stepErrors);
      if (work.orders.size() == 1) {
        fit.workOrder = work.orders[0];
        fit.workRSquared = work.rSquared;
        fit.workFlags = work.flags;
      }
    }
    result.fits.push_back(fit);
  }
  return result;
}

SweepResult runSweep(
    const SweepOptions& options, const EngineRegistry& registry,
    const std::function<void(const RunRecord&, std::size_t, std::size_t)>& onFinished) {
  const SweepPlan plan = planSweep(options, registry);
  RunScheduler scheduler(registry, options.jobs, options.timeout, options.scratchFolder);
  const std::vector<RunRecord> records = scheduler.runAll(plan.requests, onFinished);
  std::vector<std::vector<RunRecord>> repeats;
  for (int pass = 1; pass < options.repetitions; ++pass)
    repeats.push_back(scheduler.runAll(plan.requests, onFinished));
  return collectSweep(plan, records, repeats);
}

void printSweepTable(std::ostream& out, const SweepResult& result) {
  char line[256];
  out << "sweep of " << result.caseName << ": " << result.metric << " and wall time per method\n";
  if (!result.together.empty()) {
    out << "along one path: ";
    for (std::size_t i = 0; i < result.together.size(); ++i)
      out << (i ? ", " : "") << result.together[i];
    out << " varied together (the i-th values at the i-th point); orders in " << result.together[0]
        << "\n";
  }
  for (const SweepFit& fit : result.fits) {
    out << "\n" << fit.method << "\n";
    for (const SweepPoint& p : result.points) {
      if (p.method != fit.method) continue;
      std::string values;
      for (const auto& [name, value] : p.values)
        values += (values.empty() ? "" : " ") + name + "=" + value;
      if (isMeasured(p.record.status))
        std::snprintf(line, sizeof line, "  %-36s %-12.4e %9.4f s%s\n", values.c_str(), p.metric,
                      p.wallTime, p.pareto ? "  pareto" : "");
      else
        std::snprintf(line, sizeof line, "  %-36s %s: %.80s\n", values.c_str(),
                      runStatusName(p.record.status), p.record.reason.c_str());
      out << line;
    }
    if (!fit.note.empty()) {
      out << "  fit: " << fit.note << "\n";
      continue;
    }
    for (std::size_t i = 0; i < fit.parameters.size(); ++i) {
      std::snprintf(
          line, sizeof line, "  fitted order in %s: %.3f (slope %.3f, R^2 %.4f, %d points)\n",
          fit.parameters[i].c_str(), fit.orders[i], fit.slopes[i], fit.rSquared, fit.points);
      out << line;
      if (fit.model == FitModel::PowerPlusFloor) {
        std::snprintf(line, sizeof line,
                      "  model e = F + C*x^s (differences' fit), floor F = %.4e\n", fit.floor);
        out << line;
      }
    }
    if (std::isfinite(fit.workOrder)) {
      std::snprintf(line, sizeof line, "  order in the steps taken (%s): %.3f (R^2 %.4f)%s\n",
                    kStepsTakenSetting, fit.workOrder, fit.workRSquared,
                    fit.workFlags.empty() ? "" : ", flagged");
      out << line;
    }
    for (const LocalOrder& local : fit.localOrders) {
      std::snprintf(line, sizeof line, "  local order %g -> %g: %.3f\n", local.from, local.to,
                    local.order);
      out << line;
    }
    for (const ExcludedPoint& e : fit.excluded) {
      std::snprintf(line, sizeof line, "  left out %g: %.160s\n", e.value, e.reason.c_str());
      out << line;
    }
    if (!fit.warning.empty()) out << "  warning: " << fit.warning << "\n";
  }
  for (const std::string& note : result.notes)
    out << "note: " << note << "\n";
}

void writeSweepJson(const std::string& path, const SweepResult& result,
                    const RunMetadata& metadata) {
  using Json = nlohmann::json;
  Json points = Json::array();
  for (const SweepPoint& p : result.points) {
    Json values = Json::object();
    for (const auto& [name, value] : p.values)
      values[name] = value;
    points.push_back({{"method", p.method},
                      {"parameters", values},
                      {"status", runStatusName(p.record.status)},
                      {"reason", p.record.reason},
                      {"metric", std::isfinite(p.metric) ? Json(p.metric) : Json(nullptr)},
                      {"wall_time_s", p.wallTime},
                      {"wall_times_s", p.wallTimes},
                      {"pareto", p.pareto},
                      {"run", Json::parse(toJsonText(p.record))}});
  }
  Json fits = Json::array();
  for (const SweepFit& f : result.fits) {
    Json orders = Json::object();
    for (std::size_t i = 0; i < f.parameters.size(); ++i) {
      orders[f.parameters[i]] = {{"order", f.orders[i]}, {"slope", f.slopes[i]}};
      if (f.parameters.size() == 1) {
        Json local = Json::array();
        for (const LocalOrder& l : f.localOrders)
          local.push_back({{"from", l.from}, {"to", l.to}, {"order", l.order}});
        orders[f.parameters[i]]["local"] = local;
      }
    }
    Json excluded = Json::array();
    for (const ExcludedPoint& e : f.excluded)
      excluded.push_back({{"value", e.value}, {"reason", e.reason}});
    fits.push_back({{"method", f.method},
                    {"orders", orders},
                    {"r_squared", f.rSquared},
                    {"points", f.points},
                    {"note", f.note},
                    {"warning", f.warning},
                    {"excluded", excluded},
                    {"flags", f.flags},
                    {"model", fitModelName(f.model)},
                    {"floor", std::isfinite(f.floor) ? Json(f.floor) : Json(nullptr)}});
    if (std::isfinite(f.workOrder))
      fits.back()["work"] = {{"parameter", kStepsTakenSetting},
                             {"order", f.workOrder},
                             {"r_squared", f.workRSquared},
                             {"flags", f.workFlags}};
  }
  const Json document = {{"schema", "pbdval-sweep"},
                         {"schemaVersion", 1},
                         {"metadata", Json::parse(metadataJsonText(metadata))},
                         {"case", result.caseName},
                         {"metric", result.metric},
                         {"points", points},
                         {"fits", fits},
                         {"notes", result.notes},
                         {"together", result.together}};
  writeFileAtomically(path, jsonText(document) + "\n");
}

}  // namespace pbdval
