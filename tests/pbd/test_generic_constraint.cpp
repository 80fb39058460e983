// Generic particle constraints (constraints/generic_constraint.h): a generic distance
// constraint against the library's own particleDistancePbd (with the analytic gradient: to
// round-off; with central differences: to their O(h²) error); pinning a particle to a line
// (two components, linear: exact in one solve); singular K (static particles, redundant or
// vanishing components): no correction, no NaN; momentum for a translation-invariant C; the
// limits at construction; in a World, a hanging particle keeps its distance as with the
// built-in constraint (both step methods). The allocation-free step is in test_world.cpp
// (GenericConstraintWorld.StepAllocatesNothing, next to the counting allocator).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "common/tolerances.h"
#include "pbd/constraints/generic_constraint.h"
#include "pbd/constraints/particle_distance.h"
#include "pbd/model/world.h"

namespace pbd {
namespace {

const Vector3 kP1(0.3, -0.2, 0.7), kP2(-0.4, 0.5, 0.1);

// C = |x₀ − x₁| − L and its gradient (n, −n), n = (x₀ − x₁)/|x₀ − x₁|.
GenericParticleConstraint distanceConstraint(int a, int b, Real length, bool analyticGradient,
                                             Real stiffness = 1) {
  GenericValueFunction value = [length](const GenericPositions& x, GenericValue& c) {
    c(0) = (x.col(0) - x.col(1)).norm() - length;
  };
  GenericGradientFunction gradient;
  if (analyticGradient)
    gradient = [](const GenericPositions& x, GenericJacobian& j) {
      const Vector3 n = (x.col(0) - x.col(1)).normalized();
      j.block<1, 3>(0, 0) = n.transpose();
      j.block<1, 3>(0, 3) = -n.transpose();
    };
  return GenericParticleConstraint({a, b}, 1, value, gradient, stiffness);
}

GenericPositions positions(std::initializer_list<Vector3> points) {
  GenericPositions x = GenericPositions::Zero();
  int i = 0;
  for (const Vector3& p : points)
    x.col(i++) = p;
  return x;
}

std::array<Real, kGenericMaxParticles> inverseMasses(std::initializer_list<Real> w) {
  std::array<Real, kGenericMaxParticles> out{};
  std::size_t i = 0;
  for (Real wi : w)
    out[i++] = wi;
  return out;
}

TEST(GenericConstraint, DistanceMatchesTheBuiltInConstraint) {
  const Real length = Real(0.9);
  const Real w1 = 1, w2 = Real(0.4);
  const GenericPositions x = positions({kP1, kP2});
  for (Real stiffness : {Real(1), Real(0.3)}) {
    const DistanceCorrection expected = particleDistancePbd(kP1, kP2, w1, w2, length, stiffness);
    // The analytic gradient: the same formula, K = (w₁ + w₂) |n|², so a few roundings of the
    // O(0.1) corrections apart (16 ε).
    const GenericCorrection exact = genericConstraintPbd(
        distanceConstraint(0, 1, length, true, stiffness), x, inverseMasses({w1, w2}));
    ASSERT_TRUE(exact.applied);
    EXPECT_NEAR((exact.delta.col(0) - expected.first).norm(), 0, 16 * kEpsilon);
    EXPECT_NEAR((exact.delta.col(1) - expected.second).norm(), 0, 16 * kEpsilon);
    // Central differences: the Jacobian's error is (h²/6) ∂³C + O(ε/h) with h = ε^(1/3) (the
    // positions are below 1, so the step is not scaled), i.e. O(ε^(2/3)) for |x₀ − x₁| ≈ 1;
    // the corrections, linear in ∇C, carry it times |C| ≈ 0.2: within the finite-difference
    // tolerance 100 ε^(2/3).
    const GenericCorrection approximate = genericConstraintPbd(
        distanceConstraint(0, 1, length, false, stiffness), x, inverseMasses({w1, w2}));
    ASSERT_TRUE(approximate.applied);
    EXPECT_NEAR((approximate.delta.col(0) - expected.first).norm(), 0,
                test::finiteDifferenceTolerance());
    EXPECT_NEAR((approximate.delta.col(1) - expected.second).norm(), 0,
                test::finiteDifferenceTolerance());
    // ... and not to round-off: the difference is the finite differences' (it is nonzero).
    EXPECT_NE((approximate.delta.col(0) - expected.first).norm(), 0);
  }
}

// Pinning a particle to the line a + s u: C = (e₁·(x − a), e₂·(x − a)) with e₁, e₂, u
// orthonormal. C is linear, so one solve lands on the line: x' = a + u uᵀ (x − a).
TEST(GenericConstraint, TwoComponentLinePinProjectsOntoTheLineInOneSolve) {
  const Vector3 a(0.2, -0.1, 0.3);
  const Vector3 u = Vector3(1, 2, -0.5).normalized();
  const Vector3 e1 = u.unitOrthogonal();
  const Vector3 e2 = u.cross(e1);
  auto value = [a, e1, e2](const GenericPositions& x, GenericValue& c) {
    c(0) = e1.dot(x.col(0) - a);
    c(1) = e2.dot(x.col(0) - a);
  };
  auto gradient = [e1, e2](const GenericPositions&, GenericJacobian& j) {
    j.block<1, 3>(0, 0) = e1.transpose();
    j.block<1, 3>(1, 0) = e2.transpose();
  };
  const Vector3 start(0.9, 0.4, -0.6);
  const Vector3 expected = a + u * u.dot(start - a);
  for (bool analytic : {true, false}) {
    const GenericParticleConstraint pin(
        {0}, 2, value, analytic ? GenericGradientFunction(gradient) : GenericGradientFunction(), 1);
    const GenericCorrection c = genericConstraintPbd(pin, positions({start}), inverseMasses({2}));
    ASSERT_TRUE(c.applied);
    const Vector3 end = start + c.delta.col(0);
    // Analytic: round-off of O(1) numbers (16 ε). Central differences of a linear C have no
    // truncation error, only the cancellation O(ε/h) = O(ε^(2/3)).
    const Real tolerance = analytic ? 16 * kEpsilon : test::finiteDifferenceTolerance();
    EXPECT_NEAR((end - expected).norm(), 0, tolerance) << analytic;
    GenericValue after;
    pin.evaluate(positions({end}), after);
    EXPECT_NEAR(after.head(2).norm(), 0, tolerance) << analytic;
  }
}

void expectNoCorrection(const GenericCorrection& c) {
  EXPECT_FALSE(c.applied);
  EXPECT_TRUE(c.delta.allFinite());
  EXPECT_EQ(c.delta, GenericPositions::Zero());
}

TEST(GenericConstraint, SingularSystemGivesNoCorrectionAndNoNaN) {
  const GenericPositions x = positions({kP1, kP2});
  // Every particle static: K = 0.
  for (bool analytic : {true, false})
    expectNoCorrection(
        genericConstraintPbd(distanceConstraint(0, 1, 0.5, analytic), x, inverseMasses({0, 0})));
  // A redundant pair of components: C₂ = 2 C₁, K of rank 1 (a zero pivot, to round-off for
  // the analytic gradient and to the square of the finite differences' error without it).
  auto redundant = [](const GenericPositions& p, GenericValue& c) {
    c(0) = p(0, 0) + p(1, 0) - 1;
    c(1) = 2 * (p(0, 0) + p(1, 0)) - 2;
  };
  auto redundantGradient = [](const GenericPositions&, GenericJacobian& j) {
    j(0, 0) = j(0, 1) = 1;
    j(1, 0) = j(1, 1) = 2;
  };
  for (bool analytic : {true, false})
    expectNoCorrection(genericConstraintPbd(
        GenericParticleConstraint(
            {0}, 2, redundant,
            analytic ? GenericGradientFunction(redundantGradient) : GenericGradientFunction()),
        x, inverseMasses({1})));
  // Coinciding particles: the distance's gradient is NaN (0/0); no correction either.
  expectNoCorrection(genericConstraintPbd(distanceConstraint(0, 1, 0.5, true),
                                          positions({kP1, kP1}), inverseMasses({1, 1})));
  // A constant C (zero gradient): K = 0.
  auto constant = [](const GenericPositions&, GenericValue& c) { c(0) = 1; };
  expectNoCorrection(
      genericConstraintPbd(GenericParticleConstraint({0}, 1, constant), x, inverseMasses({1})));
}

TEST(GenericConstraint, SingularityThresholdIsScaleFree) {
  // The same line pin in kilometres and in micrometres, with masses of 10⁻⁶ and 10⁶ kg: the
  // seed's det K < 10⁻⁶ would reject some of them; the relative pivot test rejects none.
  for (Real scale : {Real(1e3), Real(1e-6)})
    for (Real w : {Real(1e-6), Real(1e6)}) {
      auto value = [scale](const GenericPositions& x, GenericValue& c) {
        c(0) = x(1, 0) / scale;  // a dimensionless pair of components, O(1/scale) gradient
        c(1) = x(2, 0) / scale;
      };
      auto gradient = [scale](const GenericPositions&, GenericJacobian& j) {
        j(0, 1) = 1 / scale;
        j(1, 2) = 1 / scale;
      };
      const Vector3 start = scale * Vector3(1, 0.5, -0.25);
      const GenericCorrection c =
          genericConstraintPbd(GenericParticleConstraint({0}, 2, value, gradient),
                               positions({start}), inverseMasses({w}));
      ASSERT_TRUE(c.applied) << scale << " " << w;
      // Onto the x axis: (scale, 0, 0), to round-off of numbers of size `scale` (16 ε).
      EXPECT_NEAR((start + c.delta.col(0) - Vector3(scale, 0, 0)).norm(), 0, 16 * kEpsilon * scale);
    }
}

TEST(GenericConstraint, TranslationInvariantConstraintConservesMomentum) {
  // Three particles, C = (|x₁ − x₀| − L, (x₁ − x₀)·(x₂ − x₀) − c): both components depend on
  // differences only, so Σᵢ ∇ᵢC = 0 and Σᵢ Δxᵢ/wᵢ = 0.
  const Real length = Real(0.7), product = Real(0.1);
  auto value = [length, product](const GenericPositions& x, GenericValue& c) {
    const Vector3 d1 = x.col(1) - x.col(0), d2 = x.col(2) - x.col(0);
    c(0) = d1.norm() - length;
    c(1) = d1.dot(d2) - product;
  };
  auto gradient = [](const GenericPositions& x, GenericJacobian& j) {
    const Vector3 d1 = x.col(1) - x.col(0), d2 = x.col(2) - x.col(0);
    const Vector3 n = d1.normalized();
    j.block<1, 3>(0, 0) = -n.transpose();
    j.block<1, 3>(0, 3) = n.transpose();
    j.block<1, 3>(1, 0) = -(d1 + d2).transpose();
    j.block<1, 3>(1, 3) = d2.transpose();
    j.block<1, 3>(1, 6) = d1.transpose();
  };
  const GenericPositions x = positions({kP1, kP2, Vector3(0.6, 0.4, -0.3)});
  const auto w = inverseMasses({1, Real(0.5), 2});
  for (bool analytic : {true, false}) {
    const GenericCorrection c =
        genericConstraintPbd(GenericParticleConstraint({0, 1, 2}, 2, value,
                                                       analytic ? GenericGradientFunction(gradient)
                                                                : GenericGradientFunction()),
                             x, w);
    ASSERT_TRUE(c.applied);
    Vector3 momentum = Vector3::Zero();
    for (int i = 0; i < 3; ++i)
      momentum += c.delta.col(i) / w[std::size_t(i)];
    // Analytic: the round-off of three O(1) terms (16 ε). Central differences: each column
    // sum Σᵢ ∂C/∂xᵢ is zero up to the finite-difference error (coordinates below 1: h = ε^(1/3)).
    EXPECT_NEAR(momentum.norm(), 0, analytic ? 16 * kEpsilon : test::finiteDifferenceTolerance())
        << analytic;
  }
}

TEST(GenericConstraint, LimitsAreCheckedAtConstruction) {
  auto value = [](const GenericPositions&, GenericValue& c) { c.setZero(); };
  EXPECT_THROW(GenericParticleConstraint({0, 1, 2, 3, 4, 5, 6, 7, 8}, 1, value),
               std::invalid_argument);  // 9 particles
  EXPECT_THROW(GenericParticleConstraint({}, 1, value), std::invalid_argument);
  EXPECT_THROW(GenericParticleConstraint({0}, 7, value), std::invalid_argument);
  EXPECT_THROW(GenericParticleConstraint({0}, 0, value), std::invalid_argument);
  EXPECT_THROW(GenericParticleConstraint({0}, 1, GenericValueFunction()), std::invalid_argument);
  EXPECT_THROW(GenericParticleConstraint({0, 0}, 1, value), std::invalid_argument);
  EXPECT_THROW(GenericParticleConstraint({-1}, 1, value), std::invalid_argument);
  EXPECT_THROW(GenericParticleConstraint({0}, 1, value, {}, Real(1.5)), std::invalid_argument);
  EXPECT_NO_THROW(GenericParticleConstraint({0, 1, 2, 3, 4, 5, 6, 7}, 6, value));  // the limits
}

// A static particle at the origin and one of 1 kg at (1, 0, 0): a pendulum of length 1.
Scene pendulumScene(StepMethod stepMethod) {
  Scene scene;
  scene.simulation.stepMethod = stepMethod;
  scene.simulation.timeStepSize = Real(0.005);
  scene.particles.push_back({Vector3::Zero(), Vector3::Zero(), 0});
  scene.particles.push_back({Vector3(1, 0, 0), Vector3::Zero(), 1});
  return scene;
}

TEST(GenericConstraint, WorldPendulumMatchesTheBuiltInDistanceConstraint) {
  const int steps = 400;
  for (StepMethod stepMethod : {StepMethod::Seed, StepMethod::Xpbd}) {
    World builtIn = buildWorld(pendulumScene(stepMethod));
    ParticleDistanceConstraint rod;
    rod.particle1 = 0;
    rod.particle2 = 1;
    rod.restLength = 1;
    builtIn.constraints.particleDistances.push_back(rod);
    World exact = buildWorld(pendulumScene(stepMethod));
    exact.constraints.genericConstraints.push_back(distanceConstraint(0, 1, 1, true));
    World approximate = buildWorld(pendulumScene(stepMethod));
    approximate.constraints.genericConstraints.push_back(distanceConstraint(0, 1, 1, false));
    Real largestDeviation = 0;
    for (int n = 0; n < steps; ++n) {
      builtIn.step();
      exact.step();
      approximate.step();
      const Vector3& p = exact.bodies.particles.position[1];
      largestDeviation = std::max(largestDeviation, std::abs(p.norm() - 1));
    }
    // k = 1 projects onto the circle in every solve: the length is kept to round-off (16 ε).
    EXPECT_NEAR(largestDeviation, 0, 16 * kEpsilon);
    // It swung: 2 s of a 1 m pendulum released horizontally.
    EXPECT_LT(exact.bodies.particles.position[1].y(), Real(-0.1));
    // Analytic gradient: each projection agrees with the built-in one to a few ε (above); a
    // pendulum is not chaotic, so the differences add up at most linearly: steps · 16 ε.
    const Vector3 reference = builtIn.bodies.particles.position[1];
    EXPECT_NEAR((exact.bodies.particles.position[1] - reference).norm(), 0, steps * 16 * kEpsilon);
    // Central differences: each projection within the finite-difference tolerance, adding up
    // linearly too.
    EXPECT_NEAR((approximate.bodies.particles.position[1] - reference).norm(), 0,
                steps * test::finiteDifferenceTolerance());
  }
}

}  // namespace
}  // namespace pbd
