// Metrics: computed once, here, for every engine alike, from the states read back and the
// Scene — never from an engine's own counters. Formulas: docs/metrics.md.
//
// Stable names (results.json, baselines and gates depend on them):
//   energy_drift_max, energy_drift_final, energy_drift_rate          (relative to E_ref; rate /s)
//   momentum_linear_drift_max, momentum_angular_drift_max             (only when declared
//   conserved) joint_error_linear_max, joint_error_linear_rms (m), joint_error_angular_max (rad)
//     and per joint type under joint_error_by_type
//   penetration_max, penetration_mean (m)                             (FCL oracle, margins
//   subtracted) trajectory_error_max, trajectory_error_rms (m), rotation_error_max (rad)   (against
//   a reference)
// The runner adds wall_time_s, steps, real_time_factor and, for PBD, state_hash.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "adapters/engine.h"
#include "validation/case_spec.h"

namespace pbdval {

struct JointErrorSummary {
  double linearMax = 0;   ///< m
  double linearRms = 0;   ///< m, over samples and joints of the type
  double angularMax = 0;  ///< rad
  int joints = 0;
};

struct MetricSet {
  std::map<std::string, double> values;  ///< name → value; absent when not applicable
  std::map<std::string, JointErrorSummary> jointErrorByType;  ///< jointTypeName → summary
  std::vector<std::string> notes;  ///< why a metric is absent, approximations used
};

/// Depths (m, > 0) of the overlapping body pairs in a state, engine margins already subtracted.
using PenetrationQuery = std::function<std::vector<double>(const State&)>;

/// A reference trajectory: states at the same times as the run's samples, with the bodies it
/// describes (empty mask: all bodies) and whether it gives orientations.
struct ReferenceTrajectory {
  std::string description;  ///< "analytic pendulum", "pbd/pbd at h/16", ...
  std::vector<State> samples;
  std::vector<bool> bodies;
  bool hasRotation = true;
};

struct MetricInputs {
  const pbd::Scene* scene = nullptr;
  const CaseSpec* spec = nullptr;
  const std::vector<State>* samples = nullptr;
  const ReferenceTrajectory* reference = nullptr;  ///< null: no trajectory metrics
  PenetrationQuery penetration;                    ///< empty: no penetration metrics
};

MetricSet computeMetrics(const MetricInputs& inputs);

}  // namespace pbdval
