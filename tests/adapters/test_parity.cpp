// The parity suite: identical scenes in every registered engine, each held to closed forms
// and to its profile (parity_profiles.h). Expected values come from closed forms (discrete
// free fall, elliptic pendulum period, e², g(sin θ − μ cos θ)), conservation (energy), or the
// run itself repeated (determinism) — never from an engine's output.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "adapters/engine.h"
#include "common/scene_fixtures.h"
#include "engines/selftest_engine.h"
#include "parity_profiles.h"
#include "validation/run/simulation.h"

namespace pbdval::test {
namespace {

using pbd::JointType;
using pbd::Matrix3;
using pbd::Scene;

constexpr double kG = 9.81;

struct EngineRun {
  std::vector<State> samples;
  RunOutcome outcome;
};

EngineRun run(const ParityProfile& profile, const Scene& scene, double duration) {
  EngineRun r;
  const std::unique_ptr<Engine> engine = testRegistry().make(profile.engine);
  const Method method = testRegistry().resolve(profile.method);
  RunCallbacks callbacks;
  callbacks.onSample = [&](const State& s) { r.samples.push_back(s); };
  r.outcome = runSimulation(*engine, scene, method, {duration, 0}, callbacks);
  return r;
}

Scene baseScene(double stepSize, const Vector3& gravity = Vector3(0, -kG, 0)) {
  Scene s;
  s.simulation.timeStepSize = Real(stepSize);
  s.simulation.subSteps = 5;
  s.simulation.gravitation = gravity;
  return s;
}

/// World inertia of a body's read-back state from the Scene's principal inertia.
Matrix3 worldInertia(const pbd::RigidBodyDesc& body, const BodyState& state) {
  const Matrix3 principal =
      (state.rotation * body.massProperties.principalRotation).toRotationMatrix();
  return principal * body.massProperties.principalInertia.asDiagonal() * principal.transpose();
}

class Parity : public ::testing::TestWithParam<ParityProfile> {};

// --- Free fall and projectile -----------------------------------------------------------------
// With n integration steps of h/n per scene step, semi-implicit Euler gives after k = n·steps
// integration steps x_k = x₀ + k h_s v₀ + h_s² g k(k+1)/2 exactly (up to round-off); an exact
// integrator (n = 0) gives the continuous parabola.
TEST_P(Parity, FreeFallAndProjectileMatchTheDiscreteClosedForm) {
  const ParityProfile& p = GetParam();
  Scene s = baseScene(0.005);
  s.rigidBodies.push_back(pbd::test::boxBody(1, Vector3(0.2, 0.2, 0.2), Vector3(0, 10, 0), 500));
  auto projectile = pbd::test::boxBody(2, Vector3(0.1, 0.2, 0.3), Vector3(50, 10, 0), 500);
  projectile.velocity = Vector3(3, 8, -1);
  projectile.angularVelocity = Vector3(0, 2, 1);  // spin does not affect the centre of mass
  s.rigidBodies.push_back(projectile);
  const EngineRun r = run(p, s, 1.0);
  ASSERT_EQ(r.outcome.status, RunStatus::Ok) << r.outcome.reason;
  const Vector3 g = s.simulation.gravitation;
  const double h = s.simulation.timeStepSize;
  double worst = 0;
  for (const State& state : r.samples) {
    const double t = state.time;
    for (std::size_t b = 0; b < 2; ++b) {
      const Vector3 x0 = s.rigidBodies[b].initialCenterOfMass(), v0 = s.rigidBodies[b].velocity;
      Vector3 expected;
      if (p.integrationStepsPerStep > 0) {
        const double hs = h / p.integrationStepsPerStep;
        const double k = std::round(t / hs);
        expected = x0 + k * hs * v0 + hs * hs * g * k * (k + 1) / 2;
      } else {
        expected = x0 + t * v0 + 0.5 * t * t * g;
      }
      worst = std::max(worst, double((state.bodies[b].position - expected).norm()));
    }
  }
  // Round-off: ≤ k² · 4ε · |x| with k ≤ 1000 integration steps and |x| ≤ 60 m (see
  // tests/pbd/test_integration.cpp for the derivation): 5e-8 m.
  EXPECT_LE(worst, 1000.0 * 1000.0 * 4 * 2.2e-16 * 60) << p.engine << "/" << p.method;
}

// --- Torque-free spinning box ----------------------------------------------------------------
// Kinetic energy ½ωᵀIω is conserved by the exact dynamics; a numerical method may dissipate it
// but must not create it. Bound: KE ≤ (1 + energyGrowthBound) KE₀ over 20 s (MuJoCo's own test
// uses 1 %). Two bodies: a tumble about the intermediate axis and a fast spin about the major.
// A method flagged unstable on it (spinningBodies false: explicit gyroscopic forces) is held to
// the opposite: the analysis in its profile predicts growth, so the energy must leave the bound
// (or the engine stop the run as diverged). Should a later engine version fix it, this fails and
// the profile is corrected.
TEST_P(Parity, SpinningBoxEnergyDoesNotGrow) {
  const ParityProfile& p = GetParam();
  Scene s = baseScene(0.005, Vector3::Zero());
  const Real density = Real(1 / (0.1 * 0.2 * 0.3));  // 1 kg
  auto tumble = pbd::test::boxBody(1, Vector3(0.1, 0.2, 0.3), Vector3(0, 0, 0), density);
  tumble.angularVelocity = Vector3(0.05, 5, 0.05);
  auto spin = pbd::test::boxBody(2, Vector3(0.1, 0.2, 0.3), Vector3(5, 0, 0), density);
  spin.angularVelocity = Vector3(20, 0.05, 0.05);
  s.rigidBodies = {tumble, spin};
  const EngineRun r = run(p, s, 20.0);
  if (!p.spinningBodies && r.outcome.status == RunStatus::Diverged) {
    std::printf("  %s/%s spinning bodies: diverged as predicted (%s)\n", p.engine.c_str(),
                p.method.c_str(), r.outcome.reason.c_str());
    return;
  }
  ASSERT_EQ(r.outcome.status, RunStatus::Ok) << r.outcome.reason;
  double worstGrowth = 0;
  for (std::size_t b = 0; b < 2; ++b) {
    auto energy = [&](const BodyState& st) {
      return 0.5 * double(st.angularVelocity.dot(worldInertia(s.rigidBodies[b], st) *
                                                 st.angularVelocity));
    };
    const double e0 = energy(r.samples.front().bodies[b]);
    double maxRatio = 0, minRatio = 1e9;
    for (const State& st : r.samples) {
      if (!std::isfinite(energy(st.bodies[b]))) continue;
      maxRatio = std::max(maxRatio, energy(st.bodies[b]) / e0);
      minRatio = std::min(minRatio, energy(st.bodies[b]) / e0);
    }
    if (p.spinningBodies) {
      EXPECT_LE(maxRatio, 1 + p.energyGrowthBound) << p.engine << " body " << b;
    }
    worstGrowth = std::max(worstGrowth, maxRatio);
    std::printf("  %s/%s spinning body %zu: KE/KE0 in [%.6f, %.6f] over 20 s\n", p.engine.c_str(),
                p.method.c_str(), b, minRatio, maxRatio);
  }
  if (!p.spinningBodies) {
    EXPECT_GT(worstGrowth, 1 + p.energyGrowthBound)
        << p.engine << "/" << p.method << " was expected to be unstable here: " << p.notes;
  }
}

// --- Determinism -------------------------------------------------------------------------------
TEST_P(Parity, SameSceneTwiceGivesBitwiseIdenticalTrajectories) {
  const ParityProfile& p = GetParam();
  Scene s = baseScene(0.005);
  s.rigidBodies.push_back(
      pbd::test::boxBody(0, Vector3(0.2, 0.2, 0.2), Vector3(0, 2, 0), 1, false));
  pbd::test::appendChain(s, 5, JointType::Ball);
  const EngineRun a = run(p, s, 2.0), b = run(p, s, 2.0);
  ASSERT_EQ(a.outcome.status, RunStatus::Ok) << a.outcome.reason;
  ASSERT_EQ(a.samples.size(), b.samples.size());
  for (std::size_t k = 0; k < a.samples.size(); ++k)
    for (std::size_t i = 0; i < a.samples[k].bodies.size(); ++i) {
      const BodyState &x = a.samples[k].bodies[i], &y = b.samples[k].bodies[i];
      ASSERT_TRUE(x.position == y.position && x.rotation.coeffs() == y.rotation.coeffs() &&
                  x.velocity == y.velocity && x.angularVelocity == y.angularVelocity)
          << p.engine << ": first difference at t = " << a.samples[k].time << ", body " << i;
    }
}

// --- Pendulum on each joint type ---------------------------------------------------------------
// A 1 kg box (0.1 m) swinging in the xy-plane from θ₀ = 20° about a pivot 1 m above its centre.
// Exact period of a physical pendulum: T = 4 K(sin(θ₀/2)) √(I_p/(m g d)), I_p the moment of
// inertia about the pivot (the distance joint attaches at the centre of mass, so the box's own
// rotation is free and I_p = m d²).
double ellipticK(double k) {  // complete elliptic integral of the first kind, by the AGM
  double a = 1, b = std::sqrt(1 - k * k);
  for (int i = 0; i < 30; ++i) {
    const double m = (a + b) / 2;
    b = std::sqrt(a * b);
    a = m;
  }
  return M_PI / (2 * a);
}

Scene pendulumScene(JointType type, double theta0, double length) {
  Scene s = baseScene(0.005);
  const Vector3 pivot(0, 2, 0);
  s.rigidBodies.push_back(pbd::test::boxBody(0, Vector3(0.1, 0.1, 0.1), pivot, 1, false));
  const Vector3 bob = pivot + length * Vector3(std::sin(theta0), -std::cos(theta0), 0);
  s.rigidBodies.push_back(pbd::test::boxBody(1, Vector3(0.1, 0.1, 0.1), bob, 1000));
  pbd::JointDesc j = pbd::test::makeJointDesc(type, 0, 1);
  j.position = pivot;
  j.axis = Vector3::UnitZ();
  j.axis1 = Vector3::UnitZ();
  j.axis2 = Vector3::UnitX();
  j.position1 = pivot;
  j.position2 = bob;
  s.joints.push_back(j);
  return s;
}

class PendulumParity : public ::testing::TestWithParam<std::tuple<ParityProfile, JointType>> {};

TEST_P(PendulumParity, PeriodAndJointErrorWithinStepBounds) {
  const auto& [p, type] = GetParam();
  if (!p.pendulumJoints.count(type))
    GTEST_SKIP() << p.engine << " has no " << pbd::jointTypeName(type) << " pendulum";
  const double theta0 = 20 * M_PI / 180, length = 1;
  const Scene s = pendulumScene(type, theta0, length);
  const EngineRun r = run(p, s, 8.0);
  ASSERT_EQ(r.outcome.status, RunStatus::Ok) << r.outcome.reason;

  const auto& bob = s.rigidBodies[1];
  const double m = bob.massProperties.mass;
  const double inertia = type == JointType::Distance
                             ? m * length * length
                             : bob.massProperties.principalInertia.z() + m * length * length;
  const double omega0 = std::sqrt(m * kG * length / inertia);
  const double expected = 4 * ellipticK(std::sin(theta0 / 2)) / omega0;

  // Period from upward zero crossings of the swing angle (linear interpolation between samples).
  const Vector3 pivot(0, 2, 0);
  std::vector<double> crossings;
  double previousAngle = 0, previousTime = 0, maxJointError = 0;
  for (const State& st : r.samples) {
    const Vector3 d = st.bodies[1].position - pivot;
    const double angle = std::atan2(d.x(), -d.y());
    if (st.time > 0 && previousAngle < 0 && angle >= 0)
      crossings.push_back(previousTime +
                          (st.time - previousTime) * (-previousAngle) / (angle - previousAngle));
    previousAngle = angle;
    previousTime = st.time;
    // The joint's own constraint, measured from the poses: the anchor fixed in the bob must stay
    // at the pivot (ball, hinge, universal), or at distance L (distance joint).
    const Vector3 anchorInBob =
        s.rigidBodies[1].rotation.conjugate() * (pivot - bob.initialCenterOfMass());
    const Vector3 anchor = st.bodies[1].position + st.bodies[1].rotation * anchorInBob;
    const double error =
        type == JointType::Distance ? std::abs(d.norm() - length) : (anchor - pivot).norm();
    maxJointError = std::max(maxJointError, error);
  }
  ASSERT_GE(crossings.size(), 3u) << "the pendulum did not swing";
  const double measured = (crossings.back() - crossings.front()) / double(crossings.size() - 1);
  const double h = s.simulation.timeStepSize;
  const double relative = std::abs(measured - expected) / expected;
  EXPECT_LE(relative, p.periodErrorFactor * omega0 * h)
      << p.engine << " " << pbd::jointTypeName(type) << ": T = " << measured << " s, exact "
      << expected;
  const double aMax = kG * (1 + 2 * (1 - std::cos(theta0)));
  EXPECT_LE(maxJointError, p.jointErrorFactor * h * h * aMax)
      << p.engine << " " << pbd::jointTypeName(type);
  std::printf(
      "  %s/%s %-9s pendulum: T = %.6f s (exact %.6f, rel. error %.2e), max joint error %.2e m\n",
      p.engine.c_str(), p.method.c_str(), pbd::jointTypeName(type), measured, expected, relative,
      maxJointError);
}

// --- Contacts: bounce ---------------------------------------------------------------------------
// A sphere (r = 0.1 m) dropped from 1 m onto a static box with pair restitution e = 0.8: the
// first rebound apex over the drop height (both from the contact height) is e² = 0.64.
TEST_P(Parity, DroppedSphereReboundsToESquared) {
  const ParityProfile& p = GetParam();
  if (!p.contacts) GTEST_SKIP() << p.engine << ": contacts not enabled in its profile";
  Scene s = baseScene(0.001);
  auto ground = pbd::test::boxBody(0, Vector3(4, 1, 4), Vector3(0, -0.5, 0), 1, false);
  auto ball = pbd::test::sphereBody(1, 0.1, Vector3(0, 1.1, 0), 1000);
  s.rigidBodies = {ground, ball};
  s.contactPairs.push_back(pbd::test::contactPair(0, 1, Real(0.2), Real(0.8)));
  const EngineRun r = run(p, s, 1.5);
  ASSERT_EQ(r.outcome.status, RunStatus::Ok) << r.outcome.reason;
  // First impact: sample k is the last one still moving down, k + 1 the first moving up. The
  // contact height is the lower of the two (an engine that resolves the impact within a step
  // reports the lowest position together with the rebound velocity); the apex is the highest
  // point from k + 1 on, before the velocity turns downward again.
  std::size_t k = 0;
  while (k + 1 < r.samples.size() && r.samples[k + 1].bodies[1].velocity.y() <= 0)
    ++k;
  ASSERT_LT(k + 1, r.samples.size()) << p.engine << ": the sphere never bounced";
  const double contactHeight = std::min(double(r.samples[k].bodies[1].position.y()),
                                        double(r.samples[k + 1].bodies[1].position.y()));
  double apex = contactHeight;
  for (std::size_t i = k + 1; i < r.samples.size() && r.samples[i].bodies[1].velocity.y() >= -1e-9;
       ++i)
    apex = std::max(apex, double(r.samples[i].bodies[1].position.y()));
  const double ratio = (apex - contactHeight) / (1.1 - contactHeight);
  EXPECT_NEAR(ratio, 0.64, p.reboundTolerance) << p.engine;
  std::printf("  %s/%s rebound apex ratio %.4f (e^2 = 0.64), contact at y = %.4f m\n",
              p.engine.c_str(), p.method.c_str(), ratio, contactHeight);
}

// --- Contacts: incline ----------------------------------------------------------------------
// A 0.2 m block on a static incline with pair friction μ = 0.5 (tan⁻¹ μ = 26.57°): at θ = 21.57°
// it sticks; at θ = 31.57° it slides with a = g (sin θ − μ cos θ). With the slope turned 45°
// about the vertical, an isotropic cone still slides, a world-aligned pyramid holds it
// (it resists up to √2 μ N along the diagonal, and tan 31.57° = 0.61 < 0.71).
Scene inclineScene(double theta, double yaw, double mu) {
  Scene s = baseScene(0.002);
  const pbd::Quaternion tilt = pbd::Quaternion(pbd::AngleAxis(Real(yaw), Vector3::UnitY())) *
                               pbd::Quaternion(pbd::AngleAxis(Real(theta), Vector3::UnitZ()));
  const Vector3 normal = tilt * Vector3::UnitY();
  s.rigidBodies.push_back(
      pbd::test::boxBody(0, Vector3(4, 0.2, 4), Vector3::Zero(), 1, false, tilt));
  s.rigidBodies.push_back(
      pbd::test::boxBody(1, Vector3(0.2, 0.2, 0.2), normal * Real(0.2), 1000, true, tilt));
  s.contactPairs.push_back(pbd::test::contactPair(0, 1, Real(mu), 0));
  return s;
}

/// Displacement along the slope between t = 0.5 s and 1.5 s, and the acceleration fitted from
/// the velocity change over the same window.
std::pair<double, double> slide(const EngineRun& r, const Vector3& downhill) {
  const State* a = nullptr;
  const State* b = nullptr;
  for (const State& st : r.samples) {
    if (!a && st.time >= 0.5) a = &st;
    if (!b && st.time >= 1.5) b = &st;
  }
  const double distance = (b->bodies[1].position - a->bodies[1].position).dot(downhill);
  const double acceleration =
      (b->bodies[1].velocity - a->bodies[1].velocity).dot(downhill) / (b->time - a->time);
  return {distance, acceleration};
}

TEST_P(Parity, BlockOnInclineSticksBelowAndSlidesAboveTheFrictionAngle) {
  const ParityProfile& p = GetParam();
  if (!p.contacts) GTEST_SKIP() << p.engine << ": contacts not enabled in its profile";
  const double mu = 0.5, frictionAngle = std::atan(mu), margin = 5 * M_PI / 180;
  for (double yaw : {0.0, M_PI / 4}) {
    for (double theta : {frictionAngle - margin, frictionAngle + margin}) {
      const Scene s = inclineScene(theta, yaw, mu);
      const EngineRun r = run(p, s, 1.6);
      ASSERT_EQ(r.outcome.status, RunStatus::Ok) << r.outcome.reason;
      const Vector3 downhill = (s.rigidBodies[0].rotation * Vector3(-1, 0, 0)).normalized();
      const auto [distance, acceleration] = slide(r, downhill);
      const double expected = kG * (std::sin(theta) - mu * std::cos(theta));
      const bool shouldSlide =
          theta > frictionAngle && !(yaw > 0 && p.frictionCone == FrictionCone::Pyramid);
      if (shouldSlide)
        EXPECT_NEAR(acceleration, expected, p.slideAccelerationTolerance * expected)
            << p.engine << " θ = " << theta * 180 / M_PI << "°, yaw " << yaw * 180 / M_PI << "°";
      else
        EXPECT_LE(std::abs(distance), p.stickCreep)
            << p.engine << " θ = " << theta * 180 / M_PI << "°, yaw " << yaw * 180 / M_PI << "°";
      std::printf(
          "  %s/%s incline θ = %.2f° yaw %2.0f°: moved %.2e m in 1 s, a = %.4f (sliding law "
          "%.4f)\n",
          p.engine.c_str(), p.method.c_str(), theta * 180 / M_PI, yaw * 180 / M_PI, distance,
          acceleration, expected);
    }
  }
}

std::string profileName(const ParityProfile& p) {
  std::string name = p.engine + "_" + p.method;
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return name;
}

INSTANTIATE_TEST_SUITE_P(Engines, Parity, ::testing::ValuesIn(parityProfiles()),
                         [](const ::testing::TestParamInfo<ParityProfile>& param) {
                           return profileName(param.param);
                         });

INSTANTIATE_TEST_SUITE_P(
    Engines, PendulumParity,
    ::testing::Combine(::testing::ValuesIn(parityProfiles()),
                       ::testing::Values(JointType::Ball, JointType::Hinge, JointType::Universal,
                                         JointType::Distance)),
    [](const ::testing::TestParamInfo<std::tuple<ParityProfile, JointType>>& param) {
      return profileName(std::get<0>(param.param)) + "_" +
             pbd::jointTypeName(std::get<1>(param.param));
    });

}  // namespace
}  // namespace pbdval::test
