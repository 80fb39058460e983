// The solver configuration of one MuJoCo run: the method (integrator) and its parameters,
// resolved against the scene's step size. Every value ends up in effectiveSettings().
#pragma once

#include <array>
#include <map>
#include <string>
#include <vector>

#include "adapters/engine.h"

namespace pbdval::mujoco {

struct MujocoSettings {
  std::string integrator = "Euler";  ///< MJCF name: Euler, RK4, implicit
  std::string solver = "Newton";     ///< PGS, CG, Newton
  int iterations = 100;
  double tolerance = 1e-8;
  std::string cone = "elliptic";  ///< elliptic, pyramidal
  double stepSize = 0;            ///< the scene's timeStepSize (s)
  /// Contacts: stiffness 1/τ², damping from the pair restitution (contact_softness.h).
  double contactTimeConstant = 0;
  /// Equality constraints (loop closures, distance joints): MuJoCo's (timeconst, dampratio).
  std::array<double, 2> equalitySolref = {0, 1};
  /// Impedance of every contact and equality constraint (MuJoCo's five solimp numbers).
  std::array<double, 5> solimp = {0.99, 0.99, 0.001, 0.5, 2};
  /// Motor servos reach their set point with this time constant (s).
  double servoTimeConstant = 0;
};

/// The methods mujoco.euler, mujoco.rk4 and mujoco.implicit with their parameters.
std::vector<MethodInfo> mujocoMethods();

/// Resolves `method` for `scene` ("4h" → 4 × timeStepSize). Throws std::invalid_argument
/// naming the parameter for a value out of range or not understood.
MujocoSettings mujocoSettingsFor(const pbd::Scene& scene, const Method& method);

/// The settings as text, for effectiveSettings().
std::map<std::string, std::string> describeSettings(const MujocoSettings& settings);

}  // namespace pbdval::mujoco
