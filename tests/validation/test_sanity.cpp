// The boundary checks and sanity bounds every run is held to (validation/measure/sanity.h,
// docs/metrics.md §Boundary checks, §Sanity bounds). The engine here is the tests' own: it moves
// free bodies along the exact solution (a parabola, a constant spin of an isotropic body) and
// can make each of the mistakes an engine written from the protocol's docs makes.
#include <gtest/gtest.h>

#include <cmath>

#include "fixtures.h"
#include "validation/measure/sanity.h"
#include "validation/run/simulation.h"

namespace pbdval {
namespace {

using test::kPi;

enum class Mistake { None, QuaternionXyzw, PositionsInMillimetres, OmegaInBodyAxes, BodyOrigin };

/// Free flight, exactly: x(t) = x₀ + v₀ t + ½ g t², q(t) = exp(ω₀ t) q₀ (a body with isotropic
/// inertia keeps its ω), read back with `mistake`.
class ExactFreeFlightEngine : public SteppingEngine {
 public:
  explicit ExactFreeFlightEngine(Mistake mistake) : mistake_(mistake) {}
  std::string_view name() const override { return "exact"; }
  std::vector<std::string> unsupported(const pbd::Scene&, const Method&) const override {
    return {};
  }
  void load(const pbd::Scene& scene, const Method&) override {
    scene_ = &scene;
    time_ = 0;
  }
  void step() override { time_ += double(scene_->simulation.timeStepSize); }
  void read(State& state) const override {
    const Vector3 g = scene_->simulation.gravitation;
    state.time = time_;
    state.bodies.clear();
    for (const pbd::RigidBodyDesc& body : scene_->rigidBodies) {
      BodyState b;
      b.id = body.id;
      b.position = body.initialCenterOfMass() + body.velocity * time_ + 0.5 * g * time_ * time_;
      b.velocity = body.velocity + g * time_;
      b.angularVelocity = body.angularVelocity;
      const double spin = double(body.angularVelocity.norm());
      const Quaternion turn =
          spin > 0
              ? Quaternion(Eigen::AngleAxis<pbd::Real>(spin * time_, body.angularVelocity / spin))
              : Quaternion::Identity();
      b.rotation = (turn * body.rotation).normalized();
      switch (mistake_) {
        case Mistake::None:
          break;
        case Mistake::QuaternionXyzw:  // x, y, z, w written where w, x, y, z belong
          b.rotation = Quaternion(b.rotation.x(), b.rotation.y(), b.rotation.z(), b.rotation.w());
          break;
        case Mistake::PositionsInMillimetres:
          b.position *= 1000;
          break;
        case Mistake::OmegaInBodyAxes:
          b.angularVelocity = b.rotation.conjugate() * b.angularVelocity;
          break;
        case Mistake::BodyOrigin:  // the scene frame's origin, not the centre of mass
          b.position -= b.rotation * body.massProperties.centerOfMass;
          break;
      }
      state.bodies.push_back(b);
    }
  }
  RunFacts runFacts() const override { return {}; }

