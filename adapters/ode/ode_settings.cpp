#include "adapters/ode/ode_settings.h"

#include <stdexcept>

namespace pbdval {
namespace {

constexpr const char* kStep = "ode.step";
constexpr const char* kQuickStep = "ode.quickstep";

std::vector<ParameterSpec> commonParameters() {
  return {
      realParameter("erp", 0.2, 0, 1, "", "joint error reduction per step (ODE's default)"),
      realParameter("cfm", 1e-10, 0, 1e6, "",
                    "joint constraint force mixing (ODE's double-precision default)"),
      realParameter("contactErp", 0.2, 0, 1, "", "contact error reduction per step (soft_erp)"),
      realParameter("contactCfm", 1e-10, 0, 1e6, "", "contact constraint force mixing (soft_cfm)"),
      integerParameter("maxContacts", 8, 1, 64, "contact points per colliding pair"),
      boolParameter("gyroscopic", true, "gyroscopic term (ODE's default: on)"),
  };
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
  ParameterSpec carriage = realParameter(
      "carriageMassRatio", 1e-3, 0, 1, "",
      "ball-on-line joints: mass of the auxiliary carriage body relative to the lighter dynamic "
      "end");
  carriage.minimumExclusive = true;
  step.parameters.push_back(carriage);

  MethodInfo quick;
  quick.name = kQuickStep;
  quick.engine = "ode";
  quick.description =
      "ODE 0.16 dWorldQuickStep: semi-implicit Euler, projected Gauss-Seidel with successive "
      "over-relaxation";
  ParameterSpec sor =
      realParameter("sor", 1.3, 0, 2, "", "over-relaxation factor w (ODE's default)");
  sor.minimumExclusive = sor.maximumExclusive = true;
  quick.parameters = {
      integerParameter("iterations", 20, 1, 1 << 20, "SOR sweeps per step (ODE's default)"), sor};
  for (ParameterSpec& p : commonParameters())
    quick.parameters.push_back(std::move(p));
  return {step, quick};
}

OdeSettings odeSettingsFor(const Method& method) {
  OdeSettings s;
  if (method.name == kStep) {
    s.solver = OdeSettings::Solver::Step;
    s.carriageMassRatio = method.real("carriageMassRatio");
  } else if (method.name == kQuickStep) {
    s.solver = OdeSettings::Solver::QuickStep;
    s.iterations = static_cast<int>(method.integer("iterations"));
    s.overRelaxation = method.real("sor");
  } else {
    throw std::invalid_argument("method " + method.name + " is not an ODE method");
  }
  s.erp = method.real("erp");
  s.cfm = method.real("cfm");
  s.contactErp = method.real("contactErp");
  s.contactCfm = method.real("contactCfm");
  s.maxContacts = static_cast<int>(method.integer("maxContacts"));
  s.gyroscopic = method.flag("gyroscopic");
  return s;
}

}  // namespace pbdval
