// What the parity suite (test_parity.cpp) expects of each engine. Every engine registered in
// adapters/registry.cpp has one profile here; the suite runs the same scenes in all of them
// and holds each to its profile. A profile states facts about the engine's method (its
// integrator, its friction cone) and tolerances, each with the reason for its size.
#pragma once

#include <ostream>
#include <set>
#include <string>
#include <vector>

#include "pbd/model/scene.h"

namespace pbdval::test {

enum class FrictionCone {
  Isotropic,  ///< Coulomb cone: friction opposes sliding in any direction equally
  Pyramid,    ///< per-axis limits in a world-aligned tangent basis: holds up to √2 μ at 45°
};

struct ParityProfile {
  std::string engine;
  std::string method;

  /// Free fall follows the discrete semi-implicit Euler parabola with this many integration
  /// steps per scene step (PBD: subSteps). 0: the method integrates constant acceleration
  /// exactly (RK4).
  int integrationStepsPerStep = 1;

  /// Joint types on which a pendulum can be built in this engine.
  std::set<pbd::JointType> pendulumJoints;
  /// Relative period error allowed: factor × ω₀ h (a first-order bound; ω₀ the small-angle
  /// frequency, h the scene step).
  double periodErrorFactor = 1;
  /// Joint error allowed: factor × h² a_max (the drift one step of motion can cause;
  /// a_max the pendulum's largest acceleration).
  double jointErrorFactor = 10;

  /// Spinning free body: kinetic energy ≤ (1 + bound) × its initial value.
  double energyGrowthBound = 0.01;
  /// false for a method known to be unstable on the spinning body (explicit gyroscopic forces),
  /// with the reason in `notes`: the test then asserts the predicted growth instead.
  bool spinningBodies = true;

  /// Contact tests (drop, incline) run only when true.
  bool contacts = true;
  /// Rebound apex ratio: |ratio − e²| ≤ this.
  double reboundTolerance = 0.05;
  /// Incline: a sticking block moves at most this far in 1 s (m); a sliding block's
  /// acceleration is within this relative error of g (sin θ − μ cos θ).
  double stickCreep = 1e-3;
  double slideAccelerationTolerance = 0.05;
  FrictionCone frictionCone = FrictionCone::Isotropic;

  /// Why a tolerance differs from the default, for the report.
  std::string notes;
};

/// For test names and failure messages: "ode/ode.quickstep".
inline void PrintTo(const ParityProfile& p, std::ostream* out) {
  *out << p.engine << "/" << p.method;
}

/// The profiles of the engines compiled in (registry order).
std::vector<ParityProfile> parityProfiles();

}  // namespace pbdval::test
