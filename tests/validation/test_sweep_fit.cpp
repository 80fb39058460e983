// Convergence numbers a reader can trust (validation/studies/sweep.h): local orders, the asymptotic
// range, the flags, on manufactured error sequences of known order; and the whole path (runs,
// fine reference, resampling, fit) on a case where the method's order is known from theory.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "engines/selftest_engine.h"
#include "pbdval/build_info.h"
#include "validation/run/overrides.h"
#include "validation/studies/sweep.h"

namespace pbdval {
namespace {

struct Sequence {
  std::vector<std::vector<double>> values;
  std::vector<double> errors;
};

/// e = C h^p (+ floor), h halving from h0; `noise` multiplies each error by exp(N(0, noise²)).
Sequence manufactured(double order, int points, double floor = 0, double noise = 0,
                      unsigned seed = 1) {
  std::mt19937 random(seed);
  std::normal_distribution<double> normal(0, 1);
  Sequence s;
  double h = 0.01;
  for (int k = 0; k < points; ++k, h /= 2) {
    s.values.push_back({h});
    s.errors.push_back((3 * std::pow(h, order) + floor) * std::exp(noise * normal(random)));
  }
  return s;
}

bool hasFlag(const SweepFit& fit, const std::string& flag) {
  return std::find(fit.flags.begin(), fit.flags.end(), flag) != fit.flags.end();
}

TEST(ConvergenceFit, LocalOrdersAndTheFitRecoverKnownOrders) {
  for (double order : {1.0, 2.0, 4.0}) {
    const Sequence s = manufactured(order, 5);
    const SweepFit fit = fitConvergence("m", {"timeStepSize"}, s.values, s.errors);
    ASSERT_EQ(fit.localOrders.size(), 4u);
    for (const LocalOrder& local : fit.localOrders) {
      EXPECT_NEAR(local.order, order, 1e-9);  // exact power law: round-off only
      EXPECT_DOUBLE_EQ(local.from, 2 * local.to);
    }
    EXPECT_NEAR(fit.orders[0], order, 1e-9);
    EXPECT_TRUE(fit.excluded.empty());
    EXPECT_TRUE(fit.flags.empty());
    EXPECT_TRUE(fit.warning.empty()) << fit.warning;
  }
}

// The case: order 4 down to a floor at 1e-11 (round-off of the reference). The finest
// points sit on the floor; left out and named, the fit gives 4 instead of ~2.5.
TEST(ConvergenceFit, PointsOnAFloorAreLeftOutAndNamed) {
  const std::vector<std::vector<double>> h{{0.004}, {0.002}, {0.001}, {0.0005}};
  const std::vector<double> e{2.8e-9, 1.75e-10, 1.2e-11, 2.2e-11};
  const SweepFit all = fitConvergence("rk4", {"timeStepSize"}, h, e);
  ASSERT_EQ(all.excluded.size(), 1u);
  EXPECT_EQ(all.excluded[0].value, 0.0005);
  EXPECT_NE(all.excluded[0].reason.find("on a floor"), std::string::npos) << all.excluded[0].reason;
  EXPECT_EQ(all.points, 3);
  // log2(2.8e-9 / 1.2e-11) / 2 = 3.93 over the three points left: order 4 within the 2 %
  // the manufactured numbers carry (1.75e-10 is 2.8e-9 / 16 exactly; 1.2e-11 is 1/14.6).
  EXPECT_NEAR(all.orders[0], 4, 0.1);
  EXPECT_TRUE(hasFlag(all, "floor"));
  EXPECT_NE(all.warning.find("on a floor left out"), std::string::npos) << all.warning;

  // A hard floor: e = max(3 h², 1e-7), h = 0.01 halving seven times. The local orders are 2
  // down to h = 3.125e-4; 3.125e-4 → 1.5625e-4 gives log2(2.93e-7 / 1e-7) = 1.55 (kept: above
  // half of 2); 1.5625e-4 → 7.8125e-5 gives 0 (on the floor): exactly the last point goes.
  std::vector<std::vector<double>> steps;
  std::vector<double> errors;
  double step = 0.01;
  for (int k = 0; k < 8; ++k, step /= 2) {
    steps.push_back({step});
    errors.push_back(std::max(3 * step * step, 1e-7));
  }
  const SweepFit fit = fitConvergence("m", {"timeStepSize"}, steps, errors);
  EXPECT_TRUE(hasFlag(fit, "floor"));
  ASSERT_EQ(fit.excluded.size(), 1u);
  EXPECT_EQ(fit.excluded[0].value, 0.01 / 128);
  // Seven kept points, the last 37 % above the power law (1e-7 against 7.3e-8): the slope moves
  // by less than 0.1.
  EXPECT_NEAR(fit.orders[0], 2, 0.1);
}

// A count-like parameter (iterations, substeps): the error falls as it grows.
TEST(ConvergenceFit, CountLikeParametersRefineUpwards) {
  std::vector<std::vector<double>> n;
  std::vector<double> e;
  for (double count : {1.0, 2.0, 4.0, 8.0, 16.0}) {
    n.push_back({count});
    e.push_back(0.5 / count + (count >= 8 ? 0.2 : 0));  // a floor from 8 on
  }
  const SweepFit fit = fitConvergence("m", {"subSteps"}, n, e);
  ASSERT_EQ(fit.localOrders.size(), 4u);
  EXPECT_NEAR(fit.localOrders[0].order, 1, 1e-12);
  EXPECT_EQ(fit.localOrders[0].from, 1.0);
  EXPECT_TRUE(hasFlag(fit, "floor"));
  EXPECT_EQ(fit.excluded.size(), 2u);  // 8 and 16
}

// An error-controlled integrator (Drake's continuous plant) is refined by shrinking its target
// accuracy: the global error of a tolerance-proportional integrator falls as tol¹, and the
// order is that exponent, positive, as for a step. Counted like a count, the same errors would
// give −1 and every point would be "on a floor".
TEST(ConvergenceFit, TargetAccuracyIsRefinedDownwardsLikeAStep) {
  std::vector<std::vector<double>> tolerances;
  std::vector<double> errors;
  for (double tolerance : {1e-3, 1e-4, 1e-5, 1e-6}) {
    tolerances.push_back({tolerance});
    errors.push_back(40 * tolerance);
  }
  const SweepFit fit = fitConvergence("drake.rk3", {"targetAccuracy"}, tolerances, errors);
  EXPECT_NEAR(fit.orders[0], 1, 1e-9);  // an exact power law: round-off only
  ASSERT_EQ(fit.localOrders.size(), 3u);
  EXPECT_EQ(fit.localOrders[0].from, 1e-3);  // coarse to fine: the largest tolerance first
  EXPECT_TRUE(fit.flags.empty());
}

// Noise of 5 % on an order-2 sequence: the fit is flagged only when R² < 0.99; a sequence that
// is no power law at all (errors alternating) is flagged.
TEST(ConvergenceFit, PoorFitsAreFlagged) {
  const Sequence noisy = manufactured(2, 6, 0, 0.05, 7);
  const SweepFit fine = fitConvergence("m", {"timeStepSize"}, noisy.values, noisy.errors);
  EXPECT_NEAR(fine.orders[0], 2, 0.15);  // 5 % noise on six points spanning a factor 32
  EXPECT_GE(fine.rSquared, 0.99);
  EXPECT_FALSE(hasFlag(fine, "r_squared_below_0.99"));

  // Errors that zigzag: after the first halving (local order 6.6) the error rises (order < 0):
  // the two finest points are a floor, and the two left are too few to confirm an order.
  const std::vector<std::vector<double>> h{{0.008}, {0.004}, {0.002}, {0.001}};
  const std::vector<double> zigzag{1e-3, 1e-5, 8e-4, 2e-6};
  const SweepFit bad = fitConvergence("m", {"timeStepSize"}, h, zigzag);
  EXPECT_TRUE(hasFlag(bad, "floor"));
  EXPECT_EQ(bad.excluded.size(), 2u);
  EXPECT_TRUE(hasFlag(bad, "too_few_points"));
  EXPECT_NE(bad.warning.find("only 2 points"), std::string::npos) << bad.warning;

  // Scattered errors without a floor (each local order positive, none under half the first:
  // 2, 1.5, 6, 1.2): fitted, but R² < 0.99 is flagged.
  const std::vector<double> scattered{1e-2, 2.5e-3, 8.8e-4, 1.4e-5, 6.1e-6};
  const std::vector<std::vector<double>> h5{{0.016}, {0.008}, {0.004}, {0.002}, {0.001}};
  const SweepFit rough = fitConvergence("m", {"timeStepSize"}, h5, scattered);
  EXPECT_TRUE(rough.excluded.empty());
  EXPECT_LT(rough.rSquared, 0.99);
  EXPECT_TRUE(hasFlag(rough, "r_squared_below_0.99"));
  EXPECT_NE(rough.warning.find("R^2"), std::string::npos) << rough.warning;

  const SweepFit two = fitConvergence("m", {"timeStepSize"}, {{0.01}, {0.005}}, {4e-4, 1e-4});
  EXPECT_TRUE(two.orders.empty());  // two points determine a line, not a fit
  EXPECT_NE(two.note.find("not enough points"), std::string::npos);
}

// The whole path: MuJoCo's RK4 on the hinge pendulum against its own run at h/16, over four
// halvings of the step. Theory: order 4. The error at the finest step (~1e-12 m) is four
// orders above the reference's own (~(1/16)^4 of it) and above round-off, so no floor is
// expected; the fitted order must be 4 within 0.15 (the local orders measured on this machine
// rise from 3.98 to 3.99 as the step shrinks, as the next term of the error fades).
// The power law plus a floor: on exact sequences e = F + C·x^s the differences remove F and the
// fit is exact, so the tolerances are round-off (1e-9 relative: a few hundred ulps of the logs).
TEST(ConvergenceFit, PowerPlusFloorRecoversTheOrderAndTheFloorOfManufacturedSequences) {
  for (const auto& [order, floor] :
       std::vector<std::pair<double, double>>{{1.0, 0.02}, {2.0, 1e-6}, {4.0, 3e-11}}) {
    const Sequence s = manufactured(order, 5, floor);
    const SweepFit fit =
        fitConvergence("m", {"timeStepSize"}, s.values, s.errors, FitModel::PowerPlusFloor);
    ASSERT_EQ(fit.orders.size(), 1u);
    EXPECT_NEAR(fit.orders[0], order, 1e-9 * order) << "order " << order;
    EXPECT_NEAR(fit.floor, floor, 1e-9 * floor) << "order " << order;
    EXPECT_NEAR(fit.rSquared, 1.0, 1e-12);
    EXPECT_EQ(fit.points, 5);
    EXPECT_TRUE(fit.flags.empty()) << fit.warning;
    EXPECT_EQ(fit.model, FitModel::PowerPlusFloor);
    EXPECT_EQ(fit.localOrders.size(), 4u);  // reported as for a power law
  }
}

TEST(ConvergenceFit, PowerPlusFloorTakesAnErrorThatRisesToItsFloor) {
  // e = F − C·h: the discretisation error cancels part of the modelling error (penalty joints'
  // sag), so the error grows as h falls, towards F.
  Sequence s;
  for (double h = 0.01; h > 0.0006; h /= 2) {
    s.values.push_back({h});
    s.errors.push_back(0.0235 - 0.6 * h);
  }
  const SweepFit fit =
      fitConvergence("m", {"timeStepSize"}, s.values, s.errors, FitModel::PowerPlusFloor);
  EXPECT_NEAR(fit.orders[0], 1.0, 1e-9);
  EXPECT_NEAR(fit.floor, 0.0235, 1e-9 * 0.0235);
  EXPECT_TRUE(fit.flags.empty()) << fit.warning;
}

TEST(ConvergenceFit, PowerPlusFloorRefinesCountsUpwards) {
  // e = F + C·n^−2 over substeps 1, 2, 4, 8, 16: the order in 1/n is 2.
  Sequence s;
  for (double n = 1; n <= 16; n *= 2) {
    s.values.push_back({n});
    s.errors.push_back(5e-4 + 0.1 / (n * n));
  }
  const SweepFit fit =
      fitConvergence("m", {"subSteps"}, s.values, s.errors, FitModel::PowerPlusFloor);
  EXPECT_NEAR(fit.orders[0], 2.0, 1e-9);
  EXPECT_NEAR(fit.floor, 5e-4, 1e-9 * 5e-4);
}

TEST(ConvergenceFit, PowerPlusFloorFlagsWhatItCannotFit) {
  const Sequence three = manufactured(1.0, 3, 0.01);
  EXPECT_TRUE(hasFlag(
      fitConvergence("m", {"timeStepSize"}, three.values, three.errors, FitModel::PowerPlusFloor),
      "too_few_points"));
  // A negative floor: the errors show none (a power law with an offset below zero).
  Sequence below = manufactured(1.0, 5);
  for (double& e : below.errors)
    e -= 1e-3;
  EXPECT_TRUE(hasFlag(
      fitConvergence("m", {"timeStepSize"}, below.values, below.errors, FitModel::PowerPlusFloor),
      "no_floor"));
  // Differences of both signs: no power law approaches a floor.
  Sequence zigzag = manufactured(1.0, 5, 0.01);
  zigzag.errors[3] = zigzag.errors[2] * 1.01;
  EXPECT_TRUE(hasFlag(
      fitConvergence("m", {"timeStepSize"}, zigzag.values, zigzag.errors, FitModel::PowerPlusFloor),
      "differences_change_sign"));
  // Steps not refined by one ratio: the differences would not remove the floor.
  Sequence uneven = manufactured(1.0, 5, 0.01);
  uneven.values[4][0] *= 0.9;
  EXPECT_TRUE(hasFlag(
      fitConvergence("m", {"timeStepSize"}, uneven.values, uneven.errors, FitModel::PowerPlusFloor),
      "ratio_not_constant"));
  // A 2 % error of alternating sign on every point (a floor that itself wobbles, e.g. float32
  // round-off near it) is of the size of the finest differences: they no longer follow one power
  // law (R² 0.93 by hand), and the fit says so.
  Sequence wobbling = manufactured(1.0, 5, 0.02);
  for (std::size_t k = 0; k < wobbling.errors.size(); ++k)
    wobbling.errors[k] *= k % 2 ? 0.98 : 1.02;
  const SweepFit fit = fitConvergence("m", {"timeStepSize"}, wobbling.values, wobbling.errors,
                                      FitModel::PowerPlusFloor);
  EXPECT_TRUE(hasFlag(fit, "r_squared_below_0.99")) << "R^2 " << fit.rSquared;
}

TEST(ConvergenceFit, RungeKuttaShowsOrderFourThroughTheWholeSweep) {
  SweepOptions options;
  options.caseFile = std::string(PBDVAL_SOURCE_DIR) + "/cases/joint_hinge.json";
  options.parameters = {{"timeStepSize", {"0.004", "0.002", "0.001", "0.0005"}}};
  options.methods = {"mujoco.rk4"};
  options.metric = "trajectory_error_max";
  options.referenceMode = "fine";
  options.jobs = 2;
  options.repetitions = 1;  // the order, not the wall time, is under test
  options.scratchFolder =
      (std::filesystem::temp_directory_path() / ("pbdval-sweep-rk4-" + std::to_string(::getpid())))
          .string();
  const SweepResult result = runSweep(options, testRegistry());
  std::filesystem::remove_all(options.scratchFolder);
  ASSERT_EQ(result.fits.size(), 1u);
  const SweepFit& fit = result.fits[0];
  for (const SweepPoint& p : result.points)
    ASSERT_EQ(p.record.status, RunStatus::Ok) << p.record.reason;
  ASSERT_EQ(fit.orders.size(), 1u) << fit.note;
  EXPECT_NEAR(fit.orders[0], 4, 0.15);
  EXPECT_TRUE(fit.excluded.empty());
  for (const LocalOrder& local : fit.localOrders)
    EXPECT_NEAR(local.order, 4, 0.15);
}

// A point's wall time is the median of its passes (3 passes: the middle value, whatever the
// order they came in), every pass is kept, and the metric is the first pass's.
TEST(SweepWallTime, IsTheMedianOfThePasses) {
  SweepPlan plan;
  plan.caseName = "c";
  plan.metric = "trajectory_error_max";
  plan.parameters = {{"timeStepSize", {"0.01", "0.005"}}};
  plan.methods = {"pbd"};
  std::vector<RunRecord> first;
  for (const char* step : {"0.01", "0.005"}) {
    SweepPoint point;
    point.method = "pbd";
    point.values = {{"timeStepSize", step}};
    plan.points.push_back(point);
    RunRecord record;
    record.status = RunStatus::Ok;
    record.request.method = "pbd";
    record.metrics.values = {{"trajectory_error_max", std::stod(step)}, {"wall_time_s", 0.9}};
    first.push_back(record);
  }
  std::vector<std::vector<RunRecord>> repeats = {first, first};
  repeats[0][0].metrics.values["wall_time_s"] = 0.1;
  repeats[1][0].metrics.values["wall_time_s"] = 0.2;
  repeats[0][1].metrics.values["trajectory_error_max"] = 7;  // not the first pass: not the metric
  const SweepResult result = collectSweep(plan, first, repeats);
  EXPECT_EQ(result.points[0].wallTime, 0.2);
  EXPECT_EQ(result.points[0].wallTimes, (std::vector<double>{0.9, 0.1, 0.2}));
  EXPECT_EQ(result.points[1].wallTime, 0.9);
  EXPECT_EQ(result.points[1].metric, 0.005);
  repeats[1].pop_back();
  EXPECT_THROW(collectSweep(plan, first, repeats), std::invalid_argument);
}

TEST(SweepFitOfCollectedPoints, ASettingHeldAtOneTextValueDoesNotPreventTheFit) {
  // --param stepControl=fixed --param timeStepSize=...: the text setting does not vary, so the
  // fit is over the step alone (e = h³ here: order 3 exactly, to round-off).
  SweepPlan plan;
  plan.caseName = "c";
  plan.metric = "trajectory_error_max";
  plan.parameters = {{"stepControl", {"fixed"}}, {"timeStepSize", {"0.01", "0.005", "0.0025"}}};
  plan.methods = {"drake.radau"};
  std::vector<RunRecord> records;
  for (const char* step : {"0.01", "0.005", "0.0025"}) {
    SweepPoint point;
    point.method = "drake.radau";
    point.values = {{"stepControl", "fixed"}, {"timeStepSize", step}};
    plan.points.push_back(point);
    RunRecord record;
    record.status = RunStatus::Ok;
    record.metrics.values = {{"trajectory_error_max", std::pow(std::stod(step), 3)}};
    records.push_back(record);
  }
  const SweepResult held = collectSweep(plan, records);
  ASSERT_EQ(held.fits.size(), 1u);
  EXPECT_EQ(held.fits[0].parameters, (std::vector<std::string>{"timeStepSize"}));
  EXPECT_NEAR(held.fits[0].orders[0], 3.0, 1e-9);
  // Two text values of one setting vary, and text has no order: no fit, said so.
  plan.parameters[0].second = {"fixed", "error"};
  EXPECT_NE(collectSweep(plan, records).fits[0].note.find("not all numeric"), std::string::npos);
}

TEST(SweepFitOfCollectedPoints, AnErrorControlledIntegratorsOrderInItsStepsIsFittedToo) {
  // A third-order method whose controller takes N ∝ tol^(−1/3) steps and leaves e = N^−3 ∝ tol:
  // the order in the tolerance is 1 and the order in the steps 3, exactly (to round-off).
  SweepPlan plan;
  plan.caseName = "c";
  plan.metric = "trajectory_error_max";
  plan.parameters = {{"targetAccuracy", {"1e-3", "1e-4", "1e-5", "1e-6"}}};
  plan.methods = {"drake.rk3"};
  std::vector<RunRecord> records;
  for (const char* tolerance : {"1e-3", "1e-4", "1e-5", "1e-6"}) {
    SweepPoint point;
    point.method = "drake.rk3";
    point.values = {{"targetAccuracy", tolerance}};
    plan.points.push_back(point);
    const double steps = 100 * std::cbrt(1e-3 / std::stod(tolerance));
    RunRecord record;
    record.status = RunStatus::Ok;
    record.metrics.values = {{"trajectory_error_max", std::pow(steps, -3)}};
    record.settings[kStepsTakenSetting] = std::to_string(steps);
    records.push_back(record);
  }
  SweepResult result = collectSweep(plan, records);
  ASSERT_EQ(result.fits.size(), 1u);
  EXPECT_NEAR(result.fits[0].orders[0], 1.0, 1e-5);  // the steps are written with 6 digits
  EXPECT_NEAR(result.fits[0].workOrder, 3.0, 1e-5);
  EXPECT_TRUE(result.fits[0].workFlags.empty());
  // A run without the setting (a fixed-step engine): no order in the work.
  records[2].settings.clear();
  result = collectSweep(plan, records);
  EXPECT_TRUE(std::isnan(result.fits[0].workOrder));
}

TEST(SweepPointsAlongAPath, ParametersVariedTogetherTakeTheirIthValuesAndTheRestSpanTheGrid) {
  // k·h² held: the i-th step with the i-th stiffness, times the two substep counts of the grid.
  const std::vector<std::pair<std::string, std::vector<std::string>>> parameters = {
      {"substeps", {"5", "10"}},
      {"timeStepSize", {"0.01", "0.005", "0.0025"}},
      {"jointStiffness", {"1e4", "4e4", "1.6e5"}}};
  const auto points = sweepPoints(parameters, {"timeStepSize", "jointStiffness"});
  ASSERT_EQ(points.size(), 6u);  // 2 substep counts × 3 points of the path, not 2 × 3 × 3
  const std::vector<std::pair<std::string, std::string>> pairs = {
      {"0.01", "1e4"}, {"0.005", "4e4"}, {"0.0025", "1.6e5"}};
  for (std::size_t k = 0; k < points.size(); ++k) {
    ASSERT_EQ(points[k].size(), 3u);
    // Every point lists the parameters in the order they were given.
    EXPECT_EQ(points[k][0].first, "substeps");
    EXPECT_EQ(points[k][0].second, k < 3 ? "5" : "10");
    EXPECT_EQ(points[k][1],
              (std::pair<std::string, std::string>{"timeStepSize", pairs[k % 3].first}));
    EXPECT_EQ(points[k][2],
              (std::pair<std::string, std::string>{"jointStiffness", pairs[k % 3].second}));
  }
  // Without --together the same lists are the Cartesian grid.
  EXPECT_EQ(sweepPoints(parameters, {}).size(), 18u);
}

TEST(SweepPointsAlongAPath, AListThatCannotBeAPathIsAnErrorNamingIt) {
  const std::vector<std::pair<std::string, std::vector<std::string>>> parameters = {
      {"timeStepSize", {"0.01", "0.005", "0.0025"}},
      {"jointStiffness", {"1e4", "4e4"}},
      {"stepControl", {"fixed"}}};
  auto message = [&](const std::vector<std::string>& together) -> std::string {
    try {
      sweepPoints(parameters, together);
    } catch (const OptionError& error) {
      return error.what();
    }
    return "no error";
  };
  EXPECT_NE(message({"timeStepSize"}).find("two or more parameters"), std::string::npos);
  EXPECT_NE(message({"timeStepSize", "jointStifness"}).find("jointStifness is not a swept"),
            std::string::npos);
  EXPECT_NE(message({"timeStepSize", "timeStepSize"}).find("named twice"), std::string::npos);
  const std::string unequal = message({"timeStepSize", "jointStiffness"});
  EXPECT_NE(unequal.find("--together: --param jointStiffness has 2 values and --param "
                         "timeStepSize 3"),
            std::string::npos)
      << unequal;
  EXPECT_NE(message({"stepControl", "timeStepSize"}).find("stepControl has one value"),
            std::string::npos);
}

TEST(SweepPointsAlongAPath, ThePlanRunsThePairedAssignmentsOfEachPoint) {
  SweepOptions options;
  options.caseFile = std::string(PBDVAL_SOURCE_DIR) + "/cases/joint_hinge.json";
  options.parameters = {{"timeStepSize", {"0.01", "0.005"}}, {"subSteps", {"2", "4"}}};
  options.together = {"timeStepSize", "subSteps"};
  options.methods = {"pbd"};
  const SweepPlan plan = planSweep(options, testRegistry());
  ASSERT_EQ(plan.requests.size(), 2u);
  EXPECT_EQ(plan.requests[0].assignments,
            (std::vector<std::string>{"timeStepSize=0.01", "subSteps=2"}));
  EXPECT_EQ(plan.requests[1].assignments,
            (std::vector<std::string>{"timeStepSize=0.005", "subSteps=4"}));
  EXPECT_EQ(plan.together, options.together);
  options.together = {"timeStepSize", "maxIterations"};
  EXPECT_THROW(planSweep(options, testRegistry()), OptionError);
}

TEST(SweepFitOfCollectedPoints, APairedSweepIsFittedInItsCoordinateAlone) {
  // A penalty scheme along k = 1/h²: a first-order discretisation error 3h plus a compliance
  // error 5/k = 5h², added (the manufactured e = 3h + 5h²). The fit is in h alone (k is a
  // function of it: fitting both would be singular), and the local orders fall towards 1 as h
  // falls (the h² term dies out), as written below.
  SweepPlan plan;
  plan.caseName = "c";
  plan.metric = "trajectory_error_max";
  const std::vector<double> steps = {0.04, 0.02, 0.01, 0.005, 0.0025};
  std::vector<std::string> stepText, stiffnessText;
  for (double h : steps) {
    stepText.push_back(std::to_string(h));
    stiffnessText.push_back(std::to_string(1 / (h * h)));
  }
  plan.parameters = {{"timeStepSize", stepText}, {"jointStiffness", stiffnessText}};
  plan.together = {"timeStepSize", "jointStiffness"};
  plan.methods = {"newton.semiImplicit"};
  std::vector<RunRecord> records;
  for (const auto& values : sweepPoints(plan.parameters, plan.together)) {
    SweepPoint point;
    point.method = "newton.semiImplicit";
    point.values = values;
    plan.points.push_back(point);
    const double h = std::stod(values[0].second), k = std::stod(values[1].second);
    RunRecord record;
    record.status = RunStatus::Ok;
    record.metrics.values = {{"trajectory_error_max", 3 * h + 5 / k}};
    records.push_back(record);
  }
  ASSERT_EQ(plan.points.size(), steps.size());
  const SweepResult result = collectSweep(plan, records);
  ASSERT_EQ(result.fits.size(), 1u);
  const SweepFit& fit = result.fits[0];
  EXPECT_EQ(fit.parameters, (std::vector<std::string>{"timeStepSize"}));
  ASSERT_EQ(fit.localOrders.size(), steps.size() - 1);
  // log2((3h + 5h²) / (3h/2 + 5h²/4)) for h = 0.04 … 0.005: 1 + log2((1 + 5h/3)/(1 + 5h/6)).
  for (std::size_t k = 0; k < fit.localOrders.size(); ++k) {
    const double h = steps[k];
    EXPECT_NEAR(fit.localOrders[k].order, 1 + std::log2((1 + 5 * h / 3) / (1 + 5 * h / 6)),
                1e-9)  // round-off
        << "from h = " << h;
  }
  EXPECT_NEAR(fit.orders[0], 1.0, 0.05);  // the h² term bends the slope by < 0.05 here
  EXPECT_EQ(result.together, plan.together);

  // e = 2h² exactly along the path: order 2 to the digits the values are written with.
  for (std::size_t k = 0; k < records.size(); ++k)
    records[k].metrics.values["trajectory_error_max"] = 2 / std::stod(stiffnessText[k]);
  const SweepResult quadratic = collectSweep(plan, records);
  EXPECT_NEAR(quadratic.fits[0].orders[0], 2.0, 1e-9);  // round-off: the values are exact
  EXPECT_GT(quadratic.fits[0].rSquared, 1 - 1e-9);
  EXPECT_TRUE(quadratic.fits[0].flags.empty());
}

}  // namespace
}  // namespace pbdval
