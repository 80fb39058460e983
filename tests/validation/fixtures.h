// Helpers for the metric and reference tests: scenes built in code and states set by hand.
#pragma once

#include <cmath>
#include <string>

#include "common/scene_fixtures.h"
#include "validation/case_spec.h"
#include "validation/mechanics.h"

namespace pbdval::test {

using pbd::JointType;
using pbd::Scene;

inline constexpr double kPi = 3.14159265358979323846;

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
