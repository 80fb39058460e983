// Boundary checks and sanity bounds of a run's states (validation/measure/sanity.h; derivations in
// docs/metrics.md §Boundary checks and §Sanity bounds).
#include "validation/measure/sanity.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "validation/measure/mechanics.h"

namespace pbdval {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

/// |‖q‖ − 1| above this is not a unit quaternion: every engine normalises its orientations at
/// least once per step, which leaves ~1e-15; an unnormalised first-order update drifts by
/// (|ω| h)²/8 per step, 1e-6 after a few hundred steps of a slowly spinning body.
constexpr double kUnitQuaternionTolerance = 1e-6;

/// Relative precision of positions and orientations as read back: 17 significant digits in
/// memory, CSV and NPY alike (the protocol writes repr()); 1e-12 leaves three orders of
/// magnitude for the engine's own round-off in its frame conversions.
constexpr double kReadBackPrecision = 1e-12;

/// The floor of the sanity bounds, relative: a millionth of the scale, three orders of
/// magnitude above the round-off of E and of the momenta summed over a run (N ≤ 1e6 samples ×
/// 1e-16) and below every metric the gate compares.
constexpr double kSanityFloor = 1e-6;

/// Four significant digits: what a reason sentence needs (the values are in results.json).
std::string fmt(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", value);
  return text;
}

std::string fmt(const Vector3& v) {
  return "(" + fmt(v.x()) + ", " + fmt(v.y()) + ", " + fmt(v.z()) + ")";
}

std::string bodyName(const pbd::Scene& scene, std::size_t index) {
  const pbd::RigidBodyDesc& body = scene.rigidBodies[index];
  return "body " + std::to_string(body.id) + " (" +
         (body.jsonPath.empty() ? "RigidBodies[" + std::to_string(index) + "]" : body.jsonPath) +
         ")";
}

/// The distance from `p` to the segment [a, b].
double distanceToSegment(const Vector3& p, const Vector3& a, const Vector3& b) {
  const Vector3 ab = b - a;
  const double length2 = ab.squaredNorm();
  const double s = length2 > 0 ? std::clamp((p - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
  return (p - (a + s * ab)).norm();
}

/// The rotation vector ω Δ of the world-frame rotation from `from` to `to` (to = exp(ωΔ) from),
/// the short way round.
Vector3 rotationVector(const Quaternion& from, const Quaternion& to) {
  Quaternion d = to.normalized() * from.normalized().conjugate();
  if (d.w() < 0) d.coeffs() = -d.coeffs();
  const double s = d.vec().norm();
  if (s == 0) return Vector3::Zero();
  return (2 * std::atan2(s, d.w()) / s) * d.vec();
}

double angleBetween(const Quaternion& a, const Quaternion& b) {
  return rotationVector(a, b).norm();
}

/// ¼ of the largest second difference of a series around an interval [a, b] (p before a, n
/// after b, each null at an end): twice the Δ²/8 · max|ẍ| by which a smooth velocity's chord
/// misses its mean over the interval, with ẍ estimated from the samples themselves (an impact
/// shows as a large second difference).
double curvatureSlack(const Vector3* p, const Vector3& a, const Vector3& b, const Vector3* n) {
  double largest = 0;
  if (p) largest = std::max(largest, (b - 2 * a + *p).norm());
  if (n) largest = std::max(largest, (*n - 2 * b + a).norm());
  return 0.25 * largest;
}

std::optional<CheckViolation> initialStateViolation(const pbd::Scene& scene, const State& first,
                                                    double tolerance, bool velocitiesProjected) {
  const State expected = initialState(scene);
  std::ostringstream message;
  for (std::size_t i = 0; i < expected.bodies.size() && i < first.bodies.size(); ++i) {
    const BodyState& want = expected.bodies[i];
    const BodyState& got = first.bodies[i];
    const double dx = (got.position - want.position).norm();
    const double dq = angleBetween(want.rotation, got.rotation);
    const double dv = (got.velocity - want.velocity).norm();
    const double dw = (got.angularVelocity - want.angularVelocity).norm();
    const double boundX = tolerance * std::max(1.0, want.position.norm());
    const double boundV = tolerance * std::max(1.0, want.velocity.norm());
    const double boundW = tolerance * std::max(1.0, want.angularVelocity.norm());
    const char* what = nullptr;
    if (!(dx <= boundX)) {
      message << "centre of mass " << fmt(got.position) << " m, the scene's " << fmt(want.position)
              << " m (" << fmt(dx) << " m apart, bound " << fmt(boundX) << " m)";
      what = "position";
    } else if (!(dq <= tolerance)) {
      message << "orientation (w, x, y, z) = (" << fmt(got.rotation.w()) << ", "
              << fmt(got.rotation.x()) << ", " << fmt(got.rotation.y()) << ", "
              << fmt(got.rotation.z()) << "), the scene's (" << fmt(want.rotation.w()) << ", "
              << fmt(want.rotation.x()) << ", " << fmt(want.rotation.y()) << ", "
              << fmt(want.rotation.z()) << "): " << fmt(dq) << " rad apart, bound "
              << fmt(tolerance) << " rad";
      what = "orientation";
    } else if (velocitiesProjected) {
      continue;
    } else if (!(dv <= boundV)) {
      message << "velocity " << fmt(got.velocity) << " m/s, the scene's " << fmt(want.velocity)
              << " m/s (bound " << fmt(boundV) << " m/s)";
      what = "velocity";
    } else if (!(dw <= boundW)) {
      message << "angular velocity " << fmt(got.angularVelocity) << " rad/s, the scene's "
              << fmt(want.angularVelocity) << " rad/s (bound " << fmt(boundW) << " rad/s)";
      what = "angular velocity";
    }
    if (what)
      return CheckViolation{"initial_state",
                            "initial_state: the first sample's " + std::string(what) + " of " +
                                bodyName(scene, i) +
                                " is not the scene's initial state: " + message.str()};
  }
  return std::nullopt;
}

std::optional<CheckViolation> unitQuaternionViolation(const pbd::Scene& scene, const State& s,
                                                      std::size_t k) {
  for (std::size_t i = 0; i < s.bodies.size(); ++i) {
    const double norm = s.bodies[i].rotation.norm();
    if (!(std::abs(norm - 1) <= kUnitQuaternionTolerance))
      return CheckViolation{"unit_quaternion", "unit_quaternion: the orientation of " +
                                                   bodyName(scene, i) + " at sample " +
                                                   std::to_string(k) + " (t = " + fmt(s.time) +
                                                   " s) has norm " + fmt(norm) + ", not 1 (bound " +
                                                   fmt(kUnitQuaternionTolerance) + ")"};
  }
  for (std::size_t i = 0; i < s.segments.size(); ++i) {
    const double norm = s.segments[i].rotation.norm();
    if (!(std::abs(norm - 1) <= kUnitQuaternionTolerance))
      return CheckViolation{"unit_quaternion", "unit_quaternion: the orientation of rod segment " +
                                                   std::to_string(i) + " at sample " +
                                                   std::to_string(k) + " (t = " + fmt(s.time) +
                                                   " s) has norm " + fmt(norm) + ", not 1"};
  }
  return std::nullopt;
}

/// The allowance for what happens between two samples that the samples cannot show: ¼ of the
/// largest second difference (twice the Δ²/8 · |v̈| by which a smooth velocity's chord misses
/// its mean), ½ |v_{k+1} − v_k| (the spread of the velocity inside the interval when it does
/// not change monotonically: a velocity pass, a split-impulse push, joint stabilisation) and
/// kStepJitter of the speed.
constexpr double kStepJitter = 0.25;

double intervalAllowance(const Vector3* before, const Vector3& a, const Vector3& b,
                         const Vector3* after, const Vector3& finiteDifference) {
  const double speed = std::max({a.norm(), b.norm(), finiteDifference.norm()});
  return curvatureSlack(before, a, b, after) + 0.5 * (b - a).norm() + kStepJitter * speed;
}

/// A body holds still over an interval when it moves less than this (m, rad): round-off of
/// positions near 1–100 m, far below any motion a step produces.
constexpr double kStill = 1e-9;
/// A body that holds still may report this fraction of ‖g‖h (the speed gravity adds in one
/// step) beyond the method's declared rest allowance: iterative contact solvers leave residual
/// velocities far below it (at most 3.4e-5 m/s over the case library at h = 5 ms, ‖g‖h =
/// 0.049 m/s), a velocity that does not describe the motion is not (0.4 ‖g‖h in the pbd.xpbd
/// defect of a box resting with contactTolerance 0). 1e-6 m/s without gravity.
constexpr double kRestSpeedFraction = 0.1;
constexpr double kRestSpeedFloor = 1e-6;

/// The reported (angular) velocities against the finite differences of the positions
/// (orientations) over the interval from sample k (`a`) to k+1 (`b`); `before` and `after` are
/// the neighbouring samples or null (docs/metrics.md §Boundary checks).
std::vector<IntervalMismatch> velocityMismatches(const pbd::Scene& scene, const State* before,
                                                 const State& a, const State& b, const State* after,
                                                 std::size_t k, double restAllowance,
                                                 const std::vector<double>& sizes,
                                                 const std::vector<bool>& skip) {
  std::vector<IntervalMismatch> mismatches;
  const double dt = b.time - a.time;
  if (!(dt > 0)) return mismatches;
  // What contacts and joints may do to positions inside one step without a velocity (a
  // projection, a split-impulse push): at most the speed gravity adds in a step.
  const double stepCorrection =
      double(scene.simulation.gravitation.norm()) * double(scene.simulation.timeStepSize);
  for (std::size_t i = 0; i < scene.rigidBodies.size(); ++i) {
    if (!scene.rigidBodies[i].isDynamic || skip[i]) continue;
    const BodyState& ba = a.bodies[i];
    const BodyState& bb = b.bodies[i];
    const BodyState* bp = before ? &before->bodies[i] : nullptr;
    const BodyState* bn = after ? &after->bodies[i] : nullptr;
    // Linear: (x_{k+1} − x_k)/Δ must lie on the chord [v_k, v_{k+1}] up to the allowance.
    const Vector3 fd = (bb.position - ba.position) / dt;
    // A body that holds still reports rest, up to the method's declared velocity pass.
    // Per world axis: a coordinate that holds still cannot carry a velocity (a box whose
    // height holds to 1e-12 m while it reports v_y = −0.02 m/s).
    // The rotation from a to b, once: its angle here, its rate below.
    const Vector3 turn = rotationVector(ba.rotation, bb.rotation);
    const double turned = turn.norm();
    const double residual = std::max(kRestSpeedFloor, kRestSpeedFraction * stepCorrection);
    const double restLinear = restAllowance + residual;
    const double restAngular =
        (sizes[i] > 0 ? (restAllowance + residual) / sizes[i] : 0) + kRestSpeedFloor;
    bool stillAxisMoving = false;
    for (int axis = 0; axis < 3; ++axis)
      stillAxisMoving |=
          std::abs(bb.position[axis] - ba.position[axis]) <= kStill &&
          std::min(std::abs(ba.velocity[axis]), std::abs(bb.velocity[axis])) > restLinear;
    const double spinning = std::min(ba.angularVelocity.norm(), bb.angularVelocity.norm());
    if (stillAxisMoving || (turned <= kStill && spinning > restAngular)) {
      std::ostringstream m;
      m << "velocity_at_rest: " << bodyName(scene, i) << " from sample " << k
        << " (t = " << fmt(a.time) << " s) on holds still "
        << (stillAxisMoving ? "along an axis" : "in turn") << " (between samples " << k << " and "
        << k + 1 << " it moves " << fmt(bb.position - ba.position) << " m and turns " << fmt(turned)
        << " rad) yet reports v = " << fmt(bb.velocity)
        << " m/s and ω = " << fmt(bb.angularVelocity)
        << " rad/s, more than the method's rest allowance " << fmt(restLinear) << " m/s, "
        << fmt(restAngular) << " rad/s";
      mismatches.push_back({i, false, "velocity_at_rest", m.str()});
      continue;
    }
    const double deviation = distanceToSegment(fd, ba.velocity, bb.velocity);
    const double bound = intervalAllowance(bp ? &bp->velocity : nullptr, ba.velocity, bb.velocity,
                                           bn ? &bn->velocity : nullptr, fd) +
                         stepCorrection + restAllowance +
                         kReadBackPrecision * (ba.position.norm() + bb.position.norm() + 1.0) / dt;
    if (!(deviation <= bound)) {
      std::ostringstream m;
      m << "velocity_consistency: " << bodyName(scene, i) << " from sample " << k
        << " (t = " << fmt(a.time) << " s) on: between samples " << k << " and " << k + 1
        << " its centre of mass moves at " << fmt(fd)
        << " m/s (finite difference), its reported velocities are " << fmt(ba.velocity) << " and "
        << fmt(bb.velocity) << " m/s: " << fmt(deviation) << " m/s off, more than the bound "
        << fmt(bound) << " m/s from the sample interval, the accelerations and the speed";
      mismatches.push_back({i, false, "velocity_consistency", m.str()});
    }
    // Angular: the rotation vector of q_{k+1} q_k⁻¹ over Δ must lie on the chord
    // [ω_k, ω_{k+1}] up to the allowance and the Magnus term Δ/12 |(ω_{k+1} − ω_k) × ω_k|.
    // Skipped where the samples cannot resolve the rotation (|ω| Δ > π/2: aliasing).
    const Vector3& wa = ba.angularVelocity;
    const Vector3& wb = bb.angularVelocity;
    const double spin = std::max(wa.norm(), wb.norm());
    if (spin * dt > M_PI / 2) continue;
    const Vector3 fdw = turn / dt;
    const double deviationW = distanceToSegment(fdw, wa, wb);
    const double boundW = intervalAllowance(bp ? &bp->angularVelocity : nullptr, wa, wb,
                                            bn ? &bn->angularVelocity : nullptr, fdw) +
                          (sizes[i] > 0 ? (stepCorrection + restAllowance) / sizes[i] : 0) +
                          dt / 12 * (wb - wa).cross(wa).norm() + 4 * kReadBackPrecision / dt;
    if (!(deviationW <= boundW)) {
      std::ostringstream m;
      m << "angular_velocity_consistency: " << bodyName(scene, i) << " from sample " << k
        << " (t = " << fmt(a.time) << " s) on: between samples " << k << " and " << k + 1
        << " its orientation turns at " << fmt(fdw)
        << " rad/s (world frame, finite difference), its reported angular velocities are "
        << fmt(wa) << " and " << fmt(wb) << " rad/s: " << fmt(deviationW)
        << " rad/s off, more than the bound " << fmt(boundW)
        << " rad/s from the sample interval, the accelerations and the speed";
      mismatches.push_back({i, true, "angular_velocity_consistency", m.str()});
    }
  }
  return mismatches;
}

bool isMotor(pbd::JointType type) {
  return type == pbd::JointType::TargetAngleMotorHinge ||
         type == pbd::JointType::TargetVelocityMotorHinge ||
         type == pbd::JointType::TargetPositionMotorSlider ||
         type == pbd::JointType::TargetVelocityMotorSlider;
}

/// A body's size: √(tr I / 2m), the root-mean-square distance of its mass from its centre
/// (half the diagonal over √3 for a box, 0.77 r for a sphere).
double bodySize(const pbd::RigidBodyDesc& body) {
  const double mass = double(body.massProperties.mass);
  const double trace = double(body.massProperties.principalInertia.sum());
  return mass > 0 && trace > 0 ? std::sqrt(trace / (2 * mass)) : 0.0;
}

double bodyMass(const pbd::Scene& scene, int index) {
  if (index < 0 || std::size_t(index) >= scene.rigidBodies.size()) return 0;
  const pbd::RigidBodyDesc& body = scene.rigidBodies[std::size_t(index)];
  return body.isDynamic ? double(body.massProperties.mass) : 0.0;
}

double smallestPrincipalInertia(const pbd::Scene& scene, int index) {
  if (index < 0 || std::size_t(index) >= scene.rigidBodies.size()) return 0;
  const pbd::RigidBodyDesc& body = scene.rigidBodies[std::size_t(index)];
  return body.isDynamic ? double(body.massProperties.principalInertia.minCoeff()) : 0.0;
}

}  // namespace

double SanityBounds::relativeBound(double duration) const {
  const double truncation = std::isfinite(timeScale) && timeScale > 0
                                ? stepSize * duration / (timeScale * timeScale)
                                : 0.0;
  return truncation + kSanityFloor;
}

SanityBounds sanityBounds(const pbd::Scene& scene) {
  SanityBounds b;
  b.stepSize = double(scene.simulation.timeStepSize);
  // Passive: no source of work, and the measured E holds every energy the scene stores.
  for (const pbd::JointDesc& joint : scene.joints)
    if (isMotor(joint.type) && b.notPassive.empty())
      b.notPassive = joint.jsonPath + " is a motor (it does work)";
  if (b.notPassive.empty() && !scene.particles.empty())
    b.notPassive =
        "the scene has particle models (their constraints' time scales are not derived here, "
        "and PBD constraints define no energy)";
  if (b.notPassive.empty() && (!scene.lineModels.empty() || !scene.fluidModels.empty()))
    b.notPassive = "the scene has rods or fluids";
  for (std::size_t i = 0; i < scene.rigidBodies.size() && b.notPassive.empty(); ++i)
    if (scene.rigidBodies[i].restitution > 1)
      b.notPassive = scene.rigidBodies[i].jsonPath + ".restitution > 1 (contacts create energy)";
  for (const pbd::ContactPairDesc& pair : scene.contactPairs)
    if (pair.restitution > 1 && b.notPassive.empty())
      b.notPassive = "a contact pair's restitution > 1 (contacts create energy)";
  b.passive = b.notPassive.empty();

  // Isolated: nothing outside the dynamic bodies pushes them (gravity is subtracted exactly).
  bool dynamicCollider = false;
  for (const pbd::RigidBodyDesc& body : scene.rigidBodies)
    dynamicCollider |= body.isDynamic && body.collision.type != pbd::CollisionObjectType::None;
  for (const pbd::RigidBodyDesc& body : scene.rigidBodies)
    if (!body.isDynamic && body.collision.type != pbd::CollisionObjectType::None &&
        dynamicCollider && b.notIsolated.empty())
      b.notIsolated = body.jsonPath + " is static and can be touched";
  for (const pbd::JointDesc& joint : scene.joints)
    if (b.notIsolated.empty() &&
        (bodyMass(scene, joint.body1) == 0 || bodyMass(scene, joint.body2) == 0))
      b.notIsolated = joint.jsonPath + " holds a body to a static body or a particle";
  if (b.notIsolated.empty() &&
      (!scene.particles.empty() || !scene.lineModels.empty() || !scene.fluidModels.empty()))
    b.notIsolated = "the scene has particle models, rods or fluids";
  if (b.notIsolated.empty() && !b.passive) b.notIsolated = b.notPassive;
  b.isolated = b.notIsolated.empty();

  // τ: the fastest of the scene's time scales.
  b.timeScale = kInfinity;
  auto consider = [&](double tau, const std::string& source) {
    if (tau > 0 && tau < b.timeScale) {
      b.timeScale = tau;
      b.timeScaleSource = source;
    }
  };
  const double gravity = double(scene.simulation.gravitation.norm());
  for (std::size_t i = 0; i < scene.rigidBodies.size(); ++i) {
    const pbd::RigidBodyDesc& body = scene.rigidBodies[i];
    if (!body.isDynamic) continue;
    const double size = bodySize(body);
    if (gravity > 0 && size > 0)
      consider(std::sqrt(size / gravity),
               "√(ℓ/|g|), ℓ = " + fmt(size) + " m the size of " + body.jsonPath);
    const double spin = double(body.angularVelocity.norm());
    if (spin > 0) consider(1 / spin, "1/|ω₀| of " + body.jsonPath);
  }
  for (const pbd::JointDesc& joint : scene.joints) {
    const double m1 = bodyMass(scene, joint.body1), m2 = bodyMass(scene, joint.body2);
    const double mass = m1 > 0 && m2 > 0 ? std::min(m1, m2) : std::max(m1, m2);
    if ((joint.type == pbd::JointType::RigidBodySpring || joint.type == pbd::JointType::Damper) &&
        joint.stiffness > 0 && mass > 0)
      consider(std::sqrt(mass / double(joint.stiffness)), "√(m/k) of " + joint.jsonPath);
    if (joint.type == pbd::JointType::StiffRod) {
      // Bending: k = E I_area / L with I_area = π r⁴/4, against the segments' inertia.
      const pbd::StiffRodJointParams& rod = joint.stiffRod;
      const double r = double(rod.averageRadius), length = double(rod.averageSegmentLength);
      const double inertia1 = smallestPrincipalInertia(scene, joint.body1);
      const double inertia2 = smallestPrincipalInertia(scene, joint.body2);
      const double inertia = inertia1 > 0 && inertia2 > 0 ? std::min(inertia1, inertia2)
                                                          : std::max(inertia1, inertia2);
      const double stiffness = std::max(double(rod.youngsModulus), double(rod.torsionModulus)) *
                               M_PI * r * r * r * r / 4 / std::max(length, 1e-12);
      if (inertia > 0 && stiffness > 0)
        consider(std::sqrt(inertia / stiffness), "√(I/k) of " + joint.jsonPath);
    }
  }
  return b;
}

BoundaryChecker::BoundaryChecker(const pbd::Scene& scene, double initialTolerance,
                                 double restVelocityAllowance, bool velocitiesProjected)
    : scene_(scene),
      initialTolerance_(initialTolerance),
      velocitiesProjected_(velocitiesProjected),
      streaks_(2 * scene.rigidBodies.size(), 0),
      streakStart_(2 * scene.rigidBodies.size()),
      restVelocityAllowance_(restVelocityAllowance) {
  window_.reserve(4);
  for (const pbd::RigidBodyDesc& body : scene.rigidBodies)
    sizes_.push_back(bodySize(body));
  skipVelocity_.assign(scene.rigidBodies.size(), false);
}

BoundaryChecker::BoundaryChecker(const pbd::Scene& scene, const RunFacts& facts)
    : BoundaryChecker(scene, facts.initialStateTolerance, facts.restVelocityAllowance,
                      facts.initialVelocitiesProjected) {
  for (int body : facts.velocityDrivenBodies)
    if (body >= 0 && std::size_t(body) < skipVelocity_.size())
      skipVelocity_[std::size_t(body)] = true;
}

void BoundaryChecker::checkInterval(std::size_t first) {
  if (violation_ || first + 1 >= window_.size()) return;
  const State* before = first > 0 ? &window_[first - 1] : nullptr;
  const State* after = first + 2 < window_.size() ? &window_[first + 2] : nullptr;
  const std::size_t k = samplesSeen_ - window_.size() + first;
  nextInterval_ = k + 1;
  // A mismatch counts when it persists over kPersistentIntervals intervals in a row: an
  // impact, a velocity pass at a contact event or a split-impulse push lasts one or two; a
  // protocol mistake or a defect holds at every sample.
  std::vector<char>& failing = failing_;
  failing.assign(streaks_.size(), 0);
  for (IntervalMismatch& m :
       velocityMismatches(scene_, before, window_[first], window_[first + 1], after, k,
                          restVelocityAllowance_, sizes_, skipVelocity_)) {
    const std::size_t slot = 2 * m.body + (m.angular ? 1 : 0);
    failing[slot] = 1;
    if (streaks_[slot]++ == 0) streakStart_[slot] = std::move(m);
    if (streaks_[slot] >= kPersistentIntervals && !violation_)
      violation_ = CheckViolation{streakStart_[slot].check,
                                  streakStart_[slot].message + ", and again in each of the next " +
                                      std::to_string(kPersistentIntervals - 1) +
                                      " intervals (a persistent mismatch, not a transient)",
                                  /*aboutVelocities=*/true};
  }
  for (std::size_t slot = 0; slot < streaks_.size(); ++slot)
    if (!failing[slot]) streaks_[slot] = 0;
}

const std::optional<CheckViolation>& BoundaryChecker::add(const State& sample) {
  if (violation_) return violation_;
  checkStateMatchesScene(scene_, sample);
  if (samplesSeen_ == 0)
    violation_ = initialStateViolation(scene_, sample, initialTolerance_, velocitiesProjected_);
  if (!violation_) violation_ = unitQuaternionViolation(scene_, sample, samplesSeen_);
  // Only the bodies are checked: keep them, not the particles (a fluid's 10⁵ per step). The
  // oldest sample's slot is reused for the newest (a rotation swaps the vectors): no allocation
  // per sample once the window is full.
  if (window_.size() == 4)
    std::rotate(window_.begin(), window_.begin() + 1, window_.end());
  else
    window_.emplace_back();
  window_.back().time = sample.time;
  window_.back().bodies.assign(sample.bodies.begin(), sample.bodies.end());
  ++samplesSeen_;
  // The interval [j−2, j−1] has both neighbours once sample j (the newest) is here.
  if (window_.size() >= 3) checkInterval(window_.size() - 3);
  return violation_;
}

const std::optional<CheckViolation>& BoundaryChecker::finish() {
  // The intervals not yet checked: the last one (and, with two samples, the only one).
  while (!violation_ && window_.size() >= 2 && nextInterval_ + 1 < samplesSeen_)
    checkInterval(nextInterval_ - (samplesSeen_ - window_.size()));
  return violation_;
}

std::optional<CheckViolation> boundaryViolation(const pbd::Scene& scene,
                                                const std::vector<State>& samples,
                                                double initialTolerance,
                                                double restVelocityAllowance) {
  BoundaryChecker checker(scene, initialTolerance, restVelocityAllowance);
  for (const State& s : samples)
    if (checker.add(s)) return checker.violation();
  return checker.finish();
}

std::optional<CheckViolation> sanityViolation(const pbd::Scene& scene, const CaseSpec& spec,
                                              const std::vector<State>& samples) {
  if (samples.size() < 2) return std::nullopt;
  const SanityBounds bounds = sanityBounds(scene);
  const double duration = samples.back().time - samples.front().time;
  const double relative = bounds.relativeBound(duration);
  std::ostringstream why;
  why << "h T/τ² + " << fmt(kSanityFloor) << " = " << fmt(relative)
      << " (h = " << fmt(bounds.stepSize) << " s, T = " << fmt(duration) << " s, τ = "
      << (std::isfinite(bounds.timeScale) ? fmt(bounds.timeScale) + " s: " + bounds.timeScaleSource
                                          : std::string("none: the scene has no time scale"))
      << ")";
  const double energyRef = energyScale(scene, spec);
  if (bounds.passive) {
    const double e0 = energyOf(scene, samples.front()).total();
    const double allowed = relative * energyRef;
    double worstGain = -kInfinity;
    std::size_t worstSample = 0;
    for (std::size_t k = 0; k < samples.size(); ++k) {
      const State& s = samples[k];
      const EnergyTerms terms = energyOf(scene, s);
      const double gain = terms.total() - e0;
      if (gain > worstGain) {
        worstGain = gain;
        worstSample = k;
      }
      // Speed: one body's translational kinetic energy cannot exceed what the scene makes
      // available, E(0) − V(t) plus the allowed gain (V(t) = E(t) − T(t), the potentials).
      const double available = e0 - (terms.total() - terms.kinetic()) + allowed;
      for (std::size_t i = 0; i < s.bodies.size(); ++i) {
        const pbd::RigidBodyDesc& body = scene.rigidBodies[i];
        if (!body.isDynamic) continue;
        const double mass = double(body.massProperties.mass);
        const double kinetic = 0.5 * mass * s.bodies[i].velocity.squaredNorm();
        if (kinetic > available) {
          std::ostringstream m;
          m << "speed: " << bodyName(scene, i) << " moves at " << fmt(s.bodies[i].velocity.norm())
            << " m/s at t = " << fmt(s.time) << " s (sample " << k
            << "); the energy the passive scene makes available, E(0) − V(t) + the allowed gain, "
            << "lets it reach at most " << fmt(std::sqrt(2 * std::max(available, 0.0) / mass))
            << " m/s (allowed gain " << why.str() << " × E_ref = " << fmt(energyRef) << " J)";
          return CheckViolation{"speed", m.str()};
        }
      }
    }
    if (worstGain > allowed) {
      std::ostringstream m;
      m << "energy_created: the passive scene's energy rose by " << fmt(worstGain / energyRef)
        << " E_ref (E_ref = " << fmt(energyRef) << " J) by t = " << fmt(samples[worstSample].time)
        << " s (sample " << worstSample << "); the first-order bound is " << why.str();
      return CheckViolation{"energy_created", m.str()};
    }
  }
  if (bounds.isolated) {
    const Momenta m0 = momentaOf(scene, samples.front());
    const MomentumScales scales = momentumScales(scene, energyRef);
    const Vector3 g = scene.simulation.gravitation.cast<double>();
    for (std::size_t k = 1; k < samples.size(); ++k) {
      const Momenta mk = momentaOf(scene, samples[k]);
      const double elapsed = samples[k].time - samples.front().time;
      const double linear =
          (mk.linear - m0.linear - m0.mass * g * elapsed).norm() / std::max(scales.linear, 1e-300);
      const double angular = (mk.angular - m0.angular).norm() / std::max(scales.angular, 1e-300);
      const char* check = linear > relative    ? "linear_momentum"
                          : angular > relative ? "angular_momentum"
                                               : nullptr;
      if (!check) continue;
      std::ostringstream m;
      m << check << ": the isolated scene's " << (linear > relative ? "linear" : "angular")
        << " momentum changed by " << fmt(linear > relative ? linear : angular)
        << " of its scale by t = " << fmt(samples[k].time) << " s (sample " << k
        << ", gravity's impulse M g t subtracted); the first-order bound is " << why.str();
      return CheckViolation{check, m.str()};
    }
  }
  return std::nullopt;
}

}  // namespace pbdval
