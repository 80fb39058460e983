#include "adapters/mujoco/mujoco_settings.h"

#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

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

std::vector<MethodParameter> parameters() {
  return {
      {"solver", "Newton", "constraint solver: Newton, CG or PGS"},
      {"iterations", "100", "maximum solver iterations per step"},
      {"tolerance", "1e-8", "solver tolerance (relative cost improvement)"},
      {"cone", "elliptic",
       "friction cone: elliptic (isotropic) or pyramidal (4 edges in the contact frame)"},
      {"contactTimeconst", "4h",
       "contact time constant tau (s, or a multiple of the step: '4h'); stiffness 1/tau^2, damping "
       "from the pair's restitution"},
      {"solimp", "0.99 0.99 0.001 0.5 2",
       "impedance of contacts and equality constraints (MuJoCo solimp: d0 dwidth width midpoint "
       "power)"},
      {"equalitySolref", "2h 1",
       "timeconst and dampratio of equality constraints (loop-closing joints, distance joints)"},
      {"servoTimeconst", "4h", "time constant of the motor servos (s, or a multiple of the step)"},
  };
}

[[noreturn]] void reject(const Method& method, const std::string& parameter,
                         const std::string& expectation) {
  throw std::invalid_argument("method " + method.name + ": " + parameter + " must be " +
                              expectation + ", got '" + method.text(parameter) + "'");
}

std::vector<std::string> words(const std::string& text) {
  std::istringstream in(text);
  std::vector<std::string> result;
  for (std::string word; in >> word;)
    result.push_back(word);
  return result;
}

/// A plain number; NaN when `word` is not one.
double plainNumber(const std::string& word) {
  char* end = nullptr;
  const double value = std::strtod(word.c_str(), &end);
  if (word.empty() || end != word.c_str() + word.size() || !std::isfinite(value))
    return std::nan("");
  return value;
}

/// "0.01" (seconds) or "4h" (4 × step); NaN when not understood.
double duration(const std::string& word, double stepSize) {
  const bool inSteps = !word.empty() && word.back() == 'h';
  const double value = plainNumber(inSteps ? word.substr(0, word.size() - 1) : word);
  return inSteps ? value * stepSize : value;
}

double timeConstant(const Method& method, const std::string& parameter, const std::string& word,
                    double stepSize) {
  const double value = duration(word, stepSize);
  // MuJoCo's refsafe rule: below 2h the explicit spring-damper is unstable (and MuJoCo would
  // silently raise a positive timeconst to 2h).
  if (!(value >= 2 * stepSize * (1 - 1e-12)))
    reject(method, parameter,
           "a time constant of at least 2h = " + exactNumber(2 * stepSize) + " s");
  return value;
}

std::string choice(const Method& method, const std::string& parameter,
                   const std::vector<std::string>& allowed) {
  const std::string& value = method.text(parameter);
  for (const std::string& a : allowed)
    if (value == a) return value;
  std::string list;
  for (const std::string& a : allowed)
    list += (list.empty() ? "" : ", ") + a;
  reject(method, parameter, "one of " + list);
}

std::array<double, 5> solimp(const Method& method) {
  const std::vector<std::string> w = words(method.text("solimp"));
  std::array<double, 5> v{};
  if (w.size() != 5) reject(method, "solimp", "five numbers");
  for (std::size_t i = 0; i < 5; ++i)
    v[i] = plainNumber(w[i]);
  const auto impedance = [](double d) { return d >= 0.0001 && d <= 0.9999; };  // mjMIN/MAXIMP
  if (!impedance(v[0]) || !impedance(v[1]) || !(v[2] > 0) || !(v[3] > 0 && v[3] < 1) ||
      !(v[4] >= 1))
    reject(method, "solimp",
           "d0, dwidth in [0.0001, 0.9999], width > 0, midpoint in (0, 1), power >= 1");
  return v;
}

}  // namespace

std::string exactNumber(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.17g", value);
  return buffer;
}

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
  s.solver = choice(method, "solver", {"Newton", "CG", "PGS"});
  s.cone = choice(method, "cone", {"elliptic", "pyramidal"});
  const double iterations = method.number("iterations");
  if (!(iterations >= 1 && iterations <= 1e6 && iterations == std::floor(iterations)))
    reject(method, "iterations", "an integer in [1, 1000000]");
  s.iterations = int(iterations);
  s.tolerance = method.number("tolerance");
  if (!(s.tolerance >= 0)) reject(method, "tolerance", "a number >= 0");
  const std::vector<std::string> contact = words(method.text("contactTimeconst"));
  if (contact.size() != 1) reject(method, "contactTimeconst", "one time constant");
  s.contactTimeConstant = timeConstant(method, "contactTimeconst", contact[0], s.stepSize);
  const std::vector<std::string> equality = words(method.text("equalitySolref"));
  if (equality.size() != 2) reject(method, "equalitySolref", "'timeconst dampratio'");
  s.equalitySolref[0] = timeConstant(method, "equalitySolref", equality[0], s.stepSize);
  s.equalitySolref[1] = plainNumber(equality[1]);
  if (!(s.equalitySolref[1] > 0))
    reject(method, "equalitySolref", "'timeconst dampratio' with dampratio > 0");
  const std::vector<std::string> servo = words(method.text("servoTimeconst"));
  if (servo.size() != 1) reject(method, "servoTimeconst", "one time constant");
  s.servoTimeConstant = timeConstant(method, "servoTimeconst", servo[0], s.stepSize);
  s.solimp = solimp(method);
  return s;
}

std::map<std::string, std::string> describeSettings(const MujocoSettings& s) {
  std::string solimpText;
  for (double v : s.solimp)
    solimpText += (solimpText.empty() ? "" : " ") + exactNumber(v);
  return {{"integrator", s.integrator},
          {"solver", s.solver},
          {"iterations", std::to_string(s.iterations)},
          {"tolerance", exactNumber(s.tolerance)},
          {"cone", s.cone},
          {"timestep", exactNumber(s.stepSize)},
          {"contact.timeconst", exactNumber(s.contactTimeConstant)},
          {"contact.solref", "direct (-1/tau^2, -2 zeta/tau), zeta from the pair restitution"},
          {"solimp", solimpText},
          {"equality.solref",
           exactNumber(s.equalitySolref[0]) + " " + exactNumber(s.equalitySolref[1])},
          {"servo.timeconst", exactNumber(s.servoTimeConstant)}};
}

}  // namespace pbdval::mujoco
