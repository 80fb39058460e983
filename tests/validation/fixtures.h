// Helpers for the metric and reference tests: scenes built in code and states set by hand.
#pragma once

#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/scene_fixtures.h"
#include "validation/measure/mechanics.h"
#include "validation/run/case_spec.h"

namespace pbdval::test {

using pbd::JointType;
using pbd::Scene;

inline constexpr double kPi = 3.14159265358979323846;

/// An analytic reference spec for `model` with JSON `parameters`.
inline ReferenceSpec analytic(const std::string& model, const std::string& parameters = "{}") {
  ReferenceSpec spec;
  spec.kind = ReferenceSpec::Kind::Analytic;
  spec.model = model;
  spec.parametersJson = parameters;
  return spec;
}

/// 0, interval, 2·interval, ... up to `end` (inclusive to round-off).
inline std::vector<double> timesUpTo(double end, double interval) {
  std::vector<double> times;
  for (int k = 0; k * interval <= end + 1e-12; ++k)
    times.push_back(k * interval);
  return times;
}

/// The message of the std::invalid_argument `f` throws ("" when it does not).
inline std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

/// A unit quaternion for `angle` rad about `axis` (normalised here).
inline Quaternion turn(const Vector3& axis, double angle) {
  return Quaternion(Eigen::AngleAxis<pbd::Real>(angle, axis.normalized()));
}

/// A scene with the given gravity and no bodies.
inline Scene emptyScene(const Vector3& gravity = Vector3(0, -9.81, 0)) {
  Scene s;
  s.simulation.gravitation = gravity;
  return s;
}

/// Moves body `index` of `state` rigidly: x ← R (x − pivot) + pivot + shift, q ← R q.
inline void moveBody(State& state, std::size_t index, const Quaternion& rotation,
                     const Vector3& pivot, const Vector3& shift) {
  BodyState& b = state.bodies[index];
  b.position = rotation * (b.position - pivot) + pivot + shift;
  b.rotation = (rotation * b.rotation).normalized();
}

}  // namespace pbdval::test
