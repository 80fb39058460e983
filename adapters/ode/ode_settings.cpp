#include "adapters/ode/ode_settings.h"

#include <cmath>
#include <cstdio>

namespace pbdval {
namespace {

constexpr const char* kStep = "ode.step";
constexpr const char* kQuickStep = "ode.quickstep";

std::vector<MethodParameter> commonParameters() {
  return {
      {"erp", "0.2", "joint error reduction per step, in [0, 1] (ODE's default)"},
      {"cfm", "1e-10", "joint constraint force mixing, >= 0 (ODE's double-precision default)"},
      {"contactErp", "0.2", "contact error reduction per step (soft_erp), in [0, 1]"},
      {"contactCfm", "1e-10", "contact constraint force mixing (soft_cfm), >= 0"},
      {"maxContacts", "8", "contact points per colliding pair, integer in [1, 64]"},
      {"gyroscopic", "1", "1: gyroscopic term on (ODE's default), 0: off"},
  };
}

std::string shortNumber(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%g", value);
  return buffer;
}

double numberIn(const Method& method, const std::string& name, double lowest, double highest) {
  const double value = method.number(name);
  if (!(value >= lowest && value <= highest))
    throw std::invalid_argument("method " + method.name + ": " + name + " must be in [" +
                                shortNumber(lowest) + ", " + shortNumber(highest) + "], got '" +
                                method.text(name) + "'");
  return value;
}

int integerIn(const Method& method, const std::string& name, int lowest, int highest) {
  const double value = numberIn(method, name, lowest, highest);
  if (value != std::floor(value))
    throw std::invalid_argument("method " + method.name + ": " + name +
                                " must be an integer, got '" + method.text(name) + "'");
  return static_cast<int>(value);
}

}  // namespace

std::vector<MethodInfo> odeMethods() {
  MethodInfo step;
  step.name = kStep;
  step.engine = "ode";
  step.description =
      "ODE 0.16 dWorldStep: semi-implicit Euler, the whole constraint system solved by the "
      "direct (Dantzig) LCP solver";
  step.parameters = commonParameters();
  step.parameters.push_back(
      {"carriageMassRatio", "1e-3",
       "ball-on-line joints: mass of the auxiliary carriage body relative to the lighter dynamic "
       "end, in (0, 1]"});

  MethodInfo quick;
  quick.name = kQuickStep;
  quick.engine = "ode";
  quick.description =
      "ODE 0.16 dWorldQuickStep: semi-implicit Euler, projected Gauss-Seidel with successive "
      "over-relaxation";
  quick.parameters = {{"iterations", "20", "SOR sweeps per step, integer >= 1 (ODE's default)"},
                      {"sor", "1.3", "over-relaxation factor w, in (0, 2) (ODE's default)"}};
  for (MethodParameter& p : commonParameters())
    quick.parameters.push_back(std::move(p));
  return {step, quick};
}

OdeSettings odeSettingsFor(const Method& method) {
  OdeSettings s;
  if (method.name == kStep) {
    s.solver = OdeSettings::Solver::Step;
    s.carriageMassRatio = numberIn(method, "carriageMassRatio", 1e-9, 1);
  } else if (method.name == kQuickStep) {
    s.solver = OdeSettings::Solver::QuickStep;
    s.iterations = integerIn(method, "iterations", 1, 1 << 20);
    s.overRelaxation = numberIn(method, "sor", 1e-6, 2 - 1e-6);
  } else {
    throw std::invalid_argument("method " + method.name + " is not an ODE method");
  }
  s.erp = numberIn(method, "erp", 0, 1);
  s.cfm = numberIn(method, "cfm", 0, 1e6);
  s.contactErp = numberIn(method, "contactErp", 0, 1);
  s.contactCfm = numberIn(method, "contactCfm", 0, 1e6);
  s.maxContacts = integerIn(method, "maxContacts", 1, 64);
  s.gyroscopic = integerIn(method, "gyroscopic", 0, 1) == 1;
  return s;
}

}  // namespace pbdval
