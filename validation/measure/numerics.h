// Small numerical building blocks of the metrics (docs/metrics.md): rotation angles, a
// least-squares slope, and resampling of a run onto other sample times.
#pragma once

#include <vector>

#include "adapters/engine.h"

namespace pbdval {

/// Geodesic angle between two orientations, 2 acos |⟨a, b⟩| ∈ [0, π] (rad), evaluated as
/// 2 atan2(‖vec(a⁻¹ b)‖, |w(a⁻¹ b)|), which is accurate also for tiny angles. q and −q are
/// the same orientation. Inputs need not be normalised.
double geodesicAngle(const Quaternion& a, const Quaternion& b);

/// Rotation angle of a single orientation, geodesicAngle(identity, q).
double rotationAngle(const Quaternion& q);

/// Signed rotation angle of q about the unit `axis` (its twist): 2 atan2(vec(q)·axis, w),
/// wrapped to (−π, π]. For a rotation about `axis` this is its angle.
double twistAngle(const Quaternion& q, const Vector3& axis);

/// Wraps an angle to (−π, π].
double wrapAngle(double angle);

/// Angle between two directions, atan2(‖a × b‖, a·b) ∈ [0, π] (rad).
double angleBetween(const Vector3& a, const Vector3& b);

/// Slope of the least-squares line y ≈ c + s·x: s = Σ (x − x̄)(y − ȳ) / Σ (x − x̄)².
/// Returns 0 when fewer than two distinct x are given. Throws std::invalid_argument when the
/// sizes differ.
double leastSquaresSlope(const std::vector<double>& x, const std::vector<double>& y);

/// The states of `source` (ordered by time) at `times` (interpolateState between the two
/// samples around each time). A time equal to a source sample returns that sample exactly. Times
/// may lie outside [t_first, t_last] by at most 1e-9·max(1, |t|) (then clamped); otherwise
/// std::invalid_argument. All states of `source` must hold the same bodies and particles.
std::vector<State> resampleStates(const std::vector<State>& source,
                                  const std::vector<double>& times);

/// The state between samples `a` and `b` at fraction s ∈ [0, 1] of their interval, labelled
/// `time`: positions (bodies and particles) by cubic Hermite interpolation with the samples'
/// velocities (exact for cubic motion; velocities from its derivative), rotations by a cubic
/// Hermite of the rotation vector with the angular velocities (exact for a constant angular
/// velocity, O(Δt⁴) for a smooth one; the shorter arc), angular velocities linearly. Linear
/// interpolation would add about Δt²·|a|/8 to any error measured against it, which hides the
/// order of a high-order method (docs/convergence.md).
State interpolateState(const State& a, const State& b, double s, double time);

}  // namespace pbdval
