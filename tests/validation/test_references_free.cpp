// Analytic references without contact (projectile, pendulum, harmonic oscillator, torque-free
// bodies), each against an integration written here, independently of the reference's code.
#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <functional>

#include "tests/validation/fixtures.h"
#include "validation/measure/numerics.h"
#include "validation/measure/references/pendulum.h"
#include "validation/measure/references/reference.h"

namespace pbdval {
namespace {

using pbd::JointType;
using pbd::test::boxBody;
using test::kPi;
using test::turn;

using test::analytic;
using test::errorOf;
using test::timesUpTo;

// ---- Projectile ----

pbd::Scene thrownBox(const Vector3& spin) {
  pbd::Scene scene = test::emptyScene();
  scene.rigidBodies.push_back(boxBody(1, Vector3(0.2, 0.1, 0.3), Vector3(0, 1, 0), 500));
  scene.rigidBodies[0].velocity = Vector3(3, 8, 1);
  scene.rigidBodies[0].angularVelocity = spin;
  return scene;
}

TEST(ProjectileReference, MatchesRk4OfXddEqualsG) {
  const pbd::Scene scene = thrownBox(Vector3::Zero());
  const std::vector<double> times = timesUpTo(1.5, 0.01);
  const ReferenceTrajectory r = buildAnalyticReference(scene, analytic("projectile"), times, 0);
  // RK4 on (x, v)′ = (v, g) is exact for this quadratic motion: only round-off remains.
  Vector3 x = scene.rigidBodies[0].initialCenterOfMass(), v = scene.rigidBodies[0].velocity;
  const Vector3 g = scene.simulation.gravitation;
  const double h = 0.01;
  for (std::size_t k = 0; k < times.size(); ++k) {
    EXPECT_NEAR((r.samples[k].bodies[0].position - x).norm(), 0, 1e-12) << "t = " << times[k];
    EXPECT_NEAR((r.samples[k].bodies[0].velocity - v).norm(), 0, 1e-12);
    const Vector3 k1x = v, k2x = v + h / 2 * g, k3x = v + h / 2 * g, k4x = v + h * g;
    x += h / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
    v += h * g;
  }
  EXPECT_TRUE(r.hasRotation);  // no spin: the orientation stays the initial one
  EXPECT_EQ(r.bodies, std::vector<bool>{true});
}

TEST(ProjectileReference, SemiImplicitEulerFormMatchesTheSteppedScheme) {
  const pbd::Scene scene = thrownBox(Vector3(0, 2, 1));
  const double h = 0.001;  // the run's effective step (e.g. 5 ms / 5 substeps)
  const std::vector<double> times = timesUpTo(1.5, 0.01);
  const ReferenceTrajectory r = buildAnalyticReference(
      scene, analytic("projectile", R"({"form": "semi_implicit_euler"})"), times, h);
  EXPECT_FALSE(r.hasRotation);  // a spinning box: rotation is not this model's business
  Vector3 x = scene.rigidBodies[0].initialCenterOfMass(), v = scene.rigidBodies[0].velocity;
  const Vector3 g = scene.simulation.gravitation;
  for (std::size_t k = 0, step = 0; k < times.size(); ++k) {
    for (; double(step) * h < times[k] - 1e-9; ++step) {
      v += h * g;
      x += h * v;
    }
    // 1500 steps of O(10) numbers: accumulated round-off ~1e-13.
    EXPECT_NEAR((r.samples[k].bodies[0].position - x).norm(), 0, 1e-11) << "t = " << times[k];
  }
  // The bias against the parabola is ½ g h t (validation/measure/references/ballistic.h): 7.4 mm
  // at 1.5 s.
  const ReferenceTrajectory continuous =
      buildAnalyticReference(scene, analytic("free_fall"), times, h);
  const double bias =
      (r.samples.back().bodies[0].position - continuous.samples.back().bodies[0].position).norm();
  EXPECT_NEAR(bias, 0.5 * 9.81 * h * 1.5, 1e-12);
}

TEST(ProjectileReference, NeedsTheStepForTheDiscreteFormAndRejectsUnknownForms) {
  const pbd::Scene scene = thrownBox(Vector3::Zero());
  EXPECT_NE(errorOf([&] {
              const ReferenceSpec spec =
                  analytic("projectile", R"({"form": "semi_implicit_euler"})");
              buildAnalyticReference(scene, spec, {0.0}, 0);
            }).find("parameter 'form'"),
            std::string::npos);
  EXPECT_EQ(errorOf([&] {
              buildAnalyticReference(scene, analytic("projectile", R"({"form": "rk4"})"), {0.0}, 0);
            }),
            "analytic reference 'projectile': parameter 'form': expected \"continuous\" or "
            "\"semi_implicit_euler\"");
}

TEST(ProjectileReference, DescribesTheNamedBodiesOnly) {
  pbd::Scene scene = thrownBox(Vector3::Zero());
  scene.rigidBodies.push_back(boxBody(2, Vector3(0.1, 0.1, 0.1), Vector3(5, 0, 0), 500));
  ReferenceSpec spec = analytic("projectile");
  spec.bodyIds = {2};
  const ReferenceTrajectory r = buildAnalyticReference(scene, spec, {0.0, 0.5}, 0);
  EXPECT_EQ(r.bodies, (std::vector<bool>{false, true}));
  // Body 1 (not described) holds its initial state; body 2 falls ½ g t² = 1.22625 m.
  EXPECT_EQ(r.samples[1].bodies[0].position, scene.rigidBodies[0].initialCenterOfMass());
  EXPECT_NEAR(r.samples[1].bodies[1].position.y(), -0.5 * 9.81 * 0.25, 1e-15);
}

// ---- Pendulum ----

/// The fixture's hinge pendulum: a 0.4 kg box 0.1 × 0.4 × 0.1 m hanging from (0, 2, 0) with its
/// centre at (0.6, 1.2, 0): arm d = 1 m, hinge axis z. I_cm,z = 0.4 (0.1² + 0.4²)/12.
struct HingePendulum {
  pbd::Scene scene = pbd::test::pendulumScene(JointType::Hinge);
  double mass = 0.4;
  double inertiaAboutPivot = 0.4 * 0.17 / 12 + 0.4 * 1.0;
};

/// Velocity-Verlet integration (written for the test) of φ″ = −(c) cos φ for the arm angle φ
/// from +x (gravity −y): returns φ at `times`.
std::vector<double> verletArmAngle(double c, double phi0, double rate0,
                                   const std::vector<double>& times, double h) {
  std::vector<double> out;
  double phi = phi0, rate = rate0, t = 0;
  for (const double target : times) {
    while (t < target - 1e-12) {
      const double step = std::min(h, target - t);
      rate += 0.5 * step * (-c * std::cos(phi));
      phi += step * rate;
      rate += 0.5 * step * (-c * std::cos(phi));
      t += step;
    }
    out.push_back(phi);
  }
  return out;
}

TEST(PendulumReference, MatchesAVerletIntegrationOfTheArmAngle) {
  const HingePendulum p;
  const std::vector<double> times = timesUpTo(3.0, 0.01);
  const ReferenceTrajectory r = buildAnalyticReference(p.scene, analytic("pendulum"), times, 0);
  const double c = p.mass * 9.81 * 1.0 / p.inertiaAboutPivot;  // m g d / I_p
  const double phi0 = std::atan2(-0.8, 0.6);
  const std::vector<double> phi = verletArmAngle(c, phi0, 0, times, 1e-5);
  for (std::size_t k = 0; k < times.size(); ++k) {
    const Vector3 expected = Vector3(0, 2, 0) + Vector3(std::cos(phi[k]), std::sin(phi[k]), 0);
    // Verlet's global error O(h²) with h = 1e-5 s: ~1e-9 rad over 3 s.
    EXPECT_NEAR((r.samples[k].bodies[1].position - expected).norm(), 0, 1e-8) << times[k];
    EXPECT_NEAR(twistAngle(r.samples[k].bodies[1].rotation, Vector3::UnitZ()), phi[k] - phi0, 1e-8);
  }
  EXPECT_TRUE(r.hasRotation);
  EXPECT_EQ(r.bodies, (std::vector<bool>{false, true}));
}

TEST(PendulumReference, SimplePendulumIgnoresTheBodysOwnInertia) {
  const HingePendulum p;
  const std::vector<double> times = timesUpTo(2.0, 0.05);
  const ReferenceTrajectory r =
      buildAnalyticReference(p.scene, analytic("simple_pendulum"), times, 0);
  const std::vector<double> phi = verletArmAngle(9.81, std::atan2(-0.8, 0.6), 0, times, 1e-5);
  for (std::size_t k = 0; k < times.size(); ++k)
    EXPECT_NEAR(
        (r.samples[k].bodies[1].position - Vector3(std::cos(phi[k]), 2 + std::sin(phi[k]), 0))
            .norm(),
        0, 1e-8);
}

TEST(PendulumReference, AcceptsAnExplicitPivotAndAxisAndAConsistentInitialSpin) {
  HingePendulum p;
  p.scene.joints.clear();
  // Started with φ′ = 1.5 rad/s: v₀ = ω × r₀ = 1.5 ẑ × (0.6, −0.8, 0) = (1.2, 0.9, 0).
  p.scene.rigidBodies[1].angularVelocity = Vector3(0, 0, 1.5);
  p.scene.rigidBodies[1].velocity = Vector3(1.2, 0.9, 0);
  const std::vector<double> times = timesUpTo(1.0, 0.05);
  const ReferenceTrajectory r = buildAnalyticReference(
      p.scene, analytic("pendulum", R"({"pivot": [0, 2, 0], "axis": [0, 0, 2]})"), times, 0);
  const double c = p.mass * 9.81 / p.inertiaAboutPivot;
  const std::vector<double> phi = verletArmAngle(c, std::atan2(-0.8, 0.6), 1.5, times, 1e-5);
  EXPECT_NEAR(r.samples.back().bodies[1].position.x(), std::cos(phi.back()), 1e-8);
  EXPECT_NEAR(r.samples.back().bodies[1].position.y(), 2 + std::sin(phi.back()), 1e-8);
}

TEST(PendulumReference, ExplainsWhatItCannotInfer) {
  HingePendulum p;
  p.scene.joints.clear();
  EXPECT_EQ(errorOf([&] {
              buildAnalyticReference(p.scene, analytic("pendulum"), {0.0}, 0);
            }).rfind("analytic reference 'pendulum': parameter 'pivot': expected [x, y, z]", 0),
            0u);
  const HingePendulum hinged;
  EXPECT_EQ(errorOf([&] {
              buildAnalyticReference(hinged.scene, analytic("pendulum", R"({"rk4Step": -1})"),
                                     {0.0}, 0);
            }),
            "analytic reference 'pendulum': parameter 'rk4Step': expected a positive number");
  EXPECT_EQ(errorOf([&] {
              buildAnalyticReference(p.scene, analytic("pendulum", R"({"pivot": [0, 2]})"), {0.0},
                                     0);
            }),
            "analytic reference 'pendulum': parameter 'pivot': expected an array of 3 numbers");
  p.scene.rigidBodies[1].velocity = Vector3(0, 0, 1);  // not a rotation about the pivot
  EXPECT_NE(errorOf([&] {
              buildAnalyticReference(p.scene, analytic("pendulum", R"({"pivot": [0, 2, 0]})"),
                                     {0.0}, 0);
            }).find("not a rotation about the pivot"),
            std::string::npos);
}

/// K(k) by composite Simpson quadrature of ∫₀^{π/2} dφ/√(1 − k² sin²φ) (smooth for k < 1).
double simpsonEllipticK(double k) {
  const int n = 2000;
  const double h = kPi / 2 / n;
  double sum = 0;
  for (int i = 0; i <= n; ++i) {
    const double s = std::sin(i * h);
    const double f = 1 / std::sqrt(1 - k * k * s * s);
    sum += f * (i == 0 || i == n ? 1 : (i % 2 ? 4 : 2));
  }
  return sum * h / 3;
}

TEST(PendulumPeriod, IsTheEllipticIntegralFormula) {
  for (const double k : {0.0, 0.3, 0.7, 0.95})
    EXPECT_NEAR(completeEllipticK(k), simpsonEllipticK(k), 1e-11) << k;  // Simpson error ~h⁴
  EXPECT_NEAR(completeEllipticK(0.0), kPi / 2, 1e-15);
  // Small amplitudes: T = 2π/Ω₀ (1 + θ²/16 + 11θ⁴/3072 + O(θ⁶)); at θ = 0.01 the θ⁶ term is
  // ~1e-16 relative.
  EXPECT_NEAR(pendulumPeriod(2.0, 0.01), kPi * (1 + 1e-4 / 16 + 11e-8 / 3072), 1e-14);
}

TEST(PendulumPeriod, MatchesTheZeroCrossingsOfAnIntegratedSwing) {
  const HingePendulum p;
  const double c = p.mass * 9.81 / p.inertiaAboutPivot;
  // Released at rest, the pendulum next turns (φ′ changes sign) half a period later.
  const double phi0 = std::atan2(-0.8, 0.6);
  double phi = phi0, rate = 0, t = 0;
  const double h = 1e-6;
  double previousRate = 0;
  while (true) {
    rate += 0.5 * h * (-c * std::cos(phi));
    phi += h * rate;
    rate += 0.5 * h * (-c * std::cos(phi));
    t += h;
    if (t > 0.1 && previousRate * rate <= 0) break;
    previousRate = rate;
  }
  // The amplitude about the downward direction is |φ₀ + π/2| = 0.6435 rad.
  const double period = pendulumPeriod(std::sqrt(c), std::abs(phi0 + kPi / 2));
  EXPECT_NEAR(2 * t, period, 4 * h);  // turning point located to within a step
}

// ---- Harmonic oscillator ----

pbd::Scene oscillatorScene(JointType type, double stiffness, const Vector3& v0) {
  pbd::Scene scene = test::emptyScene();
  scene.rigidBodies.push_back(boxBody(0, Vector3(0.1, 0.1, 0.1), Vector3(0, 2, 0), 1000, false));
  scene.rigidBodies.push_back(boxBody(1, Vector3(0.2, 0.2, 0.2), Vector3(0, 1, 0), 1000));  // 8 kg
  scene.rigidBodies[1].velocity = v0;
  pbd::JointDesc j = pbd::test::makeJointDesc(type, 0, 1);
  j.position1 = Vector3(0, 2, 0);
  j.position2 = Vector3(0, 1.5, 0);
  j.axis = Vector3(0, 1, 0);
  j.stiffness = stiffness;
  scene.joints.push_back(j);
  return scene;
}

/// RK4 (written for the test) of s″ = −(k/m) s + a, s(0) = 0, s′(0) = u₀, sampled at `times`.
std::vector<double> rk4Oscillator(double k, double m, double a, double u0,
                                  const std::vector<double>& times) {
  std::vector<double> out;
  double s = 0, u = u0, t = 0;
  const double hMax = 1e-4;
  const auto acc = [&](double x) { return -k / m * x + a; };
  for (const double target : times) {
    while (t < target - 1e-12) {
      const double h = std::min(hMax, target - t);
      const double k1s = u, k1u = acc(s);
      const double k2s = u + h / 2 * k1u, k2u = acc(s + h / 2 * k1s);
      const double k3s = u + h / 2 * k2u, k3u = acc(s + h / 2 * k2s);
      const double k4s = u + h * k3u, k4u = acc(s + h * k3s);
      s += h / 6 * (k1s + 2 * k2s + 2 * k3s + k4s);
      u += h / 6 * (k1u + 2 * k2u + 2 * k3u + k4u);
      t += h;
    }
    out.push_back(s);
  }
  return out;
}

TEST(HarmonicOscillatorReference, SpringMatchesRk4) {
  // 8 kg on 200 N/m, released at rest length: ω = 5 rad/s; along u = −ŷ gravity adds +9.81.
  const pbd::Scene scene = oscillatorScene(JointType::RigidBodySpring, 200, Vector3::Zero());
  const std::vector<double> times = timesUpTo(3.0, 0.01);
  const ReferenceTrajectory r =
      buildAnalyticReference(scene, analytic("harmonic_oscillator"), times, 0);
  const std::vector<double> s = rk4Oscillator(200, 8, 9.81, 0, times);
  for (std::size_t k = 0; k < times.size(); ++k)
    // RK4 at ωh = 5e-4: global error ~1e-14 m; the closed form is exact.
    EXPECT_NEAR((r.samples[k].bodies[1].position - Vector3(0, 1 - s[k], 0)).norm(), 0, 1e-11);
  EXPECT_TRUE(r.hasRotation);
}

TEST(HarmonicOscillatorReference, DamperMatchesRk4WithAnInitialSpeed) {
  const pbd::Scene scene = oscillatorScene(JointType::Damper, 2000, Vector3(0, 0.5, 0));
  const std::vector<double> times = timesUpTo(2.0, 0.01);
  const ReferenceTrajectory r = buildAnalyticReference(
      scene, analytic("harmonic_oscillator", R"({"joint": "DamperJoints[0]"})"), times, 0);
  const std::vector<double> s = rk4Oscillator(2000, 8, -9.81, 0.5, times);  // u = +ŷ
  for (std::size_t k = 0; k < times.size(); ++k)
    EXPECT_NEAR((r.samples[k].bodies[1].position - Vector3(0, 1 + s[k], 0)).norm(), 0, 1e-11);
}

TEST(HarmonicOscillatorReference, RefusesMotionOffTheSpringLine) {
  const pbd::Scene scene = oscillatorScene(JointType::RigidBodySpring, 200, Vector3(0.1, 0, 0));
  EXPECT_NE(errorOf([&] {
              buildAnalyticReference(scene, analytic("harmonic_oscillator"), {0.0}, 0);
            }).find("initial velocity is not along the spring"),
            std::string::npos);
  EXPECT_EQ(errorOf([&] {
              buildAnalyticReference(
                  scene, analytic("harmonic_oscillator", R"({"joint": "HingeJoints[0]"})"), {0.0},
                  0);
            }).rfind("analytic reference 'harmonic_oscillator': parameter 'joint': expected", 0),
            0u);
}

// ---- Torque-free bodies ----

/// Scene-frame rotation S and ω of a free body integrated (for the test) in the world frame:
/// L constant, ω = I_w(S)⁻¹ L, Ṡ = [ω]× S, RK4 on the 9 entries of S.
struct WorldFrameSpinner {
  pbd::Matrix3 rotation;
  pbd::Matrix3 sceneInertia;  ///< R_p diag(I) R_pᵀ
  Vector3 momentum;

