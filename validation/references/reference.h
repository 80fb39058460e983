// Analytic references (docs/references.md): small documented models that give the exact (or
// high-accuracy) motion of a case's bodies, sampled at a run's sample times.
#pragma once

#include <vector>

#include "validation/metrics.h"

namespace pbdval {

/// Builds the analytic reference `spec.model` with `spec.parametersJson` for `scene`, sampled
/// at `times`. `integrationStep` is the run's effective integration step (for the discrete
/// closed forms, e.g. semi-implicit Euler free fall). Throws std::invalid_argument naming the
/// model, the parameter and what was expected.
ReferenceTrajectory buildAnalyticReference(const pbd::Scene& scene, const ReferenceSpec& spec,
                                           const std::vector<double>& times,
                                           double integrationStep);

/// The analytic models known, with a one-line description each.
std::vector<std::pair<std::string, std::string>> analyticReferenceModels();

}  // namespace pbdval
