// Particle distance constraints (constraints/particle_distance.h), PBD and XPBD: the gradient
// against central differences, the rest state, rigid-motion invariance and momentum; in the
// world: the XPBD oscillator's period 2π√(m/k) whatever the iteration count (the XPBD paper's
// test), XPBD's static stretch m g / k against PBD's iteration-dependent one (closed forms),
// the tension of a hanging chain against the weight below it, and the cloth edges the loader's
// triangle models give.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

#include "common/tolerances.h"
#include "pbd/constraints/particle_distance.h"
#include "pbd/model/world.h"

namespace pbd {
namespace {

const Real kPi = Real(EIGEN_PI);
const Vector3 kP1(0.3, -0.2, 0.7), kP2(-0.4, 0.5, 0.1);

TEST(ParticleDistance, GradientMatchesCentralDifferences) {
  const Real length = Real(0.9);
  const Vector3 n = (kP1 - kP2).normalized();  // ∇_{p₁}C = n, ∇_{p₂}C = −n
  const Real h = test::finiteDifferenceStep();
  for (int axis = 0; axis < 3; ++axis) {
    const Vector3 e = h * Vector3::Unit(axis);
    const Real d1 = (particleDistanceValue(kP1 + e, kP2, length) -
                     particleDistanceValue(kP1 - e, kP2, length)) /
                    (2 * h);
    const Real d2 = (particleDistanceValue(kP1, kP2 + e, length) -
                     particleDistanceValue(kP1, kP2 - e, length)) /
                    (2 * h);
    EXPECT_NEAR(d1, n(axis), test::finiteDifferenceTolerance());
    EXPECT_NEAR(d2, -n(axis), test::finiteDifferenceTolerance());
  }
}

TEST(ParticleDistance, RestStateHasNoErrorAndNoCorrection) {
  const Real rest = (kP1 - kP2).norm();
  EXPECT_EQ(particleDistanceValue(kP1, kP2, rest), 0);
  const DistanceCorrection pbd = particleDistancePbd(kP1, kP2, 2, 3, rest, 1);
  const DistanceCorrection xpbd = particleDistanceXpbd(kP1, kP2, 2, 3, rest, 1e3, 1e-3, 0);
  EXPECT_EQ(pbd.first, Vector3::Zero());
  EXPECT_EQ(pbd.second, Vector3::Zero());
  EXPECT_EQ(xpbd.first, Vector3::Zero());
  EXPECT_EQ(xpbd.multiplier, 0);
}

TEST(ParticleDistance, RigidMotionsLeaveTheErrorAndRotateTheCorrection) {
  const Real rest = Real(0.5);
  const Quaternion q(AngleAxis(1.1, Vector3(1, -2, 0.5).normalized()));
  const Vector3 t(3, -1, 2);
  // Round-off of |p₁ − p₂| after a rotation and translation of O(1) coordinates: a few ε.
  const Real tolerance = 10 * kEpsilon;
  EXPECT_NEAR(particleDistanceValue(q * kP1 + t, q * kP2 + t, rest),
              particleDistanceValue(kP1, kP2, rest), tolerance);
  const DistanceCorrection c = particleDistanceXpbd(kP1, kP2, 2, 3, rest, 50, 1e-2, 0.01);
  const DistanceCorrection moved =
      particleDistanceXpbd(q * kP1 + t, q * kP2 + t, 2, 3, rest, 50, 1e-2, 0.01);
  EXPECT_LT((moved.first - q * c.first).norm(), tolerance);
  EXPECT_LT((moved.second - q * c.second).norm(), tolerance);
}

TEST(ParticleDistance, CorrectionsConserveMomentum) {
  const Real w1 = 2, w2 = Real(0.25);  // masses 0.5 and 4
  for (const DistanceCorrection& c : {particleDistancePbd(kP1, kP2, w1, w2, 0.4, 0.7),
                                      particleDistanceXpbd(kP1, kP2, w1, w2, 0.4, 80, 1e-2, 0)}) {
    EXPECT_GT(c.first.norm(), 0.01);
    // m₁Δp₁ + m₂Δp₂ = 0 up to round-off of O(1) products.
    EXPECT_LT((c.first / w1 + c.second / w2).norm(), 10 * kEpsilon);
  }
  // A stiff XPBD constraint (α̃ → 0) is the exact projection, PBD with k = 1.
  const DistanceCorrection exact = particleDistancePbd(kP1, kP2, w1, w2, 0.4, 1);
  const DistanceCorrection stiff = particleDistanceXpbd(kP1, kP2, w1, w2, 0.4, 1e12, 1e-2, 0);
  EXPECT_LT((exact.first - stiff.first).norm(), 1e-7);  // α̃/(w₁+w₂) = 10⁻⁸/2.25 relative
}

// A particle of mass m on a constraint of stiffness k from a static particle, no gravity unless
// given: a harmonic oscillator along x.
World oscillator(Real mass, Real stiffness, bool xpbd, int iterations, Real stretch,
                 const Vector3& gravity = Vector3::Zero()) {
  Scene scene;
  scene.simulation.gravitation = gravity;
  scene.simulation.timeStepSize = Real(0.005);
  scene.simulation.subSteps = 5;
  scene.simulation.maxIterations = iterations;
  const Vector3 direction = gravity.isZero() ? Vector3::UnitX() : Vector3(gravity.normalized());
  scene.particles.push_back({Vector3::Zero(), Vector3::Zero(), 0});
  scene.particles.push_back({(1 + stretch) * direction, Vector3::Zero(), mass});
  World world = buildWorld(scene);
  ParticleDistanceConstraint c;
  c.particle1 = 0;
  c.particle2 = 1;
  c.restLength = 1;
  c.xpbd = xpbd;
  c.stiffness = stiffness;
  world.constraints.particleDistances.push_back(c);
  return world;
}

// The period from the upward zero crossings of x − L, linearly interpolated between steps.
Real measuredPeriod(World& world, Real duration) {
  std::vector<Real> crossings;
  Real previous = world.bodies.particles.position[1].x() - 1;
  while (world.time < duration) {
    world.step();
    const Real now = world.bodies.particles.position[1].x() - 1;
    if (previous < 0 && now >= 0)
      crossings.push_back(world.time - world.settings.timeStepSize * now / (now - previous));
    previous = now;
  }
  if (crossings.size() < 2) return 0;
  return (crossings.back() - crossings.front()) / Real(crossings.size() - 1);
}

TEST(ParticleDistanceWorld, XpbdOscillatorPeriodIsTwoPiRootMOverKForEveryIterationCount) {
  const Real mass = 1, stiffness = 100;  // ω = 10 rad/s, T = 0.628 s
  const Real period = 2 * kPi * std::sqrt(mass / stiffness);
  for (int iterations : {1, 4, 16}) {
    World world = oscillator(mass, stiffness, true, iterations, Real(0.01));
    // Backward Euler's phase per substep is atan(ω h_s) (ω h_s = 0.01): a period error of
    // (ω h_s)²/3 ≈ 3·10⁻⁵; the crossings interpolated between 5 ms steps add O((ω h)²) ≈ 10⁻³
    // at most. Allowed: 1 %.
    const Real measured = measuredPeriod(world, 4);
    std::printf("  XPBD oscillator, %2d iterations: period %.6f s (2 pi sqrt(m/k) = %.6f s)\n",
                iterations, double(measured), double(period));
    EXPECT_NEAR(measured, period, 0.01 * period) << iterations << " iterations";
  }
}

TEST(ParticleDistanceWorld, XpbdStretchIsMgOverKAndPbdStretchDependsOnIterations) {
  const Real mass = Real(0.5), g = Real(9.81);
  const Vector3 gravity(0, -g, 0);
  auto meanStretch = [](World& world, Real from, Real to) {
    Real sum = 0;
    int count = 0;
    while (world.time < to) {
      world.step();
      if (world.time > from) {
        sum += world.bodies.particles.position[1].norm() - 1;
        ++count;
      }
    }
    return sum / count;
  };
  // XPBD: the fixed point of every substep is the static stretch m g / k, whatever the
  // iterations. It oscillates about it (ω = 20 rad/s, lightly damped): the mean over 3 s, about
  // ten periods, is within 1 % of it (the oscillation's share of a partial period).
  const Real stiffness = 200;
  for (int iterations : {1, 8}) {
    World world = oscillator(mass, stiffness, true, iterations, 0, gravity);
    const Real stretch = meanStretch(world, 0, 3);
    std::printf("  XPBD hanging particle, %d iterations: stretch %.6g m (m g / k = %.6g m)\n",
                iterations, double(stretch), double(mass * g / stiffness));
    EXPECT_NEAR(stretch, mass * g / stiffness, 0.01 * mass * g / stiffness)
        << iterations << " iterations";
  }
  // PBD with k = 0.5: each substep's prediction adds g h_s² to the error and n iterations keep
  // a fraction (1 − k)ⁿ of it, so the stretch settles at (1 − k)ⁿ g h_s² / (1 − (1 − k)ⁿ):
  // g h_s² with one iteration, g h_s²/255 with eight. Independent of the mass: PBD's k is not a
  // stiffness.
  const Real substep = Real(0.001);
  for (int iterations : {1, 8}) {
    const Real kept = std::pow(Real(0.5), Real(iterations));
    const Real expected = kept * g * substep * substep / (1 - kept);
    // Double-only (the last case; everything above has run): with eight iterations the stretch
    // is g h_s²/255 = 3.8e-8 m on a link of 1 m, a third of float's ulp at 1 m (1.2e-7 m), so
    // |x| − 1 rounds to 0 in float.
    if (sizeof(Real) < 8 && iterations == 8)
      GTEST_SKIP() << "needs double precision: the 8-iteration stretch g h^2/255 = 3.8e-8 m is "
                      "below float's ulp of 1.2e-7 m at the 1 m link length";
    World world = oscillator(mass, Real(0.5), false, iterations, 0, gravity);
    const Real stretch = meanStretch(world, 0.5, 1);
    std::printf(
        "  PBD hanging particle, k = 0.5, %d iterations: stretch %.6g m (closed form %.6g m)\n",
        iterations, double(stretch), double(expected));
    EXPECT_NEAR(stretch, expected, 0.01 * expected) << iterations << " iterations";
  }
}

TEST(ParticleDistanceWorld, HangingChainTensionAtTheTopIsTheWeightBelow) {
  // 20 particles of 0.1 kg hang 5 cm apart below a static one, XPBD links of 10⁴ N/m. Over a
  // window the mean of the top link's tension equals the chain's weight: the chain's momentum
  // is bounded, so the mean of the net force on it vanishes (its change over the window,
  // ≤ 2·10⁻³ kg·m/s here, divided by 2 s, is far below 1 % of 19.6 N).
  Scene scene;
  scene.simulation.timeStepSize = Real(0.005);
  scene.simulation.subSteps = 5;
  scene.simulation.maxIterations = 2;
  const int count = 20;
  const Real mass = Real(0.1), spacing = Real(0.05);
  for (int i = 0; i <= count; ++i)
    scene.particles.push_back({Vector3(0, -spacing * i, 0), Vector3::Zero(), i == 0 ? 0 : mass});
  World world = buildWorld(scene);
  for (int i = 0; i < count; ++i) {
    ParticleDistanceConstraint c;
    c.particle1 = i;
    c.particle2 = i + 1;
    c.restLength = spacing;
    c.xpbd = true;
    c.stiffness = 1e4;
    world.constraints.particleDistances.push_back(c);
  }
  const Real substep = world.settings.timeStepSize / Real(world.settings.subSteps);
  std::vector<Real> sums(std::size_t(count), 0);
  int samples = 0;
  while (world.time < 2.5) {
    world.step();
    if (world.time > 0.5) {
      for (int i = 0; i < count; ++i)
        sums[std::size_t(i)] += particleDistanceTension(
            world.constraints.particleDistances[std::size_t(i)].multiplier, substep);
      ++samples;
    }
  }
  // Every link carries the particles below it: link i holds count − i of them. For the lower
  // links the momentum term is a larger share of a smaller weight (the bottom particle's
  // m·v ≲ 0.01 kg·m/s over 2 s is 0.5 % of 0.98 N): allowed 2 %.
  std::printf(
      "  hanging chain: top link %.5f N (weight below %.5f N), bottom link %.5f N (%.5f N)\n",
      double(sums.front() / samples), double(count * mass * Real(9.81)),
      double(sums.back() / samples), double(mass * Real(9.81)));
  for (int i = 0; i < count; ++i) {
    const Real weight = Real(count - i) * mass * Real(9.81);
    EXPECT_NEAR(sums[std::size_t(i)] / samples, weight, (i == 0 ? 0.01 : 0.02) * weight)
        << "link " << i;
  }
}

// The chain's total static stretch, Σ_links (weight below)/k = m g/k · n(n+1)/2, from the mean
// length over a window: XPBD reaches it whatever the iteration count; PBD's stretch (k = 1, a
// rigid link in the limit) is set by the iterations instead.
Real chainStretch(bool xpbd, int iterations) {
  Scene scene;
  scene.simulation.timeStepSize = Real(0.005);
  scene.simulation.subSteps = 5;
  scene.simulation.maxIterations = iterations;
  const int count = 20;
  for (int i = 0; i <= count; ++i)
    scene.particles.push_back(
        {Vector3(0, -Real(0.05) * i, 0), Vector3::Zero(), i == 0 ? 0 : Real(0.1)});
  World world = buildWorld(scene);
  for (int i = 0; i < count; ++i) {
    ParticleDistanceConstraint c;
    c.particle1 = i;
    c.particle2 = i + 1;
    c.restLength = Real(0.05);
    c.xpbd = xpbd;
    c.stiffness = xpbd ? Real(1e4) : Real(1);
    world.constraints.particleDistances.push_back(c);
  }
  Real sum = 0;
  int samples = 0;
  while (world.time < 2.5) {
    world.step();
    if (world.time > 0.5) {
      sum += -world.bodies.particles.position.back().y() - count * Real(0.05);
      ++samples;
    }
  }
  return sum / samples;
}

TEST(ParticleDistanceWorld, XpbdChainStretchIsTheClosedFormAndPbdsIsSetByIterations) {
  const Real expected = Real(0.1) * Real(9.81) / Real(1e4) * 20 * 21 / 2;  // 20.6 mm
  std::vector<Real> xpbd, pbd;
  for (int iterations : {1, 4, 16}) {
    xpbd.push_back(chainStretch(true, iterations));
    pbd.push_back(chainStretch(false, iterations));
    std::printf(
        "  chain of 20, %2d iterations: XPBD stretch %.6g m (closed form %.6g m), "
        "PBD k = 1: %.6g m\n",
        iterations, double(xpbd.back()), double(expected), double(pbd.back()));
  }
  // XPBD converges to the implicit step's solution as the iterations grow: with 4 and 16 the
  // stretch is the closed form within the window's share of the oscillation (0.5 % allowed;
  // 0.09 % measured) and the same to 0.1 %. One Gauss–Seidel sweep down a 20-link chain is not
  // converged: it is softer, by less than 10 % (6 % measured).
  EXPECT_NEAR(xpbd[1], expected, 0.005 * expected);
  EXPECT_NEAR(xpbd[2], expected, 0.005 * expected);
  EXPECT_NEAR(xpbd[2], xpbd[1], 0.001 * expected);
  EXPECT_NEAR(xpbd[0], expected, 0.1 * expected);
  // PBD with k = 1 has no stiffness: what is left of the stretch is the error the sweeps leave,
  // falling about as 1/n (each fourfold increase divides it by about 4; at least 3 required).
  EXPECT_GT(pbd[0] / pbd[1], 3.0);
  EXPECT_GT(pbd[1] / pbd[2], 3.0);
}

TEST(ParticleDistanceWorld, ClothEdgesComeFromTheTriangleModels) {
  // Two triangles sharing an edge: 5 edges, the edge 0–1 between the two static particles 0 and
  // 1 included (the seed keeps it: it moves nothing but takes its particles in a colour group).
  // Only clothSimulationMethod 1 and 4 make constraints, with cloth_stiffness.
  Scene scene;
  TriangleModelDesc cloth;
  cloth.mesh.vertices = {Vector3(0, 0, 0), Vector3(1, 0, 0), Vector3(0, 0, 1), Vector3(1, 0, 1)};
  cloth.mesh.triangles = {{0, 1, 2}, {1, 3, 2}};
  scene.triangleModels.push_back(cloth);
  for (int i = 0; i < 4; ++i)
    scene.particles.push_back(
        {cloth.mesh.vertices[std::size_t(i)], Vector3::Zero(), i < 2 ? Real(0) : Real(1)});
  scene.simulation.clothSimulationMethod = 4;
  // Unset, the stiffness is the seed's forced default: 10⁵ N/m for XPBD distance constraints.
  EXPECT_EQ(buildWorld(scene).constraints.particleDistances.front().stiffness, Real(1e5));
  scene.simulation.cloth_stiffness = 300;
  for (int method : {0, 1, 2, 3, 4}) {
    scene.simulation.clothSimulationMethod = method;
    const World world = buildWorld(scene);
    const std::size_t expected = method == 1 || method == 4 ? 5u : 0u;
    ASSERT_EQ(world.constraints.particleDistances.size(), expected)
        << "clothSimulationMethod " << method;
    for (const ParticleDistanceConstraint& c : world.constraints.particleDistances) {
      EXPECT_EQ(c.xpbd, method == 4);
      EXPECT_EQ(c.stiffness, 300);
      EXPECT_EQ(c.restLength, (cloth.mesh.vertices[std::size_t(c.particle1)] -
                               cloth.mesh.vertices[std::size_t(c.particle2)])
                                  .norm());
    }
  }
  // The seed's IndexedFaceMesh order and orientation: per triangle (t₀, t₁), (t₁, t₂), (t₂, t₀),
  // each side where it first appears.
  scene.simulation.clothSimulationMethod = 1;
  const std::vector<ParticleDistanceConstraint> listed = deformableDistanceConstraints(scene);
  const std::vector<std::array<int, 2>> seedOrder = {{0, 1}, {1, 2}, {2, 0}, {1, 3}, {3, 2}};
  ASSERT_EQ(listed.size(), seedOrder.size());
  for (std::size_t k = 0; k < listed.size(); ++k) {
    EXPECT_EQ(listed[k].particle1, seedOrder[k][0]) << "edge " << k;
    EXPECT_EQ(listed[k].particle2, seedOrder[k][1]) << "edge " << k;
  }
}

}  // namespace
}  // namespace pbd
