#include "validation/measure/measure_trajectory.h"

#include <cmath>
#include <optional>
#include <stdexcept>

#include "validation/io/trajectory.h"
#include "validation/measure/mechanics.h"
#include "validation/measure/references/reference.h"
#include "validation/run/run_execution.h"

namespace pbdval {
namespace {

/// At least one sample, finite non-decreasing times. The analytic references integrate from
/// t = 0 to each sample time in turn, so a NaN, an infinite or a decreasing time would make
/// them loop or read outside their tables; resampling needs ordered times too.
void checkSampleTimes(const std::vector<State>& samples, const std::string& name) {
  if (samples.empty())
    throw std::invalid_argument(name + ": expected at least one sample, got none");
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const double t = samples[k].time;
    if (!std::isfinite(t))
      throw std::invalid_argument(name + "[" + std::to_string(k) +
                                  "]: expected a finite time, got " + formatNumber(t));
    if (k > 0 && t < samples[k - 1].time)
      throw std::invalid_argument(name + "[" + std::to_string(k) + "]: " + formatNumber(t) +
                                  " s is before the previous sample's " +
                                  formatNumber(samples[k - 1].time) +
                                  " s: expected non-decreasing times");
  }
}

/// How far a body's quaternion norm may be from 1: every engine renormalises its orientations
/// each step (round-off ~1e-15) and the trajectory files keep every digit; a zero or scaled
/// quaternion (|1 − norm| of order 1) is no rotation, e.g. an angular velocity that overflowed.
constexpr double kUnitQuaternionTolerance = 1e-3;

/// The first finite quaternion of `samples` that is not a unit one, as "sample k: ...", or empty.
/// (Non-finite ones are measureSamples' divergences.)
std::string nonUnitQuaternion(const std::vector<State>& samples) {
  for (std::size_t k = 0; k < samples.size(); ++k)
    for (const BodyState& b : samples[k].bodies) {
      const double norm = double(b.rotation.norm());
      if (std::isfinite(norm) && !(std::abs(norm - 1) <= kUnitQuaternionTolerance))
        return "sample " + std::to_string(k) + ": the rotation of body " + std::to_string(b.id) +
               " is not a unit quaternion (norm " + formatNumber(norm) + ")";
    }
  return "";
}

}  // namespace

MeasuredTrajectory measureTrajectory(const pbd::Scene& scene, const CaseSpec& spec,
                                     const std::vector<State>& samples, ReferenceChoice choice,
                                     const ReferenceTrajectory* given, double contactMargin,
                                     double integrationStep, MetricSeries* series) {
  checkSampleTimes(samples, "times");
  for (const State& s : samples)
    checkStateMatchesScene(scene, s);
  checkContactMargin(contactMargin);
  if (const std::string problem = nonUnitQuaternion(samples); !problem.empty())
    throw EngineDivergence(problem + "; a diverged trajectory is not measured");
  if (!std::isfinite(integrationStep) || integrationStep < 0)
    throw std::invalid_argument("integration_step: expected a positive number of seconds, got " +
                                formatNumber(integrationStep));
  std::optional<ReferenceTrajectory> reference;
  std::vector<double> times;
  times.reserve(samples.size());
  for (const State& s : samples)
    times.push_back(s.time);
  if (choice == ReferenceChoice::CaseDefault &&
      spec.reference.kind == ReferenceSpec::Kind::Analytic) {
    // (the reference depends on the scene and the times only: a diverged sample is named by
    // measureSamples below)
    reference = buildAnalyticReference(
        scene, spec.reference, times,
        integrationStep > 0 ? integrationStep : double(scene.simulation.timeStepSize));
  } else if (choice == ReferenceChoice::Given) {
    if (!given) throw std::invalid_argument("reference: none given");
    checkSampleTimes(given->samples, "reference.times");
    for (const State& s : given->samples)
      checkStateMatchesScene(scene, s);
    if (const std::string problem = nonUnitQuaternion(given->samples); !problem.empty())
      throw std::invalid_argument("reference: " + problem);
    reference = resampleReference(*given, times);
  }
  MeasuredTrajectory measured;
  measured.metrics = measureSamples(scene, spec, samples, reference ? &*reference : nullptr,
                                    contactMargin, series);
  measured.referenceDescription = reference ? reference->description : std::string();
  return measured;
}

}  // namespace pbdval