 private:
  Mistake mistake_;
  const pbd::Scene* scene_ = nullptr;
  double time_ = 0;
};

/// One tumbling cube (isotropic inertia: any spin is steady) thrown under gravity, its scene
/// frame tilted and its centre of mass 5 cm from the frame's origin (as a mesh's may be).
pbd::Scene tumblingCubeScene() {
  pbd::Scene scene = test::emptyScene(Vector3(0, -9.81, 0));
  pbd::RigidBodyDesc cube = pbd::test::boxBody(0, Vector3(0.2, 0.2, 0.2), Vector3(1, 2, 3), 1000,
                                               true, test::turn(Vector3(1, 1, 0), 0.7));
  cube.massProperties.centerOfMass = Vector3(0.05, 0, 0);
  cube.velocity = Vector3(1, 4, 0);
  cube.angularVelocity = Vector3(0, 0, 3);  // about world z; the tilted body axes turn with it
  scene.rigidBodies.push_back(cube);
  scene.simulation.timeStepSize = pbd::Real(0.005);
  return scene;
}

RunOutcome runExact(const pbd::Scene& scene, Mistake mistake, double sampleInterval = 0.05) {
  ExactFreeFlightEngine engine(mistake);
  return runSimulation(engine, scene, Method{}, RunLength{1.0, sampleInterval}, {});
}

TEST(BoundaryChecks, TheExactMotionOfAThrownTumblingCubePassesAtEverySampleInterval) {
  const pbd::Scene scene = tumblingCubeScene();
  for (double interval : {0.0, 0.05, 0.25}) {
    const RunOutcome outcome = runExact(scene, Mistake::None, interval);
    EXPECT_EQ(outcome.status, RunStatus::Ok) << "interval " << interval << ": " << outcome.reason;
  }
}

TEST(BoundaryChecks, QuaternionsWrittenXyzwAreAnErrorNamingTheCheckTheBodyAndTheSample) {
  const RunOutcome outcome = runExact(tumblingCubeScene(), Mistake::QuaternionXyzw);
  EXPECT_EQ(outcome.status, RunStatus::Error);
  EXPECT_NE(outcome.reason.find("initial_state"), std::string::npos) << outcome.reason;
  EXPECT_NE(outcome.reason.find("orientation of body 0 (RigidBodies[0])"), std::string::npos)
      << outcome.reason;
}

TEST(BoundaryChecks, PositionsInMillimetresAreAnError) {
  const RunOutcome outcome = runExact(tumblingCubeScene(), Mistake::PositionsInMillimetres);
  EXPECT_EQ(outcome.status, RunStatus::Error);
  EXPECT_NE(outcome.reason.find("initial_state: the first sample's position"), std::string::npos)
      << outcome.reason;
}

TEST(BoundaryChecks, PositionsInMillimetresFromTheOriginAreCaughtByTheirVelocities) {
  // At the origin a scale error leaves the first sample right: the motion gives it away.
  pbd::Scene scene = tumblingCubeScene();
  scene.rigidBodies[0].translation =
      -(scene.rigidBodies[0].rotation * scene.rigidBodies[0].massProperties.centerOfMass);
  const RunOutcome outcome = runExact(scene, Mistake::PositionsInMillimetres);
  EXPECT_EQ(outcome.status, RunStatus::Error);
  EXPECT_NE(outcome.reason.find("velocity_consistency: body 0"), std::string::npos)
      << outcome.reason;
  EXPECT_NE(outcome.reason.find("between samples 0 and 1"), std::string::npos) << outcome.reason;
}

TEST(BoundaryChecks, AngularVelocityInBodyAxesIsAnError) {
  const RunOutcome outcome = runExact(tumblingCubeScene(), Mistake::OmegaInBodyAxes);
  EXPECT_EQ(outcome.status, RunStatus::Error);
  // The first sample's ω is already in the tilted body axes.
  EXPECT_NE(outcome.reason.find("angular velocity of body 0"), std::string::npos) << outcome.reason;
}

TEST(BoundaryChecks, TheBodyOriginInsteadOfTheCentreOfMassIsAnError) {
  const RunOutcome outcome = runExact(tumblingCubeScene(), Mistake::BodyOrigin);
  EXPECT_EQ(outcome.status, RunStatus::Error);
  EXPECT_NE(outcome.reason.find("initial_state: the first sample's position"), std::string::npos)
      << outcome.reason;
}

TEST(BoundaryChecks, AConstantVelocityReportedForABodyAtRestIsAnError) {
  // The pbd.xpbd defect of issue 24: a box held still reports v_y = −0.0194 m/s every sample.
  const pbd::Scene scene = tumblingCubeScene();
  std::vector<State> samples;
  for (int k = 0; k <= 20; ++k) {
    State s;
    s.time = 0.05 * k;
    const pbd::RigidBodyDesc& body = scene.rigidBodies[0];
    BodyState b{body.id, body.initialCenterOfMass(), body.rotation, body.velocity,
                body.angularVelocity};
    if (k > 0) {
      b.position = samples.front().bodies[0].position;
      b.velocity = Vector3(0, -0.0194, 0);
      b.angularVelocity = Vector3::Zero();
      b.rotation = body.rotation;
    }
    s.bodies.push_back(b);
    samples.push_back(s);
  }
  // The first interval holds the jump from the thrown state to rest (an impact); from the
  // second on the body is still and its velocity is not.
  const std::optional<CheckViolation> v = boundaryViolation(scene, samples);
  ASSERT_TRUE(v.has_value());
  EXPECT_EQ(v->check, "velocity_at_rest");
  EXPECT_NE(v->message.find("0.0194"), std::string::npos) << v->message;
  // A method whose velocity pass is declared to leave that much at rest (the seed's PBD step:
  // (1 + e)|g|h, here 2 · 9.81 · 0.005 = 0.098 m/s) passes.
  EXPECT_FALSE(boundaryViolation(scene, samples, 1e-9, 2 * 9.81 * 0.005).has_value());
}

TEST(BoundaryChecks, ANonUnitQuaternionIsAnError) {
  const pbd::Scene scene = tumblingCubeScene();
  ExactFreeFlightEngine engine(Mistake::None);
  engine.load(scene, Method{});
  std::vector<State> samples(2);
  engine.read(samples[0]);
  engine.step();
  engine.read(samples[1]);
  samples[1].bodies[0].rotation.coeffs() *= 1.001;
  const std::optional<CheckViolation> v = boundaryViolation(scene, samples);
  ASSERT_TRUE(v.has_value());
  EXPECT_EQ(v->check, "unit_quaternion");
  EXPECT_NE(v->message.find("sample 1"), std::string::npos) << v->message;
}

TEST(BoundaryChecks, AnImpactBetweenTwoSamplesIsNotAViolation) {
  // A ball dropped at rest onto a floor at y = 0 from 1 m, bouncing with restitution 1/2,
  // sampled every 0.1 s: impacts fall between samples.
  pbd::Scene scene = test::emptyScene(Vector3(0, -9.81, 0));
  scene.rigidBodies.push_back(pbd::test::sphereBody(0, 0.1, Vector3(0, 1, 0), 1000));
  const double g = 9.81;
  std::vector<State> samples;
  for (int k = 0; k <= 20; ++k) {
    const double t = 0.1 * k;
    // The exact bouncing motion: flights of decreasing height.
    double start = 0, y0 = 1, v0 = 0;
    for (int bounce = 0; bounce < 10; ++bounce) {
      const double flight = (v0 + std::sqrt(v0 * v0 + 2 * g * y0)) / g;  // until y = 0
      if (t < start + flight) break;
      const double impact = v0 - g * flight;  // < 0
      start += flight;
      y0 = 0;
      v0 = -0.5 * impact;
    }
    const double tau = t - start;
    State s;
    s.time = t;
    s.bodies.push_back({0, Vector3(0, y0 + v0 * tau - 0.5 * g * tau * tau, 0),
                        Quaternion::Identity(), Vector3(0, v0 - g * tau, 0), Vector3::Zero()});
    samples.push_back(s);
  }
  const std::optional<CheckViolation> v = boundaryViolation(scene, samples);
  EXPECT_FALSE(v.has_value()) << v->message;
}

/// A sphere spinning about z that alternates its turn every step (+θ, −θ, …), reporting the
/// angular velocity of each step's own turn: consistent step by step, and a constant ω at every
/// second step's state, where the net turn is zero.
class StepOscillationEngine : public SteppingEngine {
 public:
  std::string_view name() const override { return "oscillation"; }
  std::vector<std::string> unsupported(const pbd::Scene&, const Method&) const override {
    return {};
  }
  void load(const pbd::Scene& scene, const Method&) override {
    scene_ = &scene;
    step_ = 0;
  }
  void step() override { ++step_; }
  void read(State& state) const override {
    const double h = double(scene_->simulation.timeStepSize);
    const pbd::RigidBodyDesc& body = scene_->rigidBodies[0];
    const double sign = step_ % 2 == 1 ? 1.0 : -1.0;  // the last step's turn
    const double angle = step_ % 2 == 1 ? kTurn : 0.0;
    state.time = double(step_) * h;
    state.bodies = {{body.id, body.initialCenterOfMass(),
                     Quaternion(Eigen::AngleAxis<pbd::Real>(angle, Vector3::UnitZ())),
                     Vector3::Zero(),
                     step_ == 0 ? Vector3(Vector3::Zero()) : Vector3(0, 0, sign * kTurn / h)}};
  }
  RunFacts runFacts() const override {
    RunFacts facts;
    facts.initialVelocitiesProjected = false;
    return facts;
  }
  static constexpr double kTurn = 0.05;  ///< rad per step

