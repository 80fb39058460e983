#include "adapters/mujoco/mujoco_settings.h"

#include <stdexcept>
#include <utility>

#include "pbd/io/number_text.h"

namespace pbdval::mujoco {
namespace {

struct IntegratorMethod {
  const char* method;
  const char* integrator;
  const char* description;
};
constexpr IntegratorMethod kIntegrators[] = {
    {"mujoco.euler", "Euler",
     "MuJoCo 2.2.2, semi-implicit Euler (implicit in joint damping only); reduced coordinates, "
     "soft constraints solved as a convex program"},
    {"mujoco.rk4", "RK4",
     "MuJoCo 2.2.2, 4th-order Runge-Kutta (collision and constraints at every stage)"},
    {"mujoco.implicit", "implicit",
     "MuJoCo 2.2.2, implicit in velocity (passive, actuator and Coriolis derivatives)"},
};

// MuJoCo's refsafe rule: a time constant below 2h makes the explicit spring-damper unstable
// (and MuJoCo would silently raise a positive one to 2h), so every time constant is >= 2h.
constexpr double kMinimumTimeConstantSteps = 2;

ParameterSpec impedance(std::string name, double value, std::string description) {
  return realParameter(std::move(name), value, 0.0001, 0.9999, "",
                       std::move(description));  // mjMIN/MAXIMP
}

std::vector<ParameterSpec> parameters() {
  ParameterSpec width =
      realParameter("solimpWidth", 0.001, 0, 1e6, "m",
                    "solimp width: distance over which the impedance goes from d0 to dwidth");
  width.minimumExclusive = true;
  ParameterSpec midpoint =
      realParameter("solimpMidpoint", 0.5, 0, 1, "", "solimp midpoint of the impedance sigmoid");
  midpoint.minimumExclusive = midpoint.maximumExclusive = true;
  ParameterSpec dampratio = realParameter("equalityDampratio", 1, 0, 1e6, "",
                                          "damping ratio of equality constraints (solref[1])");
  dampratio.minimumExclusive = true;
  return {
      choiceParameter("solver", "Newton", {"Newton", "CG", "PGS"}, "constraint solver"),
      integerParameter("iterations", 100, 1, 1e6, "maximum solver iterations per step"),
      realParameter("tolerance", 1e-8, 0, 1, "", "solver tolerance (relative cost improvement)"),
      choiceParameter(
          "cone", "elliptic", {"elliptic", "pyramidal"},
          "friction cone: elliptic (isotropic) or pyramidal (4 edges in the contact frame)"),
      durationParameter("contactTimeconst", "4h", kMinimumTimeConstantSteps,
                        "contact time constant tau; stiffness 1/tau^2, damping from the pair's "
                        "restitution"),
      impedance("solimpD0", 0.99,
                "impedance of contacts and equality constraints at zero violation (solimp[0])"),
      impedance("solimpDwidth", 0.99,
                "impedance at a violation of solimpWidth or more (solimp[1])"),
      width,
      midpoint,
      realParameter("solimpPower", 2, 1, 1e6, "", "power of the impedance sigmoid (solimp[4])"),
      durationParameter("equalityTimeconst", "2h", kMinimumTimeConstantSteps,
                        "time constant of equality constraints (loop-closing joints, distance "
                        "joints; solref[0])"),
      dampratio,
      durationParameter("servoTimeconst", "4h", kMinimumTimeConstantSteps,
                        "time constant of the motor servos"),
  };
}

}  // namespace

std::vector<MethodInfo> mujocoMethods() {
  std::vector<MethodInfo> methods;
  for (const IntegratorMethod& i : kIntegrators)
    methods.push_back({i.method, "mujoco", i.description, parameters()});
  return methods;
}

MujocoSettings mujocoSettingsFor(const pbd::Scene& scene, const Method& method) {
  MujocoSettings s;
  bool known = false;
  for (const IntegratorMethod& i : kIntegrators)
    if (method.name == i.method) {
      s.integrator = i.integrator;
      known = true;
    }
  if (!known) throw std::invalid_argument("method " + method.name + " is not a MuJoCo method");
  s.stepSize = double(scene.simulation.timeStepSize);
  s.solver = method.choice("solver");
  s.cone = method.choice("cone");
  s.iterations = static_cast<int>(method.integer("iterations"));
  s.tolerance = method.real("tolerance");
  s.contactTimeConstant = method.seconds("contactTimeconst", s.stepSize);
  s.equalitySolref = {method.seconds("equalityTimeconst", s.stepSize),
                      method.real("equalityDampratio")};
  s.servoTimeConstant = method.seconds("servoTimeconst", s.stepSize);
  s.solimp = {method.real("solimpD0"), method.real("solimpDwidth"), method.real("solimpWidth"),
              method.real("solimpMidpoint"), method.real("solimpPower")};
  return s;
}

std::map<std::string, std::string> describeSettings(const MujocoSettings& s) {
  std::string solimpText;
  for (double v : s.solimp)
    solimpText += (solimpText.empty() ? "" : " ") + pbd::formatReal(v);
  return {{"integrator", s.integrator},
          {"solver", s.solver},
          {"iterations", std::to_string(s.iterations)},
          {"tolerance", pbd::formatReal(s.tolerance)},
          {"cone", s.cone},
          {"timestep", pbd::formatReal(s.stepSize)},
          {"contact.timeconst", pbd::formatReal(s.contactTimeConstant)},
          {"contact.solref", "direct (-1/tau^2, -2 zeta/tau), zeta from the pair restitution"},
          {"solimp", solimpText},
          {"equality.solref",
           pbd::formatReal(s.equalitySolref[0]) + " " + pbd::formatReal(s.equalitySolref[1])},
          {"servo.timeconst", pbd::formatReal(s.servoTimeConstant)}};
}

}  // namespace pbdval::mujoco
