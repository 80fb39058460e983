// Running one request in this process (the body of every isolated child process).
#pragma once

#include "adapters/registry.h"
#include "validation/measure/metrics.h"
#include "validation/run/case_spec.h"
#include "validation/run/run_record.h"

namespace pbdval {

/// Runs one request in this process: loads the case, runs the engine from `registry`, builds the
/// reference, computes the metrics, writes the trajectory. Never throws: every failure becomes
/// the record's status and reason.
RunRecord executeRun(const RunRequest& request, const EngineRegistry& registry);

/// The engine whose run is the reference of `request` — the engine of `--reference METHOD`, or,
/// with the case's reference (an empty referenceMode), the engine of its Validation.reference of
/// type "engine" — so that the scheduler starts that engine's server in the run's worker too;
/// "" when the reference is no other engine's run. Reads the case file for the latter; throws
/// (std::invalid_argument, pbd::SceneError) on what executeRun would report as the run's error.
std::string referenceEngineOf(const RunRequest& request, const EngineRegistry& registry);

/// The largest contact margin, in magnitude, that the penetration metrics take (m). Engines
/// declare millimetres to centimetres; the FCL oracle's broad phase inflates every box by a
/// negative margin, and a margin of -1.8e308 overflowed its AABB tree (a segfault, found by the
/// `measure` fuzz target). 1 m is far above any engine's and far below an overflow.
inline constexpr double kMaxContactMargin = 1.0;

/// Throws std::invalid_argument ("contact_margin: ...") unless |margin| ≤ kMaxContactMargin.
void checkContactMargin(double margin);

/// The metrics of a run's `samples` (the one measurement path: executeRun and the Python
/// binding both call it): computeMetrics with the FCL oracle's penetration depths (engine
/// margin `contactMargin` subtracted) and `reference` (null: no trajectory metrics; it must be
/// sampled at the samples' times: resampleReference). Notes say what could not be measured.
/// Throws EngineDivergence naming the first sample that holds NaN or Inf (time included) or a
/// blow-up (divergenceReason): a diverged trajectory has no metrics, as in the runner; and
/// std::invalid_argument for a margin beyond kMaxContactMargin (checkContactMargin).
// With `series`, also the per-sample values behind the metrics (the report's curves).
MetricSet measureSamples(const pbd::Scene& scene, const CaseSpec& spec,
                         const std::vector<State>& samples, const ReferenceTrajectory* reference,
                         double contactMargin, MetricSeries* series = nullptr);

}  // namespace pbdval
