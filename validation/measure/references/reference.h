// Analytic references (docs/references.md): small documented models that give the exact (or
// high-accuracy) motion of a case's bodies, sampled at a run's sample times. Models (one
// header each in validation/measure/references/, formula and literature at its top): projectile and
// free_fall (ballistic.h), pendulum and simple_pendulum (pendulum.h), harmonic_oscillator,
// torque_free_symmetric and torque_free_asymmetric (torque_free.h), sliding_block,
// rolling_sphere and bowling_ball (contact_motion.h), bouncing_ball.
#pragma once

#include <vector>

#include "validation/measure/metrics.h"

namespace pbdval {

/// Builds the analytic reference `spec.model` with `spec.parametersJson` for `scene`, sampled
/// at `times` (non-decreasing, ≥ 0). The samples hold every body of the Scene (undescribed
/// ones at their initial state); `bodies` masks the described ones; `hasRotation` says whether
/// the model gives their orientations. `integrationStep` is the run's effective integration step
/// (for the discrete closed forms, e.g. semi-implicit Euler free fall). Throws
/// std::invalid_argument naming the model, the parameter and what was expected.
ReferenceTrajectory buildAnalyticReference(const pbd::Scene& scene, const ReferenceSpec& spec,
                                           const std::vector<double>& times,
                                           double integrationStep);

/// The analytic models known, with a one-line description each.
std::vector<std::pair<std::string, std::string>> analyticReferenceModels();

}  // namespace pbdval
