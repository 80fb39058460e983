// Analytic references with contact (sliding block, rolling sphere, bowling ball, bouncing
// ball) against time-stepped Coulomb / restitution integrations written here, plus the
// dispatcher's errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>

#include "tests/validation/fixtures.h"
#include "validation/measure/numerics.h"
#include "validation/measure/references/bouncing_ball.h"
#include "validation/measure/references/reference.h"

namespace pbdval {
namespace {

using pbd::test::boxBody;
using pbd::test::sphereBody;
using test::kPi;
using test::turn;

constexpr double kG = 9.81;

using test::analytic;
using test::errorOf;
using test::timesUpTo;

/// A static 4 × 0.2 × 4 m incline turned by θ about z (normal (−sin θ, cos θ, 0)) and body 1.
pbd::Scene inclineScene(double theta, pbd::RigidBodyDesc body) {
  pbd::Scene scene = test::emptyScene(Vector3(0, -kG, 0));
  scene.rigidBodies.push_back(
      boxBody(0, Vector3(4, 0.2, 4), Vector3::Zero(), 1000, false, turn(Vector3::UnitZ(), theta)));
  scene.rigidBodies.push_back(std::move(body));
  return scene;
}

/// Downhill on that incline: g_t = −g sin θ (cos θ, sin θ, 0).
Vector3 downhill(double theta) {
  return -Vector3(std::cos(theta), std::sin(theta), 0);
}

/// Time-stepped 1D Coulomb contact (velocity level, written for the test): each step adds
/// gravity, then the friction impulse (≤ μ g cos θ h) that best removes the contact slip
/// u − r w; κ = m r²/I (0: a block). Returns s(t) at `times`, and the final u and w.
struct SteppedLine {
  std::vector<double> s;
  double u = 0, w = 0;
};
SteppedLine stepCoulombLine(double theta, double mu, double kappa, double radius, double u0,
                            double w0, const std::vector<double>& times, double h) {
  SteppedLine out;
  double s = 0, t = 0;
  out.u = u0;
  out.w = w0;
  const double maxImpulse = mu * kG * std::cos(theta) * h;
  for (const double target : times) {
    while (t < target - 1e-12) {
      out.u += h * kG * std::sin(theta);
      const double slip = out.u - radius * out.w;
      const double impulse = std::clamp(-slip / (1 + kappa), -maxImpulse, maxImpulse);
      out.u += impulse;
      if (kappa > 0) out.w -= impulse * kappa / radius;
      s += h * out.u;
      t += h;
    }
    out.s.push_back(s);
  }
  return out;
}

// The stepped integrations converge as O(h): with h = 1e-5 s the positions are off by
// ~½ a h t ≲ 5e-5 m over the runs below.
constexpr double kSteppedTolerance = 2e-4;

pbd::RigidBodyDesc block(const Vector3& velocity) {
  pbd::RigidBodyDesc b = boxBody(1, Vector3(0.2, 0.2, 0.2), Vector3(0, 0.2, 0), 500);
  b.velocity = velocity;
  return b;
}

void expectBlockMatches(double theta, double mu, double u0, double duration) {
  const pbd::Scene scene = inclineScene(theta, block(u0 * downhill(theta)));
  const std::vector<double> times = timesUpTo(duration, 0.05);
  const ReferenceTrajectory r = buildAnalyticReference(
      scene, analytic("sliding_block", R"({"friction": )" + std::to_string(mu) + "}"), times, 0);
  const SteppedLine line = stepCoulombLine(theta, mu, 0, 0, u0, 0, times, 1e-5);
  for (std::size_t k = 0; k < times.size(); ++k) {
    const Vector3 expected = Vector3(0, 0.2, 0) + line.s[k] * downhill(theta);
    EXPECT_NEAR((r.samples[k].bodies[1].position - expected).norm(), 0, kSteppedTolerance)
        << "t = " << times[k];
  }
  EXPECT_TRUE(r.hasRotation);
}

TEST(SlidingBlockReference, SlidesWhenTheInclineIsSteeperThanTheFrictionAngle) {
  expectBlockMatches(kPi / 6, 0.2, 0, 1.0);  // tan 30° = 0.577 > 0.2
  // And by hand: s = ½ g (sin θ − μ cos θ) t².
  const pbd::Scene scene = inclineScene(kPi / 6, block(Vector3::Zero()));
  const ReferenceTrajectory r =
      buildAnalyticReference(scene, analytic("sliding_block", R"({"friction": 0.2})"), {1.0}, 0);
  const double s = 0.5 * kG * (0.5 - 0.2 * std::cos(kPi / 6));
  EXPECT_NEAR(
      (r.samples[0].bodies[1].position - (Vector3(0, 0.2, 0) + s * downhill(kPi / 6))).norm(), 0,
      1e-14);
}

TEST(SlidingBlockReference, DeceleratesAndSticksWhenFrictionHolds) {
  expectBlockMatches(20 * kPi / 180, 0.5, 1.0, 1.5);  // stops at ≈ 0.79 s
}

TEST(SlidingBlockReference, ThrownUphillStopsThenSlidesBack) {
  expectBlockMatches(kPi / 6, 0.2, -2.0, 1.5);
}

TEST(SlidingBlockReference, TakesTheFrictionFromThePairMaterialByDefault) {
  pbd::Scene scene = inclineScene(kPi / 6, block(Vector3::Zero()));
  scene.rigidBodies[0].friction = 0.1;
  scene.rigidBodies[1].friction = 0.15;
  const double mu = scene.pairMaterial(1, 0).friction;
  const ReferenceTrajectory byDefault =
      buildAnalyticReference(scene, analytic("sliding_block"), {0.7}, 0);
  const ReferenceTrajectory explicitMu = buildAnalyticReference(
      scene, analytic("sliding_block", R"({"friction": )" + std::to_string(mu) + "}"), {0.7}, 0);
  EXPECT_NEAR(
      (byDefault.samples[0].bodies[1].position - explicitMu.samples[0].bodies[1].position).norm(),
      0, 1e-9);  // std::to_string keeps 6 decimals
}

TEST(SlidingBlockReference, RefusesSpinAndSidewaysSlip) {
  pbd::RigidBodyDesc spinning = block(Vector3::Zero());
  spinning.angularVelocity = Vector3(0, 1, 0);
  EXPECT_NE(errorOf([&] {
              buildAnalyticReference(inclineScene(0.3, spinning), analytic("sliding_block"), {0.0},
                                     0);
            }).find("must not"),
            std::string::npos);
  EXPECT_NE(errorOf([&] {
              buildAnalyticReference(inclineScene(0.3, block(Vector3(0, 0, 1))),
                                     analytic("sliding_block"), {0.0}, 0);
            }).find("not along the downhill direction"),
            std::string::npos);
}

pbd::RigidBodyDesc ball(double radius, const Vector3& velocity, const Vector3& spin) {
  pbd::RigidBodyDesc b = sphereBody(1, radius, Vector3(0, radius, 0), 1000);
  b.velocity = velocity;
  b.angularVelocity = spin;
  return b;
}

TEST(RollingSphereReference, RollsAtFiveSeventhsGSinTheta) {
  const double theta = 15 * kPi / 180;
  const pbd::Scene scene = inclineScene(theta, ball(0.05, Vector3::Zero(), Vector3::Zero()));
  const std::vector<double> times = timesUpTo(1.0, 0.05);
  const ReferenceTrajectory r =
      buildAnalyticReference(scene, analytic("rolling_sphere", R"({"friction": 1})"), times, 0);
  const SteppedLine line = stepCoulombLine(theta, 1.0, 2.5, 0.05, 0, 0, times, 1e-5);
  for (std::size_t k = 0; k < times.size(); ++k) {
    // By hand (solid sphere, I = 2/5 m r²): s = ½ (5/7) g sin θ t². The sphere's inertia is
    // the closed form, so only round-off separates them.
    const double s = 0.5 * 5.0 / 7.0 * kG * std::sin(theta) * times[k] * times[k];
    EXPECT_NEAR(
        (r.samples[k].bodies[1].position - (Vector3(0, 0.05, 0) + s * downhill(theta))).norm(), 0,
        1e-12);
    EXPECT_NEAR(line.s[k], s, kSteppedTolerance);
  }
  // Rolling: ω = (u/r) ẑ (e = n × d = ẑ on this incline), and the orientation turns about ẑ.
  const double u = 5.0 / 7.0 * kG * std::sin(theta);
  EXPECT_NEAR((r.samples.back().bodies[1].angularVelocity - Vector3(0, 0, u / 0.05)).norm(), 0,
              1e-10);
  EXPECT_TRUE(r.hasRotation);
  const double angle = 0.5 * u / 0.05;  // ∫ w dt = ½ (u′/r) t² at t = 1 (18 rad)
  EXPECT_NEAR(twistAngle(r.samples.back().bodies[1].rotation, Vector3::UnitZ()), wrapAngle(angle),
              1e-10);
}

TEST(RollingSphereReference, SlidesWhenFrictionIsBelowTwoSeventhsTanTheta) {
  const double theta = 15 * kPi / 180;  // (2/7) tan 15° = 0.0766
  const pbd::Scene scene = inclineScene(theta, ball(0.05, Vector3::Zero(), Vector3::Zero()));
  const std::vector<double> times = timesUpTo(1.0, 0.05);
  const ReferenceTrajectory r =
      buildAnalyticReference(scene, analytic("rolling_sphere", R"({"friction": 0.05})"), times, 0);
  const SteppedLine line = stepCoulombLine(theta, 0.05, 2.5, 0.05, 0, 0, times, 1e-5);
  for (std::size_t k = 0; k < times.size(); ++k)
    EXPECT_NEAR(
        (r.samples[k].bodies[1].position - (Vector3(0, 0.05, 0) + line.s[k] * downhill(theta)))
            .norm(),
        0, kSteppedTolerance);
  // Spin grows at μ g cos θ κ / r while sliding.
  EXPECT_NEAR(r.samples.back().bodies[1].angularVelocity.z(),
              0.05 * kG * std::cos(theta) * 2.5 / 0.05, 1e-9);
}

TEST(RollingSphereReference, BackspinSlidesThenRolls) {
  const double theta = 10 * kPi / 180;
  // Backspin −20 rad/s about e = ẑ: the contact point slips downhill at r · 20 = 1 m/s.
  const pbd::Scene scene = inclineScene(theta, ball(0.05, Vector3::Zero(), Vector3(0, 0, -20)));
  const std::vector<double> times = timesUpTo(1.5, 0.05);
  const ReferenceTrajectory r =
      buildAnalyticReference(scene, analytic("rolling_sphere", R"({"friction": 0.3})"), times, 0);
  const SteppedLine line = stepCoulombLine(theta, 0.3, 2.5, 0.05, 0, -20, times, 1e-5);
  for (std::size_t k = 0; k < times.size(); ++k)
    EXPECT_NEAR(
        (r.samples[k].bodies[1].position - (Vector3(0, 0.05, 0) + line.s[k] * downhill(theta)))
            .norm(),
        0, kSteppedTolerance);
  EXPECT_NEAR(r.samples.back().bodies[1].angularVelocity.z(), line.w, 1e-2);  // O(h)·κ/r
}

/// Drake's bowling ball: r = 0.10795 m, m = 6.35 kg, I = 0.0296 kg m², μ = 0.12, on level
/// ground (normal ŷ), thrown with v₀ and ω₀ that make it slip sideways too.
struct BowlingBall {
  pbd::Scene scene = test::emptyScene(Vector3(0, -kG, 0));
  double radius = 0.10795, mu = 0.12;
  Vector3 v0 = Vector3(8, 0, 1), w0 = Vector3(2, 5, -3);
  BowlingBall() {
    scene.rigidBodies.push_back(boxBody(0, Vector3(100, 1, 100), Vector3(0, -0.5, 0), 1000, false));
    pbd::RigidBodyDesc b = sphereBody(1, radius, Vector3(0, radius, 0), 1000);
    b.massProperties.mass = 6.35;
    b.massProperties.principalInertia = Vector3::Constant(0.0296);
    b.velocity = v0;
    b.angularVelocity = w0;
    scene.rigidBodies.push_back(b);
  }
  double kappa() const { return 6.35 * radius * radius / 0.0296; }
};

TEST(BowlingBallReference, MatchesAVectorCoulombIntegrationAndRollsAfterTStar) {
  const BowlingBall bowl;
  const std::vector<double> times = timesUpTo(3.0, 0.05);
  const ReferenceTrajectory r = buildAnalyticReference(
      bowl.scene, analytic("bowling_ball", R"({"friction": 0.12})"), times, 0);
  // Vector time stepping on the plane (written for the test): impulse per unit mass p ⟂ n with
  // ‖p‖ ≤ μ g h removing the slip σ = v − r ω × n; Δv = p, Δω = −(κ/r) n × p.
  const Vector3 n = Vector3::UnitY();
  Vector3 x(0, bowl.radius, 0), v = bowl.v0, w = bowl.w0;
  const double h = 1e-5, kappa = bowl.kappa();
  double t = 0;
  for (std::size_t k = 0; k < times.size(); ++k) {
    while (t < times[k] - 1e-12) {
      const Vector3 slip = v - bowl.radius * w.cross(n);
      Vector3 p = -slip / (1 + kappa);
      if (p.norm() > bowl.mu * kG * h) p *= bowl.mu * kG * h / p.norm();
      v += p;
      w -= kappa / bowl.radius * n.cross(p);
      x += h * v;
      t += h;
    }
    EXPECT_NEAR((r.samples[k].bodies[1].position - x).norm(), 0, kSteppedTolerance) << times[k];
    EXPECT_NEAR((r.samples[k].bodies[1].velocity - v).norm(), 0, 1e-3);  // O(μ g h)
    // The spin's error is (κ/r) times the velocity's: ≲ 23 · 1.2e-5 rad/s.
    EXPECT_NEAR((r.samples[k].bodies[1].angularVelocity - w).norm(), 0, 2e-3);
  }
  // Drake's closed form: sliding stops at t* = ‖σ₀‖ / (μ g (1 + κ)); then v is constant.
  const Vector3 slip0 = bowl.v0 - bowl.radius * bowl.w0.cross(n);
  const double tStar = slip0.norm() / (bowl.mu * kG * (1 + kappa));
  ASSERT_LT(tStar, 2.5);
  const ReferenceTrajectory later = buildAnalyticReference(
      bowl.scene, analytic("bowling_ball", R"({"friction": 0.12})"), {tStar, tStar + 0.5}, 0);
  EXPECT_NEAR((later.samples[0].bodies[1].velocity - later.samples[1].bodies[1].velocity).norm(), 0,
              1e-12);
  EXPECT_NE(later.description.find("rolls from t = "), std::string::npos);
}

TEST(BowlingBallReference, RefusesAnInclinedPlane) {
  const pbd::Scene scene = inclineScene(0.2, ball(0.05, Vector3::Zero(), Vector3::Zero()));
  EXPECT_NE(errorOf([&] {
              buildAnalyticReference(scene, analytic("bowling_ball"), {0.0}, 0);
            }).find("use rolling_sphere"),
            std::string::npos);
}

/// A 0.1 m ball dropped from 1.1 m (1 m above its contact height 0.1 m) onto a box whose top
/// face is at y = 0.
pbd::Scene dropScene() {
  pbd::Scene scene = test::emptyScene(Vector3(0, -kG, 0));
  scene.rigidBodies.push_back(boxBody(0, Vector3(10, 1, 10), Vector3(0, -0.5, 0), 1000, false));
  scene.rigidBodies.push_back(sphereBody(1, 0.1, Vector3(0, 1.1, 0), 1000));
  return scene;
}

TEST(BouncingBallReference, MatchesATimeSteppedDropWithRestitution) {
  const pbd::Scene scene = dropScene();
  const std::vector<double> times = timesUpTo(2.5, 0.01);
  const ReferenceTrajectory r =
      buildAnalyticReference(scene, analytic("bouncing_ball", R"({"restitution": 0.8})"), times, 0);
  // Semi-implicit Euler with reflection (written for the test), h = 1e-6 s: the impact times
  // are off by ≲ h per bounce, heights by ~g h t ≲ 3e-5 m.
  double y = 1.0, u = 0, t = 0;
  const double h = 1e-6;
  for (std::size_t k = 0; k < times.size(); ++k) {
    while (t < times[k] - 1e-12) {
      u -= h * kG;
      y += h * u;
      if (y < 0 && u < 0) {
        y = -0.8 * y;
        u = -0.8 * u;
      }
      t += h;
    }
    EXPECT_NEAR(r.samples[k].bodies[1].position.y(), 0.1 + y, 1e-4) << "t = " << times[k];
  }
}

TEST(BouncingBallReference, ApexHeightsFormTheGeometricSequenceAndTheBallComesToRest) {
  const pbd::Scene scene = dropScene();
  const std::vector<double> expected = bounceApexHeights(1.0, 0.8, 4);
  ASSERT_EQ(expected.size(), 4u);
  EXPECT_NEAR(expected[1], 0.64, 1e-15);
  EXPECT_NEAR(expected[3], 0.262144, 1e-15);
  const std::vector<double> times = timesUpTo(3.0, 1e-4);
  const ReferenceTrajectory r =
      buildAnalyticReference(scene, analytic("bouncing_ball", R"({"restitution": 0.8})"), times, 0);
  std::vector<double> apexes;
  for (std::size_t k = 1; k + 1 < times.size(); ++k) {
    const double y = r.samples[k].bodies[1].position.y();
    if (y > r.samples[k - 1].bodies[1].position.y() && y >= r.samples[k + 1].bodies[1].position.y())
      apexes.push_back(y - 0.1);
  }
  ASSERT_GE(apexes.size(), 3u);
  // Sampled every 0.1 ms, an apex is missed by at most g Δt²/8 ≈ 1.2e-8 m.
  for (std::size_t k = 0; k < 3; ++k)
    EXPECT_NEAR(apexes[k], expected[k + 1], 2e-8) << k;
  // At rest after t∞ = t₁ + 2 e v₁ / (g (1 − e)) = 0.4515 + 3.612 s.
  const double t1 = std::sqrt(2 / kG), v1 = std::sqrt(2 * kG);
  const double tRest = t1 + 2 * 0.8 * v1 / (kG * 0.2);
  const ReferenceTrajectory late = buildAnalyticReference(
      scene, analytic("bouncing_ball", R"({"restitution": 0.8})"), {tRest + 0.01, 6.0}, 0);
  EXPECT_NEAR(late.samples[0].bodies[1].position.y(), 0.1, 1e-12);
  EXPECT_EQ(late.samples[1].bodies[1].velocity.norm(), 0.0);
}

TEST(BouncingBallReference, TakesRestitutionFromThePairMaterial) {
  pbd::Scene scene = dropScene();
  scene.rigidBodies[0].restitution = 0.9;
  scene.rigidBodies[1].restitution = 0.5;
  const double e = scene.pairMaterial(1, 0).restitution;
  const ReferenceTrajectory byDefault =
      buildAnalyticReference(scene, analytic("bouncing_ball"), {0.9}, 0);
  const ReferenceTrajectory explicitE = buildAnalyticReference(
      scene, analytic("bouncing_ball", R"({"restitution": )" + std::to_string(e) + "}"), {0.9}, 0);
  EXPECT_NEAR(byDefault.samples[0].bodies[1].position.y(),
              explicitE.samples[0].bodies[1].position.y(), 1e-6);
  EXPECT_NE(byDefault.description.find("e = " + std::to_string(e).substr(0, 4)), std::string::npos);
}

TEST(AnalyticReferences, ListEveryModel) {
  std::vector<std::string> names;
  for (const auto& [name, summary] : analyticReferenceModels()) {
    names.push_back(name);
    EXPECT_FALSE(summary.empty()) << name;
  }
  for (const char* model :
       {"projectile", "free_fall", "pendulum", "simple_pendulum", "harmonic_oscillator",
        "torque_free_symmetric", "torque_free_asymmetric", "sliding_block", "rolling_sphere",
        "bowling_ball", "bouncing_ball"})
    EXPECT_NE(std::find(names.begin(), names.end(), model), names.end()) << model;
}

TEST(AnalyticReferences, ExplainBadModelsParametersAndTimes) {
  const pbd::Scene scene = dropScene();
  EXPECT_EQ(errorOf([&] {
              buildAnalyticReference(scene, analytic("parabola"), {0.0}, 0);
            }).rfind("analytic reference 'parabola': unknown model (known: projectile, ", 0),
            0u);
  EXPECT_EQ(
      errorOf([&] {
        buildAnalyticReference(scene, analytic("bouncing_ball", R"({"restitutoin": 1})"), {0.0}, 0);
      }).rfind("analytic reference 'bouncing_ball': unknown parameter 'restitutoin' (known: ", 0),
      0u);
  EXPECT_EQ(errorOf([&] {
              buildAnalyticReference(scene, analytic("bouncing_ball", R"({"restitution": 1.5})"),
                                     {0.0}, 0);
            }),
            "analytic reference 'bouncing_ball': parameter 'restitution': expected a number in "
            "[0, 1]");
  EXPECT_NE(errorOf([&] {
              buildAnalyticReference(scene, analytic("free_fall"), {0.2, 0.1}, 0);
            }).find("earlier than the one before"),
            std::string::npos);
  EXPECT_NE(errorOf([&] {
              buildAnalyticReference(scene, analytic("bouncing_ball", "[1, 2]"), {0.0}, 0);
            }).find("expected an object"),
            std::string::npos);
  pbd::Scene two = scene;
  two.rigidBodies.push_back(sphereBody(2, 0.1, Vector3(1, 1.1, 0), 1000));
  EXPECT_EQ(errorOf([&] { buildAnalyticReference(two, analytic("bouncing_ball"), {0.0}, 0); }),
            "analytic reference 'bouncing_ball': parameter 'body': expected the scene id of the "
            "body (the scene has 2 dynamic bodies)");
  EXPECT_EQ(buildAnalyticReference(
                two, analytic("bouncing_ball", R"({"body": 2, "restitution": 0.5})"), {0.0}, 0)
                .bodies,
            (std::vector<bool>{false, false, true}));
}

}  // namespace
}  // namespace pbdval
