// Typed method parameters: one parser and one range check for every engine. Every built-in
// method's defaults satisfy their own declarations, values out of range are refused with the
// range named, and the canonical text reads back to the same value.
#include <gtest/gtest.h>

#include "adapters/built_in_engines.h"
#include "adapters/parameters.h"
#include "engines/selftest_engine.h"
#include "pbd/io/number_text.h"

namespace pbdval {
namespace {

std::string errorOf(const ParameterSpec& spec, const std::string& text) {
  try {
    parseParameter(spec, text, "m");
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(Parameters, EveryDefaultOfEveryMethodParsesAndRoundTrips) {
  for (const EngineEntry& engine : testRegistry().entries())
    for (const MethodInfo& method : engine.methods)
      for (const ParameterSpec& spec : method.parameters) {
        const ParameterValue value = parseParameter(spec, spec.defaultValue, method.name);
        EXPECT_EQ(parseParameter(spec, value.text(), method.name), value)
            << method.name << "." << spec.name;
        EXPECT_FALSE(spec.description.empty()) << method.name << "." << spec.name;
      }
}

TEST(Parameters, RangesAreCheckedAndNamed) {
  const ParameterSpec iterations = integerParameter("iterations", 10, 1, 100, "sweeps");
  EXPECT_EQ(parseParameter(iterations, "100", "m").number, 100);
  EXPECT_EQ(errorOf(iterations, "0"),
            "method m: iterations: expected an integer in [1, 100], got '0'");
  EXPECT_NE(errorOf(iterations, "2.5"), "");
  EXPECT_NE(errorOf(iterations, "1e1"), "");  // integers are written as integers
  EXPECT_NE(errorOf(iterations, ""), "");

  ParameterSpec sor = realParameter("sor", 1.3, 0, 2, "", "relaxation");
  sor.minimumExclusive = sor.maximumExclusive = true;
  EXPECT_EQ(errorOf(sor, "2"), "method m: sor: expected a number in (0, 2), got '2'");
  EXPECT_NE(errorOf(sor, "nan"), "");
  EXPECT_NE(errorOf(sor, "inf"), "");
  EXPECT_NE(errorOf(sor, " 1"), "");
  EXPECT_EQ(parseParameter(sor, "1.999", "m").number, 1.999);

  const ParameterSpec flag = boolParameter("gyroscopic", true, "on");
  EXPECT_EQ(parseParameter(flag, "0", "m").number, 0);
  EXPECT_EQ(parseParameter(flag, "true", "m").text(), "true");
  EXPECT_NE(errorOf(flag, "yes"), "");

  const ParameterSpec solver = choiceParameter("solver", "Newton", {"Newton", "CG"}, "solver");
  EXPECT_EQ(errorOf(solver, "PGS"), "method m: solver: expected one of Newton, CG, got 'PGS'");
}

TEST(Parameters, DurationsInStepsAreResolvedAndCheckedAgainstTheStep) {
  const ParameterSpec tau = durationParameter("timeconst", "4h", 2, "time constant");
  const ParameterValue steps = parseParameter(tau, "4h", "m");
  EXPECT_TRUE(steps.inSteps);
  EXPECT_DOUBLE_EQ(durationSeconds(tau, steps, 0.002, "m"), 0.008);
  EXPECT_NE(errorOf(tau, "1h"), "");  // fewer than 2 steps, whatever the step
  const ParameterValue seconds = parseParameter(tau, "0.003", "m");
  EXPECT_DOUBLE_EQ(durationSeconds(tau, seconds, 0.001, "m"), 0.003);
  EXPECT_THROW(durationSeconds(tau, seconds, 0.002, "m"), std::invalid_argument);  // 1.5 steps
}

TEST(Parameters, UnknownParametersAndWrongKindsAreErrors) {
  EXPECT_THROW(testRegistry().resolve("ode.quickstep", {{"substeps", "2"}}), std::invalid_argument);
  const Method quick = testRegistry().resolve("ode.quickstep", {{"iterations", "40"}});
  EXPECT_EQ(quick.integer("iterations"), 40);
  EXPECT_THROW(quick.real("iterations"), std::invalid_argument);  // an integer, not a real
  EXPECT_THROW(quick.real("noSuchParameter"), std::invalid_argument);
}

TEST(NumberText, ShortestRoundTripAndStrictParsing) {
  for (double v : {0.1, 1e-10, 1.0 / 3.0, -2.5e300, 5e-324, 0.0})
    EXPECT_EQ(pbd::parseReal(pbd::formatReal(v)), v) << pbd::formatReal(v);
  EXPECT_EQ(pbd::formatReal(0.1), "0.1");
  EXPECT_EQ(pbd::formatReal(1e-10), "1e-10");
  EXPECT_FALSE(pbd::parseReal("1e999"));  // overflow
  EXPECT_FALSE(pbd::parseReal("0x10"));
  EXPECT_FALSE(pbd::parseReal("1.5m"));
  EXPECT_FALSE(pbd::parseReal("+1"));
  EXPECT_EQ(pbd::parseInteger("-12"), -12);
  EXPECT_FALSE(pbd::parseInteger("99999999999999999999"));
  EXPECT_FALSE(pbd::parseInteger("1.0"));
}

TEST(Registry, EnginesAndMethodsAreUniqueAndTheSelftestEngineIsTheTestsOnly) {
  EngineRegistry registry = testEngines();
  EXPECT_THROW(registry.add(selftestEngineEntry()), std::invalid_argument);  // taken name
  const std::vector<std::string> names = builtInEngines().engineNames();
  EXPECT_EQ(names, (std::vector<std::string>{"pbd", "bullet", "ode", "mujoco"}));
  EXPECT_THROW(builtInEngines().method("selftest.ok"), std::invalid_argument);
}

}  // namespace
}  // namespace pbdval
