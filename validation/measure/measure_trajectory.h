// The metrics of a trajectory given from outside (pbdval.measure in Python, the `measure` fuzz
// target): the samples are checked as a run's would be, the reference is chosen, then the one
// measurement path (run_execution.h measureSamples) computes the metrics.
#pragma once

#include <string>
#include <vector>

#include "validation/measure/metrics.h"
#include "validation/run/case_spec.h"

namespace pbdval {

/// Which reference a given trajectory is compared with.
enum class ReferenceChoice {
  None,         ///< no trajectory metrics
  CaseDefault,  ///< the case's analytic reference when its Validation block declares one, else none
  Given,        ///< the given reference trajectory, resampled at the samples' times
};

struct MeasuredTrajectory {
  MetricSet metrics;
  std::string referenceDescription;  ///< empty without a reference
};

/// The metrics of `samples` of `scene` (whose case is `spec`). `given` is used (and must be
/// non-null) with ReferenceChoice::Given; `integrationStep` (s, > 0) is the step the analytic
/// reference integrates at (0: the scene's step); `contactMargin` (m) is subtracted from
/// penetration depths. Throws std::invalid_argument naming the argument ("times",
/// "reference.times", "contact_margin", "integration_step") for no samples, a time that is
/// not finite or is before its predecessor, a sample that does not hold the scene's bodies, or
/// a margin beyond ±kMaxContactMargin or a non-finite step (a reference's quaternion that is
/// not a unit one too);
/// EngineDivergence naming the first sample with a finite quaternion that is not a unit one
/// (|1 − norm| > 1e-3: a zero quaternion is no rotation), or a non-finite or blown-up sample
/// (measureSamples).
MeasuredTrajectory measureTrajectory(const pbd::Scene& scene, const CaseSpec& spec,
                                     const std::vector<State>& samples, ReferenceChoice choice,
                                     const ReferenceTrajectory* given, double contactMargin,
                                     double integrationStep, MetricSeries* series = nullptr);

}  // namespace pbdval
