// Metrics: computed once, here, for every engine alike, from the states read back and the
// Scene — never from an engine's own counters. Formulas: docs/metrics.md.
//
// Stable names (results.json, baselines and gates depend on them), declared in namespace
// metric below with their units (metric::declared(): the one list the units of the report and
// `pbdval sweep --metric` come from); when each is present: docs/metrics.md.
// The runner adds wall_time_s, steps, real_time_factor and, for PBD, state_hash.
//
// The building blocks (energy and momenta of a state: validation/measure/mechanics.h; per-joint
// error: validation/measure/joint_error.h; slope, geodesic angle, resampling:
// validation/measure/numerics.h) are public for the runner and the reports.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "adapters/engine.h"
#include "validation/run/case_spec.h"

namespace pbdval {

struct JointErrorSummary {
  double linearMax = 0;   ///< m
  double linearRms = 0;   ///< m, over samples and joints of the type
  double angularMax = 0;  ///< rad
  int joints = 0;
  // Extensions (schema-compatible additions):
  double angularRms = 0;    ///< rad, over samples and joints of the type
  bool hasAngular = false;  ///< the type has an angular error (hinge, universal, slider kinds)
  /// Motors: max and RMS of |tracking error| over samples after the first, in the unit of
  /// `trackingQuantity` ("angle" rad, "angular_velocity" rad/s, "position" m, "velocity" m/s).
  std::string trackingQuantity;  ///< empty: not a motor
  double trackingMax = 0;
  double trackingRms = 0;
};

/// The stable metric names.
namespace metric {
inline constexpr const char* kEnergyDriftMax = "energy_drift_max";
inline constexpr const char* kEnergyDriftFinal = "energy_drift_final";
inline constexpr const char* kEnergyDriftRate = "energy_drift_rate";
inline constexpr const char* kMomentumLinearDriftMax = "momentum_linear_drift_max";
inline constexpr const char* kMomentumAngularDriftMax = "momentum_angular_drift_max";
inline constexpr const char* kJointErrorLinearMax = "joint_error_linear_max";
inline constexpr const char* kJointErrorLinearRms = "joint_error_linear_rms";
inline constexpr const char* kJointErrorAngularMax = "joint_error_angular_max";
inline constexpr const char* kJointErrorAngularRms = "joint_error_angular_rms";
inline constexpr const char* kPenetrationMax = "penetration_max";
inline constexpr const char* kPenetrationMean = "penetration_mean";
inline constexpr const char* kTrajectoryErrorMax = "trajectory_error_max";
inline constexpr const char* kTrajectoryErrorRms = "trajectory_error_rms";
inline constexpr const char* kRotationErrorMax = "rotation_error_max";
inline constexpr const char* kParticleStretchMax = "particle_stretch_max";
inline constexpr const char* kParticleStretchRms = "particle_stretch_rms";
inline constexpr const char* kTetVolumeErrorMax = "tet_volume_error_max";
inline constexpr const char* kSolidVolumeErrorMax = "solid_volume_error_max";
inline constexpr const char* kParticlePenetrationMax = "particle_penetration_max";
inline constexpr const char* kSolidPenetrationMax = "solid_penetration_max";
inline constexpr const char* kFluidEscapeMax = "fluid_escape_max";
inline constexpr const char* kParticleTrajectoryErrorMax = "particle_trajectory_error_max";
inline constexpr const char* kParticleTrajectoryErrorRms = "particle_trajectory_error_rms";
inline constexpr const char* kStaticDisplacement = "static_displacement";
inline constexpr const char* kStaticDisplacementError = "static_displacement_error";
/// "motor_tracking_<quantity>_max", quantity "angle", "angular_velocity", "position", "velocity".
std::string motorTrackingMax(const std::string& quantity);
/// A metric name with its unit: "m", "rad", "1/s", or "1 (of E_ref)" for a dimensionless ratio
/// (what it is a ratio of in parentheses).
struct Declared {
  std::string name;
  std::string unit;
};
/// Every name a run's metrics may hold, with its unit, in the order of docs/metrics.md: the
/// constants above, the motor-tracking names, the scales (energy_scale, momentum_*_scale) and
/// what the runner adds (wall_time_s, steps, real_time_factor).
std::vector<Declared> declared();
/// The names of declared(): what `pbdval sweep --metric` accepts.
std::vector<std::string> names();
}  // namespace metric

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

/// The per-sample values behind the summaries (the report's curves), one entry per sample: at
/// each sample the largest value over the joints of a type, the overlapping pairs or the
/// compared bodies. NaN where a sample has no value (a motor's first sample, whose set point is
/// not yet tracked; samples beyond the reference). A series is empty when its metric is absent.
struct MetricSeries {
  std::vector<double> times;
  std::vector<double> energyDrift;                               ///< (E − E₀)/E_ref
  std::map<std::string, std::vector<double>> jointErrorLinear;   ///< joint type → m
  std::map<std::string, std::vector<double>> jointErrorAngular;  ///< joint type → rad
  std::map<std::string, std::vector<double>> motorTracking;      ///< quantity → its unit
  std::vector<double> penetration;                               ///< m (0: no overlap)
  std::vector<double> trajectoryError;                           ///< m
  std::vector<double> rotationError;                             ///< rad
};

struct MetricInputs {
  const pbd::Scene* scene = nullptr;
  const CaseSpec* spec = nullptr;
  const std::vector<State>* samples = nullptr;
  const ReferenceTrajectory* reference = nullptr;  ///< null: no trajectory metrics
  PenetrationQuery penetration;                    ///< empty: no penetration metrics
  MetricSeries* series = nullptr;                  ///< also record the series (null: don't)
};

/// All metrics of a run. Throws std::invalid_argument when scene, spec or samples is null, or
/// a sample does not hold the Scene's bodies (mechanics.h checkStateMatchesScene).
MetricSet computeMetrics(const MetricInputs& inputs);

// ---- Building blocks of computeMetrics, for the runner and the reports ----

/// max |y|, the final y (signed) and the least-squares slope of y against t.
struct DriftSummary {
  double max = 0;
  double final = 0;
  double rate = 0;
};
DriftSummary summarizeDrift(const std::vector<double>& times, const std::vector<double>& values);

/// ΔE(t_k)/E_ref = (E(t_k) − E(t_0))/E_ref for every sample.
std::vector<double> relativeEnergyDrift(const pbd::Scene& scene, const std::vector<State>& samples,
                                        double energyScale);

struct TrajectoryErrors {
  double positionMax = 0;  ///< max ‖x − x_ref‖ over masked bodies and compared samples, m
  double positionRms = 0;  ///< RMS of ‖x − x_ref‖ over the same, m
  double rotationMax = 0;  ///< max geodesic angle, rad (0 when the reference has no rotations)
  std::size_t samplesCompared = 0;
  std::size_t bodiesCompared = 0;
  /// Particles, when the run and the reference both hold the same ones (cloth, solids; an
  /// engine reference): max and RMS of ‖x − x_ref‖ over particles and compared samples, m.
  double particlePositionMax = 0;
  double particlePositionRms = 0;
  std::size_t particlesCompared = 0;
};
/// Compares `samples` with `reference` sample by sample (the first min(n, n_ref) samples).
/// Throws std::invalid_argument when a compared pair's times differ by more than
/// 1e-9·max(1, |t|) s (resample the reference first: resampleReference) or when the mask
/// names more bodies than the states hold.
/// With `series`, also its trajectoryError and rotationError per sample.
TrajectoryErrors trajectoryErrors(const std::vector<State>& samples,
                                  const ReferenceTrajectory& reference,
                                  MetricSeries* series = nullptr);

/// `reference` resampled at `times` (numerics.h resampleStates: linear positions and
/// velocities, slerp rotations), for fine-step and cross-engine references whose samples fall
/// at other times. The mask and hasRotation are kept; the description says it was resampled.
ReferenceTrajectory resampleReference(const ReferenceTrajectory& reference,
                                      const std::vector<double>& times);

}  // namespace pbdval
