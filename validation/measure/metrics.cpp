// computeMetrics: one code path for every engine (docs/metrics.md).
#include "validation/measure/metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "pbd/collision/collision_shape.h"
#include "pbd/collision/mesh_distance.h"
#include "pbd/model/mesh.h"
#include "validation/io/trajectory.h"
#include "validation/measure/deformation.h"
#include "validation/measure/joint_error.h"
#include "validation/measure/mechanics.h"
#include "validation/measure/numerics.h"

namespace pbdval {

namespace metric {
std::string motorTrackingMax(const std::string& quantity) {
  return "motor_tracking_" + quantity + "_max";
}

std::vector<Declared> declared() {
  std::vector<Declared> all = {{kEnergyDriftMax, "1 (of E_ref)"},
                               {kEnergyDriftFinal, "1 (of E_ref)"},
                               {kEnergyDriftRate, "1/s"},
                               {"energy_scale", "J"},
                               {kMomentumLinearDriftMax, "1 (of its scale)"},
                               {"momentum_linear_scale", "kg m/s"},
                               {kMomentumAngularDriftMax, "1 (of its scale)"},
                               {"momentum_angular_scale", "kg m^2/s"},
                               {kJointErrorLinearMax, "m"},
                               {kJointErrorLinearRms, "m"},
                               {kJointErrorAngularMax, "rad"},
                               {kJointErrorAngularRms, "rad"},
                               {kPenetrationMax, "m"},
                               {kPenetrationMean, "m"},
                               {kTrajectoryErrorMax, "m"},
                               {kTrajectoryErrorRms, "m"},
                               {kRotationErrorMax, "rad"},
                               {kParticleStretchMax, "1 (strain)"},
                               {kParticleStretchRms, "1 (strain)"},
                               {kTetVolumeErrorMax, "1 (of the rest volume)"},
                               {kSolidVolumeErrorMax, "1 (of the rest volume)"},
                               {kParticlePenetrationMax, "m"},
                               {kSolidPenetrationMax, "m"},
                               {kFluidEscapeMax, "m"},
                               {kParticleTrajectoryErrorMax, "m"},
                               {kParticleTrajectoryErrorRms, "m"},
                               {kStaticDisplacement, "m"},
                               {kStaticDisplacementError, "1 (of the expected displacement)"}};
  // Each motor quantity in its own unit (JointErrorSummary::trackingQuantity).
  for (const auto& [quantity, unit] : {std::pair<const char*, const char*>{"angle", "rad"},
                                       {"angular_velocity", "rad/s"},
                                       {"position", "m"},
                                       {"velocity", "m/s"}})
    all.push_back({motorTrackingMax(quantity), unit});
  all.push_back({"wall_time_s", "s"});
  all.push_back({"steps", "1 (steps)"});
  all.push_back({"real_time_factor", "1 (simulated / wall time)"});
  return all;
}

std::vector<std::string> names() {
  std::vector<std::string> all;
  for (const Declared& d : declared())
    all.push_back(d.name);
  return all;
}
}  // namespace metric

namespace {

constexpr double kNoValue = std::numeric_limits<double>::quiet_NaN();

double timeSlack(double time) {
  return 1e-9 * std::max(1.0, std::abs(time));
}

std::vector<double> sampleTimes(const std::vector<State>& samples) {
  std::vector<double> times;
  times.reserve(samples.size());
  for (const State& s : samples)
    times.push_back(s.time);
  return times;
}

/// Max, sum of squares and count of a series of non-negative errors.
struct ErrorAccumulator {
  double max = 0;
  double sumOfSquares = 0;
  std::size_t count = 0;
  void add(double value) {
    max = std::max(max, std::abs(value));
    sumOfSquares += value * value;
    ++count;
  }
  double rms() const { return count > 0 ? std::sqrt(sumOfSquares / double(count)) : 0; }
};

void addEnergyMetrics(const MetricInputs& in, MetricSet& out) {
  std::string scaleNote;
  const double scale = energyScale(*in.scene, *in.spec, &scaleNote);
  std::vector<double> relative = relativeEnergyDrift(*in.scene, *in.samples, scale);
  const DriftSummary drift = summarizeDrift(sampleTimes(*in.samples), relative);
  if (in.series) in.series->energyDrift = std::move(relative);
  out.values["energy_scale"] = scale;
  out.values[metric::kEnergyDriftMax] = drift.max;
  out.values[metric::kEnergyDriftFinal] = drift.final;
  if (in.samples->size() >= 2) {
    out.values[metric::kEnergyDriftRate] = drift.rate;
  } else {
    out.notes.push_back("energy_drift_rate: needs at least two samples");
  }
  out.notes.push_back("energy: " + scaleNote);
  if (!in.spec->energyConserved)
    out.notes.push_back(
        "energy: not declared conserved (Validation.energyConserved); the drift includes the "
        "scene's physical dissipation and work");
  if ((!in.scene->triangleModels.empty() || !in.scene->tetModels.empty() ||
       !in.scene->lineModels.empty()) &&
      !in.samples->front().particles.empty()) {
    const ElasticEnergy elastic(*in.scene);
    if (elastic.defined())
      out.notes.push_back(
          "energy: includes the elastic energy of the XPBD particle constraints (½ k C²)");
    if (elastic.hasPbdConstraints())
      out.notes.push_back(
          "energy: PBD particle constraints (k a fraction per iteration) define no elastic "
          "energy; the drift includes what they store and dissipate");
    const bool segmentsRead = !in.samples->front().segments.empty();
    if (elastic.hasXpbdRods())
      out.notes.push_back(
          segmentsRead
              ? "energy: includes the XPBD Cosserat rods' elastic energy (stretch-shear "
                "½ ℓ Σ k_i (d_i·C)², bend-twist (2/ℓ̄) Σ K_i C_i²)"
              : "energy: the XPBD Cosserat rods' elastic energy is not included (it needs the "
                "segment orientations, which the read-back state does not hold)");
    if (!in.scene->lineModels.empty())
      out.notes.push_back(
          segmentsRead
              ? "energy: includes the rod segments' rotational kinetic energy ½ |ω|²/(4 w_q)"
              : "energy: the rod segments' rotational kinetic energy (½ |ω|²/(4 w_q), >= 0) is "
                "not included (the read-back state holds no segment orientations)");
  }
}

/// Stretch of the models' edges and volume change of their tets over the samples.
void addDeformationMetrics(const MetricInputs& in, MetricSet& out) {
  const pbd::Scene& scene = *in.scene;
  if (scene.triangleModels.empty() && scene.tetModels.empty() && scene.lineModels.empty()) return;
  if (in.samples->front().particles.empty()) {
    out.notes.push_back(
        "particle_stretch_max: the engine reads back no particles: no deformation metrics");
    return;
  }
  const RestShape rest(scene);
  if (rest.empty()) return;
  RestShape::Measures worst;
  double sumOfSquares = 0;
  std::size_t count = 0;
  for (const State& s : *in.samples) {
    const RestShape::Measures m = rest.measure(s);
    worst.stretchMax = std::max(worst.stretchMax, m.stretchMax);
    worst.tetVolumeErrorMax = std::max(worst.tetVolumeErrorMax, m.tetVolumeErrorMax);
    worst.solidVolumeErrorMax = std::max(worst.solidVolumeErrorMax, m.solidVolumeErrorMax);
    sumOfSquares += m.stretchSumOfSquares;
    count += m.edges;
  }
  if (count > 0) {
    out.values[metric::kParticleStretchMax] = worst.stretchMax;
    out.values[metric::kParticleStretchRms] = std::sqrt(sumOfSquares / double(count));
  }
  if (rest.hasTets()) {
    out.values[metric::kTetVolumeErrorMax] = worst.tetVolumeErrorMax;
    out.values[metric::kSolidVolumeErrorMax] = worst.solidVolumeErrorMax;
  }
}

/// The deepest particle inside a rigid body's collision shape: max over samples, particles and
/// bodies with a collisionObjectType of −φ(x) (φ the body's SDF in its scene frame at the
/// sample's pose, the same analytic shape or grid the PBD library collides with), 0 when none
/// is inside. Measured against the surface, not the contact tolerance shell.
void addParticlePenetrationMetrics(const MetricInputs& in, MetricSet& out) {
  const pbd::Scene& scene = *in.scene;
  if (scene.triangleModels.empty() && scene.tetModels.empty()) return;
  std::vector<std::pair<std::size_t, pbd::CollisionShape>> shapes;
  for (std::size_t b = 0; b < scene.rigidBodies.size(); ++b)
    if (scene.rigidBodies[b].collision.type != pbd::CollisionObjectType::None)
      shapes.emplace_back(b, pbd::makeCollisionShape(scene.rigidBodies[b]));
  if (shapes.empty()) return;
  if (in.samples->front().particles.empty()) {
    out.notes.push_back("particle_penetration_max: the engine reads back no particles");
    return;
  }
  double deepest = 0;
  for (const State& s : *in.samples)
    for (const auto& [body, shape] : shapes) {
      const pbd::RigidBodyDesc& desc = scene.rigidBodies[body];
      const Quaternion rotation = s.bodies[body].rotation.normalized();
      const Vector3 origin = s.bodies[body].position - rotation * desc.massProperties.centerOfMass;
      const Quaternion inverse = rotation.conjugate();
      for (const ParticleState& p : s.particles)
        deepest = std::max(
            deepest, -double(shape.distance((inverse * (p.position - origin)).cast<pbd::Real>())));
    }
  out.values[metric::kParticlePenetrationMax] = deepest;
}

/// The deepest particle of a tet model inside another tet model: max over samples and ordered
/// pairs (A, B) of models of the distance from a particle of A that lies inside a tet of B
/// (barycentric coordinates all ≥ 0) to B's current boundary surface (the faces of exactly one
/// tet), 0 when none is inside. Brute force over B's tets and faces.
void addSolidPenetrationMetrics(const MetricInputs& in, MetricSet& out) {
  const pbd::Scene& scene = *in.scene;
  if (scene.tetModels.size() < 2) return;
  if (in.samples->front().particles.empty()) {
    out.notes.push_back("solid_penetration_max: the engine reads back no particles");
    return;
  }
  // Boundary faces per model (pbd::boundaryFaces), global particle indices.
  std::vector<std::vector<std::array<int, 3>>> boundaries;
  for (const pbd::TetModelDesc& m : scene.tetModels) {
    std::vector<std::array<int, 3>> faces = pbd::boundaryFaces(m.mesh);
    for (std::array<int, 3>& face : faces)
      for (int& v : face)
        v += m.firstParticle;
    boundaries.push_back(std::move(faces));
  }
  double deepest = 0;
  for (const State& s : *in.samples) {
    pbd::TriangleMesh surface;
    for (const ParticleState& p : s.particles)
      surface.vertices.push_back(p.position.cast<pbd::Real>());
    for (std::size_t b = 0; b < scene.tetModels.size(); ++b) {
      const pbd::TetModelDesc& tetSide = scene.tetModels[b];
      if (boundaries[b].empty()) continue;
      surface.triangles = boundaries[b];
      const pbd::MeshDistance boundary(surface);
      for (std::size_t a = 0; a < scene.tetModels.size(); ++a) {
        if (a == b) continue;
        const pbd::TetModelDesc& vertexSide = scene.tetModels[a];
        for (std::size_t i = 0; i < vertexSide.mesh.vertices.size(); ++i) {
          const pbd::Vector3& x = surface.vertices[std::size_t(vertexSide.firstParticle) + i];
          for (const auto& t : tetSide.mesh.tetrahedra) {
            const auto at = [&](std::size_t j) {
              return surface.vertices[std::size_t(t[j] + tetSide.firstParticle)];
            };
            pbd::Matrix3 edges;
            edges << at(1) - at(0), at(2) - at(0), at(3) - at(0);
            if (edges.determinant() == 0) continue;
            const pbd::Vector3 w = edges.inverse() * (x - at(0));
            if (!(w.minCoeff() >= 0 && w.sum() <= 1)) continue;
            pbd::Vector3 closest;
            deepest = std::max(deepest, double(boundary.closestPoint(x, closest)));
            break;
          }
        }
      }
    }
  }
  out.values[metric::kSolidPenetrationMax] = deepest;
}

/// The farthest any fluid particle gets outside its model's container, over the samples (0
/// when all stay inside): max_k max_i max_axis (min − x_i, x_i − max), clamped at 0.
void addFluidMetrics(const MetricInputs& in, MetricSet& out) {
  const pbd::Scene& scene = *in.scene;
  bool contained = false;
  for (const pbd::FluidModelDesc& model : scene.fluidModels)
    contained = contained || model.container.has_value();
  if (!contained) return;
  if (in.samples->front().particles.empty()) {
    out.notes.push_back("fluid_escape_max: the engine reads back no particles");
    return;
  }
  double escape = 0;
  for (const State& s : *in.samples)
    for (const pbd::FluidModelDesc& model : scene.fluidModels) {
      if (!model.container) continue;
      for (int i = 0; i < model.particleCount; ++i) {
        const Vector3& x = s.particles[std::size_t(model.firstParticle + i)].position;
        const Vector3 outside = (model.container->min - x).cwiseMax(x - model.container->max);
        escape = std::max(escape, double(outside.maxCoeff()));
      }
    }
  out.values[metric::kFluidEscapeMax] = escape;
}

/// The case's static displacement (Validation.staticDisplacement): the mean over the samples at
/// t ≥ from and over its particles of (x − x₀)·d, and its relative error against `expected`.
void addStaticDisplacementMetrics(const MetricInputs& in, MetricSet& out) {
  if (!in.spec->staticDisplacement) return;
  const StaticDisplacementSpec& d = *in.spec->staticDisplacement;
  if (in.samples->front().particles.empty()) {
    out.notes.push_back("static_displacement: the engine reads back no particles");
    return;
  }
  double sum = 0;
  long count = 0;
  for (const State& s : *in.samples) {
    if (s.time < d.from) continue;
    for (int i : d.particles) {
      const auto index = std::size_t(i);
      sum += double(
          (s.particles[index].position - in.scene->particles[index].position).dot(d.direction));
      ++count;
    }
  }
  if (count == 0) {
    out.notes.push_back("static_displacement: no sample at or after t = " + formatNumber(d.from) +
                        " s");
    return;
  }
  const double mean = sum / double(count);
  out.values[metric::kStaticDisplacement] = mean;
  out.values[metric::kStaticDisplacementError] = std::abs(mean - d.expected) / std::abs(d.expected);
}

/// max_k ‖Q(t_k) − Q(t_0)‖ / scale for a vector quantity Q of each sample.
template <typename Quantity>
double maxVectorDrift(const std::vector<State>& samples, double scale, Quantity quantity) {
  const Vector3 start = quantity(samples.front());
  double drift = 0;
  for (const State& s : samples)
    drift = std::max(drift, double((quantity(s) - start).norm()));
  return drift / scale;
}

void addMomentumMetrics(const MetricInputs& in, MetricSet& out) {
  const pbd::Scene& scene = *in.scene;
  const CaseSpec& spec = *in.spec;
  if (!spec.linearMomentumConserved)
    out.notes.push_back("momentum_linear_drift_max: linear momentum not declared conserved");
  if (!spec.angularMomentumConserved)
    out.notes.push_back("momentum_angular_drift_max: angular momentum not declared conserved");
  if (!spec.linearMomentumConserved && !spec.angularMomentumConserved) return;
  const MomentumScales scales = momentumScales(scene, energyScale(scene, spec));
  if (spec.linearMomentumConserved) {
    if (scales.linear > 0) {
      out.values["momentum_linear_scale"] = scales.linear;
      out.values[metric::kMomentumLinearDriftMax] = maxVectorDrift(
          *in.samples, scales.linear, [&](const State& s) { return momentaOf(scene, s).linear; });
    } else {
      out.notes.push_back("momentum_linear_drift_max: no moving mass (scale 0)");
    }
  }
  if (spec.angularMomentumConserved) {
    if (scales.angular > 0) {
      out.values["momentum_angular_scale"] = scales.angular;
      out.values[metric::kMomentumAngularDriftMax] = maxVectorDrift(
          *in.samples, scales.angular, [&](const State& s) { return momentaOf(scene, s).angular; });
    } else {
      out.notes.push_back("momentum_angular_drift_max: no moving mass (scale 0)");
    }
  }
}

/// Errors of the joints of one type over all samples.
struct TypeAccumulator {
  ErrorAccumulator linear, angular, tracking;
  int joints = 0;
  bool hasAngular = false;
  MotorQuantity motor = MotorQuantity::None;
  bool recordSeries = false;
  /// Per sample, the largest error over the type's joints (recordSeries only).
  std::vector<double> linearSeries, angularSeries, trackingSeries;
};

/// series[k] = max(series[k], value), sizing the series (NaN: no value yet) on first use.
void raiseTo(std::vector<double>& series, std::size_t samples, std::size_t k, double value) {
  if (series.empty()) series.assign(samples, kNoValue);
  series[k] = std::isnan(series[k]) ? value : std::max(series[k], value);
}

void measureJointOverRun(const JointGeometry& joint, const std::vector<State>& samples,
                         TypeAccumulator& acc) {
  const std::size_t n = samples.size();
  for (std::size_t k = 0; k < n; ++k) {
    const JointMeasurement m = measureJoint(joint, samples[k]);
    acc.linear.add(m.linear);
    if (acc.recordSeries) raiseTo(acc.linearSeries, n, k, m.linear);
    if (m.angular) {
      acc.angular.add(*m.angular);
      if (acc.recordSeries) raiseTo(acc.angularSeries, n, k, *m.angular);
    }
    // The motor acts from the first step on: its set point at t_0 is not yet tracked.
    if (m.tracking && k > 0) {
      acc.tracking.add(*m.tracking);
      if (acc.recordSeries) raiseTo(acc.trackingSeries, n, k, std::abs(*m.tracking));
    }
  }
}

JointErrorSummary summarize(const TypeAccumulator& acc) {
  JointErrorSummary s;
  s.joints = acc.joints;
  s.linearMax = acc.linear.max;
  s.linearRms = acc.linear.rms();
  s.hasAngular = acc.hasAngular;
  s.angularMax = acc.angular.max;
  s.angularRms = acc.angular.rms();
  s.trackingQuantity = motorQuantityName(acc.motor);
  s.trackingMax = acc.tracking.max;
  s.trackingRms = acc.tracking.rms();
  return s;
}

void addJointMetrics(const MetricInputs& in, MetricSet& out) {
  const pbd::Scene& scene = *in.scene;
  const bool statesHaveParticles = !in.samples->front().particles.empty();
  std::map<std::string, TypeAccumulator> byType;
  for (const pbd::JointDesc& joint : scene.joints) {
    if (!isConstraint(joint.type)) continue;
    if (joint.type == pbd::JointType::RigidBodyParticleBall && !statesHaveParticles) {
      out.notes.push_back("joint error: " + joint.jsonPath +
                          " skipped: the engine's states hold no particles");
      continue;
    }
    TypeAccumulator& acc = byType[pbd::jointTypeName(joint.type)];
    acc.recordSeries = in.series != nullptr;
    ++acc.joints;
    acc.hasAngular = hasAngularError(joint.type);
    acc.motor = motorQuantity(joint.type);
    measureJointOverRun(captureJointGeometry(scene, joint), *in.samples, acc);
  }
  if (byType.empty()) {
    out.notes.push_back("joint error: the scene has no constrained joints (springs are excluded)");
    return;
  }
  ErrorAccumulator linear, angular;
  std::map<std::string, double> trackingMax;
  bool anyAngular = false;
  for (const auto& [name, acc] : byType) {
    out.jointErrorByType[name] = summarize(acc);
    if (in.series) {
      in.series->jointErrorLinear[name] = acc.linearSeries;
      if (acc.hasAngular && !acc.angularSeries.empty())
        in.series->jointErrorAngular[name] = acc.angularSeries;
      if (acc.motor != MotorQuantity::None && !acc.trackingSeries.empty()) {
        std::vector<double>& tracking = in.series->motorTracking[motorQuantityName(acc.motor)];
        for (std::size_t k = 0; k < acc.trackingSeries.size(); ++k)
          if (!std::isnan(acc.trackingSeries[k]))
            raiseTo(tracking, acc.trackingSeries.size(), k, acc.trackingSeries[k]);
      }
    }
    linear.max = std::max(linear.max, acc.linear.max);
    linear.sumOfSquares += acc.linear.sumOfSquares;
    linear.count += acc.linear.count;
    if (acc.hasAngular) {
      anyAngular = true;
      angular.max = std::max(angular.max, acc.angular.max);
      angular.sumOfSquares += acc.angular.sumOfSquares;
      angular.count += acc.angular.count;
    }
    if (acc.motor != MotorQuantity::None && acc.tracking.count > 0) {
      double& value = trackingMax[motorQuantityName(acc.motor)];
      value = std::max(value, acc.tracking.max);
    }
  }
  out.values[metric::kJointErrorLinearMax] = linear.max;
  out.values[metric::kJointErrorLinearRms] = linear.rms();
  if (anyAngular) {
    out.values[metric::kJointErrorAngularMax] = angular.max;
    out.values[metric::kJointErrorAngularRms] = angular.rms();
  } else {
    out.notes.push_back("joint_error_angular_max: no joint with an angular error");
  }
  for (const auto& [quantity, value] : trackingMax)
    out.values[metric::motorTrackingMax(quantity)] = value;
}

void addPenetrationMetrics(const MetricInputs& in, MetricSet& out) {
  if (!in.penetration) {
    out.notes.push_back("penetration: no distance oracle was given");
    return;
  }
  double max = 0, sum = 0;
  std::size_t contacts = 0;
  if (in.series) in.series->penetration.assign(in.samples->size(), 0.0);
  for (std::size_t k = 0; k < in.samples->size(); ++k)
    for (const double depth : in.penetration((*in.samples)[k])) {
      if (!(depth > 0)) continue;  // touching or separated pairs are not active contacts
      max = std::max(max, depth);
      sum += depth;
      ++contacts;
      if (in.series) in.series->penetration[k] = std::max(in.series->penetration[k], depth);
    }
  out.values[metric::kPenetrationMax] = max;
  out.values[metric::kPenetrationMean] = contacts > 0 ? sum / double(contacts) : 0;
  if (contacts == 0) out.notes.push_back("penetration: no overlapping pair in any sample");
}

void addTrajectoryMetrics(const MetricInputs& in, MetricSet& out) {
  if (!in.reference) {
    out.notes.push_back("trajectory: no reference");
    return;
  }
  const ReferenceTrajectory& reference = *in.reference;
  if (reference.samples.empty()) {
    out.notes.push_back("trajectory: the reference (" + reference.description + ") has no samples");
    return;
  }
  const TrajectoryErrors e = trajectoryErrors(*in.samples, reference, in.series);
  if (e.particlesCompared > 0) {
    out.values[metric::kParticleTrajectoryErrorMax] = e.particlePositionMax;
    out.values[metric::kParticleTrajectoryErrorRms] = e.particlePositionRms;
    if (e.bodiesCompared == 0) return;  // a scene of particles only: no body metrics
  } else if (!in.samples->front().particles.empty()) {
    out.notes.push_back("particle_trajectory_error: the reference (" + reference.description +
                        ") holds no particles of the run");
  }
  out.values[metric::kTrajectoryErrorMax] = e.positionMax;
  out.values[metric::kTrajectoryErrorRms] = e.positionRms;
  if (reference.hasRotation) {
    out.values[metric::kRotationErrorMax] = e.rotationMax;
  } else {
    out.notes.push_back("rotation_error_max: the reference (" + reference.description +
                        ") gives no orientations");
  }
  if (e.samplesCompared < in.samples->size()) {
    std::ostringstream note;
    note << "trajectory: the reference (" << reference.description << ") covers only the first "
         << e.samplesCompared << " of " << in.samples->size() << " samples";
    out.notes.push_back(note.str());
  }
}

}  // namespace

DriftSummary summarizeDrift(const std::vector<double>& times, const std::vector<double>& values) {
  DriftSummary d;
  if (values.empty()) return d;
  for (const double v : values)
    d.max = std::max(d.max, std::abs(v));
  d.final = values.back();
  d.rate = leastSquaresSlope(times, values);
  return d;
}

std::vector<double> relativeEnergyDrift(const pbd::Scene& scene, const std::vector<State>& samples,
                                        double energyScale) {
  std::vector<double> drift;
  if (samples.empty()) return drift;
  const ElasticEnergy elastic(scene);
  const double start = energyOf(scene, samples.front(), elastic).total();
  drift.reserve(samples.size());
  for (const State& s : samples)
    drift.push_back((energyOf(scene, s, elastic).total() - start) / energyScale);
  return drift;
}

TrajectoryErrors trajectoryErrors(const std::vector<State>& samples,
                                  const ReferenceTrajectory& reference, MetricSeries* series) {
  TrajectoryErrors e;
  const std::size_t count = std::min(samples.size(), reference.samples.size());
  ErrorAccumulator position, particlePosition;
  if (series) {
    series->trajectoryError.assign(samples.size(), kNoValue);
    if (reference.hasRotation) series->rotationError.assign(samples.size(), kNoValue);
  }
  for (std::size_t k = 0; k < count; ++k) {
    const State& run = samples[k];
    const State& ref = reference.samples[k];
    if (std::abs(run.time - ref.time) > timeSlack(run.time)) {
      std::ostringstream message;
      message << "trajectory metrics: sample " << k << " is at t = " << run.time
              << " s, the reference's at " << ref.time << " s (resample the reference)";
      throw std::invalid_argument(message.str());
    }
    const std::size_t bodies = std::min(run.bodies.size(), ref.bodies.size());
    if (reference.bodies.size() > bodies &&
        std::find(reference.bodies.begin() + std::ptrdiff_t(bodies), reference.bodies.end(),
                  true) != reference.bodies.end())
      throw std::invalid_argument(
          "trajectory metrics: the reference's body mask names bodies "
          "the states do not hold");
    std::size_t compared = 0;
    for (std::size_t i = 0; i < bodies; ++i) {
      if (!reference.bodies.empty() && (i >= reference.bodies.size() || !reference.bodies[i]))
        continue;
      ++compared;
      const double distance = (run.bodies[i].position - ref.bodies[i].position).norm();
      position.add(distance);
      if (series) raiseTo(series->trajectoryError, samples.size(), k, distance);
      if (reference.hasRotation) {
        const double angle = geodesicAngle(run.bodies[i].rotation, ref.bodies[i].rotation);
        e.rotationMax = std::max(e.rotationMax, angle);
        if (series) raiseTo(series->rotationError, samples.size(), k, angle);
      }
    }
    e.bodiesCompared = compared;
    if (!run.particles.empty() && run.particles.size() == ref.particles.size()) {
      for (std::size_t i = 0; i < run.particles.size(); ++i)
        particlePosition.add((run.particles[i].position - ref.particles[i].position).norm());
      e.particlesCompared = run.particles.size();
    }
  }
  e.samplesCompared = count;
  e.positionMax = position.max;
  e.positionRms = position.rms();
  e.particlePositionMax = particlePosition.max;
  e.particlePositionRms = particlePosition.rms();
  return e;
}

ReferenceTrajectory resampleReference(const ReferenceTrajectory& reference,
                                      const std::vector<double>& times) {
  ReferenceTrajectory out;
  out.description = reference.description + ", resampled";
  out.samples = resampleStates(reference.samples, times);
  out.bodies = reference.bodies;
  out.hasRotation = reference.hasRotation;
  return out;
}

MetricSet computeMetrics(const MetricInputs& inputs) {
  if (!inputs.scene || !inputs.spec || !inputs.samples)
    throw std::invalid_argument("computeMetrics: scene, spec and samples are required");
  MetricSet out;
  if (inputs.samples->empty()) {
    out.notes.push_back("no samples: no metrics");
    return out;
  }
  for (const State& s : *inputs.samples)
    checkStateMatchesScene(*inputs.scene, s);
  if (inputs.series) {
    *inputs.series = MetricSeries{};
    inputs.series->times = sampleTimes(*inputs.samples);
  }
  addEnergyMetrics(inputs, out);
  addMomentumMetrics(inputs, out);
  addJointMetrics(inputs, out);
  addPenetrationMetrics(inputs, out);
  addTrajectoryMetrics(inputs, out);
  addDeformationMetrics(inputs, out);
  addParticlePenetrationMetrics(inputs, out);
  addSolidPenetrationMetrics(inputs, out);
  addFluidMetrics(inputs, out);
  addStaticDisplacementMetrics(inputs, out);
  return out;
}

}  // namespace pbdval