 private:
  const pbd::Scene* scene_ = nullptr;
  long step_ = 0;
};

TEST(BoundaryChecks, AStepFrequencyOscillationIsConsistentPerStepAndSuspectOnACoarserSampleGrid) {
  pbd::Scene scene = test::emptyScene(Vector3::Zero());
  scene.rigidBodies.push_back(pbd::test::sphereBody(0, 0.1, Vector3(0, 0, 0), 1000));
  scene.simulation.timeStepSize = pbd::Real(0.01);
  StepOscillationEngine engine;
  // Every step a sample: nothing aliases.
  RunOutcome perStep = runSimulation(engine, scene, Method{}, RunLength{0.5, 0}, {});
  EXPECT_EQ(perStep.status, RunStatus::Ok) << perStep.reason;
  // Every second step a sample: ω = −5 rad/s at every sample, no net turn.
  RunOutcome sampled = runSimulation(engine, scene, Method{}, RunLength{0.5, 0.02}, {});
  EXPECT_EQ(sampled.status, RunStatus::Suspect);
  EXPECT_NE(sampled.reason.find("2 integrator steps apart"), std::string::npos) << sampled.reason;
}

// ---- Sanity bounds ----

/// A projectile integrated by semi-implicit Euler at step h: the reference problem of the
/// energy bound (docs/metrics.md): its exact energy error is −½ M g² h t.
std::vector<State> semiImplicitProjectile(const pbd::Scene& scene, double h, int steps,
                                          double velocityGainPerStep = 1) {
  const pbd::RigidBodyDesc& body = scene.rigidBodies[0];
  const Vector3 g = scene.simulation.gravitation;
  Vector3 x = body.initialCenterOfMass(), v = body.velocity;
  std::vector<State> samples;
  for (int n = 0; n <= steps; ++n) {
    if (n > 0) {
      v = velocityGainPerStep * (v + g * h);
      x += h * v;
    }
    State s;
    s.time = n * h;
    s.bodies.push_back({body.id, x, body.rotation, v, Vector3::Zero()});
    samples.push_back(s);
  }
  return samples;
}

pbd::Scene projectileScene(double h) {
  pbd::Scene scene = test::emptyScene(Vector3(0, -9.81, 0));
  scene.rigidBodies.push_back(pbd::test::sphereBody(0, 0.1, Vector3(0, 0, 0), 1000));
  scene.rigidBodies[0].velocity = Vector3(3, 5, 0);
  scene.simulation.timeStepSize = pbd::Real(h);
  return scene;
}

TEST(SanityBounds, TheEnergyBoundHoldsTheReferenceProblemWithRoomToSpare) {
  // Semi-implicit Euler loses ½ M g² h T; the bound (h T/τ²) E_ref is at least twice that.
  const double h = 0.01;
  const pbd::Scene scene = projectileScene(h);
  const SanityBounds bounds = sanityBounds(scene);
  EXPECT_TRUE(bounds.passive) << bounds.notPassive;
  const double mass = double(scene.rigidBodies[0].massProperties.mass);
  const double loss = 0.5 * mass * 9.81 * 9.81 * h * 2.0;
  const double allowed = bounds.relativeBound(2.0) * energyScale(scene, CaseSpec{});
  EXPECT_GE(allowed, 2 * loss);
  // The run itself (a loss, and an isolated body whose momentum follows M g t exactly) passes.
  const std::optional<CheckViolation> v =
      sanityViolation(scene, CaseSpec{}, semiImplicitProjectile(scene, h, 200));
  EXPECT_FALSE(v.has_value()) << v->message;
}

TEST(SanityBounds, EnergyCreatedBeyondTheBoundMakesTheRunSuspectWithTheNumbers) {
  // 2 % more speed every step: the energy grows by a factor of ~e^(0.04·200) within 2 s.
  const double h = 0.01;
  const pbd::Scene scene = projectileScene(h);
  const std::optional<CheckViolation> v =
      sanityViolation(scene, CaseSpec{}, semiImplicitProjectile(scene, h, 200, 1.02));
  ASSERT_TRUE(v.has_value());
  EXPECT_TRUE(v->check == "speed" || v->check == "energy_created") << v->check;
  EXPECT_NE(v->message.find("body 0 (RigidBodies[0])"), std::string::npos) << v->message;
  EXPECT_NE(v->message.find("τ = "), std::string::npos) << v->message;
}

TEST(SanityBounds, MomentumChangedInAnIsolatedSceneWithoutGravityIsSuspect) {
  // Two free spheres without gravity, and nothing between them to turn one's velocity.
  pbd::Scene scene = test::emptyScene(Vector3::Zero());
  scene.rigidBodies.push_back(pbd::test::sphereBody(0, 0.1, Vector3(0, 0, 0), 1000));
  scene.rigidBodies.push_back(pbd::test::sphereBody(1, 0.1, Vector3(1, 0, 0), 1000));
  scene.rigidBodies[0].velocity = Vector3(1, 0, 0);
  scene.rigidBodies[1].velocity = Vector3(-1, 0, 0);
  scene.simulation.timeStepSize = pbd::Real(0.01);
  const SanityBounds bounds = sanityBounds(scene);
  ASSERT_TRUE(bounds.isolated) << bounds.notIsolated;
  std::vector<State> samples;
  for (int k = 0; k <= 10; ++k) {
    State s;
    s.time = 0.01 * k;
    // From sample 5 on, body 0's velocity is turned by 0.1 rad: the energy is unchanged, the
    // momentum is not (‖ΔP‖ = 2 m sin 0.05 ≈ 0.1 m).
    const Vector3 velocity = k >= 5 ? Vector3(std::cos(0.1), std::sin(0.1), 0) : Vector3(1, 0, 0);
    s.bodies.push_back(
        {0, Vector3(0.01 * k, 0, 0), Quaternion::Identity(), velocity, Vector3::Zero()});
    s.bodies.push_back({1, Vector3(1 - 0.01 * k, 0, 0), Quaternion::Identity(), Vector3(-1, 0, 0),
                        Vector3::Zero()});
    samples.push_back(s);
  }
  const std::optional<CheckViolation> v = sanityViolation(scene, CaseSpec{}, samples);
  ASSERT_TRUE(v.has_value());
  EXPECT_EQ(v->check, "linear_momentum") << v->message;
  EXPECT_NE(v->message.find("sample 5"), std::string::npos) << v->message;
}

TEST(SanityBounds, AMotorMakesASceneNonPassiveAndAStaticColliderNonIsolated) {
  pbd::Scene scene = pbd::test::singleJointScene(pbd::JointType::TargetVelocityMotorHinge);
  EXPECT_FALSE(sanityBounds(scene).passive);
  EXPECT_NE(sanityBounds(scene).notPassive.find("motor"), std::string::npos);
  pbd::Scene ground = projectileScene(0.01);
  ground.rigidBodies.push_back(
      pbd::test::boxBody(1, Vector3(10, 1, 10), Vector3(0, -5, 0), 1, /*dynamic=*/false));
  EXPECT_TRUE(sanityBounds(ground).passive);
  EXPECT_FALSE(sanityBounds(ground).isolated);
}

}  // namespace
}  // namespace pbdval