  Vector3 omegaOf(const pbd::Matrix3& s) const {
    return (s * sceneInertia * s.transpose()).inverse() * momentum;
  }
  pbd::Matrix3 rate(const pbd::Matrix3& s) const {
    const Vector3 w = omegaOf(s);
    pbd::Matrix3 cross;
    cross << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
    return cross * s;
  }
  void advance(double duration, double h) {
    const int steps = int(std::ceil(duration / h - 1e-9));
    const double dt = duration / steps;
    for (int i = 0; i < steps; ++i) {
      const pbd::Matrix3 k1 = rate(rotation);
      const pbd::Matrix3 k2 = rate(rotation + dt / 2 * k1);
      const pbd::Matrix3 k3 = rate(rotation + dt / 2 * k2);
      const pbd::Matrix3 k4 = rate(rotation + dt * k3);
      rotation += dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
    }
  }
};

void expectMatchesWorldFrameSpinner(const pbd::Scene& scene, const ReferenceTrajectory& r,
                                    const std::vector<double>& times, double tolerance) {
  const pbd::RigidBodyDesc& body = scene.rigidBodies[0];
  WorldFrameSpinner spinner;
  spinner.rotation = body.rotation.toRotationMatrix();
  const pbd::Matrix3 rp = body.massProperties.principalRotation.toRotationMatrix();
  spinner.sceneInertia = rp * body.massProperties.principalInertia.asDiagonal() * rp.transpose();
  spinner.momentum =
      spinner.rotation * spinner.sceneInertia * spinner.rotation.transpose() * body.angularVelocity;
  double t = 0;
  for (std::size_t k = 0; k < times.size(); ++k) {
    spinner.advance(times[k] - t, 2e-5);
    t = times[k];
    // The nearest rotation to the integrated matrix (its polar factor U Vᵀ).
    const Eigen::JacobiSVD<pbd::Matrix3> svd(spinner.rotation,
                                             Eigen::ComputeFullU | Eigen::ComputeFullV);
    const Quaternion expected(pbd::Matrix3(svd.matrixU() * svd.matrixV().transpose()));
    EXPECT_NEAR(geodesicAngle(r.samples[k].bodies[0].rotation, expected), 0, tolerance)
        << "t = " << times[k];
    EXPECT_NEAR((r.samples[k].bodies[0].angularVelocity - spinner.omegaOf(spinner.rotation)).norm(),
                0, 10 * tolerance);
  }
}

pbd::Scene spinningBody(const Vector3& moments, const Vector3& omega) {
  pbd::Scene scene = test::emptyScene();
  pbd::RigidBodyDesc body =
      boxBody(1, Vector3(0.2, 0.2, 0.6), Vector3(0, 5, 0), 100, true, turn(Vector3(1, 2, 0), 0.8));
  body.massProperties.principalInertia = moments;
  body.massProperties.principalRotation = turn(Vector3(0, 1, 1), 0.5);  // principal ≠ scene axes
  body.velocity = Vector3(1, 2, 0);
  body.angularVelocity = omega;
  scene.rigidBodies.push_back(body);
  return scene;
}

TEST(TorqueFreeReference, SymmetricTopMatchesAWorldFrameIntegration) {
  const pbd::Scene scene = spinningBody(Vector3(0.3, 0.3, 0.1), Vector3(1, 0.5, 3));
  const std::vector<double> times = timesUpTo(2.0, 0.1);
  const ReferenceTrajectory r =
      buildAnalyticReference(scene, analytic("torque_free_symmetric"), times, 0);
  // RK4 at h = 2e-5 s on |ω| ~ 10 rad/s: ~1e-13 rad; the closed form is exact.
  expectMatchesWorldFrameSpinner(scene, r, times, 1e-9);
  // The centre of mass is ballistic: x₀ + v₀ t + ½ g t².
  EXPECT_NEAR((r.samples.back().bodies[0].position - Vector3(2, 5 + 4 - 0.5 * 9.81 * 4, 0)).norm(),
              0, 1e-12);
}

TEST(TorqueFreeReference, SymmetricTopFindsTheSymmetryAxisAmongThePrincipalAxes) {
  const pbd::Scene scene = spinningBody(Vector3(0.05, 0.2, 0.2), Vector3(-2, 1, 0.5));
  const std::vector<double> times = timesUpTo(1.0, 0.1);
  expectMatchesWorldFrameSpinner(
      scene, buildAnalyticReference(scene, analytic("torque_free_symmetric"), times, 0), times,
      1e-9);
}

TEST(TorqueFreeReference, SymmetricModelRefusesAnAsymmetricBody) {
  const pbd::Scene scene = spinningBody(Vector3(0.1, 0.2, 0.3), Vector3(0, 5, 0));
  EXPECT_NE(errorOf([&] {
              buildAnalyticReference(scene, analytic("torque_free_symmetric"), {0.0}, 0);
            }).find("is not axisymmetric"),
            std::string::npos);
}

TEST(TorqueFreeReference, AsymmetricBodyGivesItsCentreOfMassAndOnRequestItsRotation) {
  // The Dzhanibekov case: spin mostly about the intermediate axis.
  const pbd::Scene scene = spinningBody(Vector3(0.1, 0.2, 0.3), Vector3(0.05, 5, 0.05));
  const std::vector<double> times = timesUpTo(3.0, 0.1);
  const ReferenceTrajectory plain =
      buildAnalyticReference(scene, analytic("torque_free_asymmetric"), times, 0);
  EXPECT_FALSE(plain.hasRotation);
  EXPECT_NE(plain.description.find("angular momentum"), std::string::npos);
  EXPECT_NEAR(
      (plain.samples.back().bodies[0].position - Vector3(3, 5 + 6 - 0.5 * 9.81 * 9, 0)).norm(), 0,
      1e-12);
  const ReferenceTrajectory integrated = buildAnalyticReference(
      scene, analytic("torque_free_asymmetric", R"({"integrateRotation": true})"), times, 0);
  EXPECT_TRUE(integrated.hasRotation);
  // Both integrations are ~1e-12 accurate; the unstable axis amplifies differences over 3 s.
  expectMatchesWorldFrameSpinner(scene, integrated, times, 1e-7);
}

}  // namespace
}  // namespace pbdval
