// Isometric bending (constraints/isometric_bending.h): zero energy and no correction at the flat
// rest state and its rigid motions, the gradient against central differences, the energy of a
// symmetric fold against its closed form (6/d) sin²(φ/2), momentum, and the constraints a cloth
// gets from clothBendingMethod.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <optional>
#include <vector>

#include "common/tolerances.h"
#include "pbd/constraints/isometric_bending.h"
#include "pbd/model/world.h"

namespace pbd {
namespace {

const Real kPi = Real(EIGEN_PI);

// An edge of length 1 on the x axis; the opposite vertices over the foot point (0.4, 0, 0) at
// distance d, folded by the dihedral angle φ (0: flat).
std::array<Vector3, 4> fold(Real phi, Real d = Real(0.7)) {
  return {Vector3(0, 0, 0), Vector3(1, 0, 0),
          Vector3(Real(0.4), d * std::cos(phi / 2), d * std::sin(phi / 2)),
          Vector3(Real(0.4), -d * std::cos(phi / 2), d * std::sin(phi / 2))};
}

IsometricBendingConstraint constraintAt(const std::array<Vector3, 4>& rest, bool xpbd,
                                        Real stiffness) {
  IsometricBendingConstraint c;
  c.particles = {0, 1, 2, 3};
  EXPECT_TRUE(isometricBendingStencil(rest, c.weights, c.scale));
  c.xpbd = xpbd;
  c.stiffness = stiffness;
  return c;
}

TEST(IsometricBending, FlatRestStateAndItsRigidMotionsHaveNoEnergy) {
  // A generic flat stencil (not symmetric).
  const std::array<Vector3, 4> rest = {Vector3(0, 0, 0), Vector3(1, Real(0.1), 0),
                                       Vector3(Real(0.3), Real(0.8), 0),
                                       Vector3(Real(0.6), Real(-0.7), 0)};
  const IsometricBendingConstraint c = constraintAt(rest, false, 1);
  EXPECT_NEAR(c.weights[0] + c.weights[1] + c.weights[2] + c.weights[3], 0, 10 * kEpsilon);
  const Quaternion q(AngleAxis(1.3, Vector3(2, -1, 1).normalized()));
  std::array<Vector3, 4> moved;
  for (std::size_t i = 0; i < 4; ++i)
    moved[i] = q * rest[i] + Vector3(1, 2, 3);
  // |H| is a sum of O(1) terms: round-off ~10 ε, squared in C. Precision-aware: the double
  // bounds (1e-25 on C ~ (10 ε)²·2·10⁴, 1e-12 = 4500 ε on Δx) keep their multiples of ε in
  // float, with ε² for the energy.
  const Real energyRoundOff = test::roundOffBound(1e-25) * test::kEpsilonRatio;
  for (const auto& x : {rest, moved}) {
    EXPECT_LT(isometricBendingEnergy(x, c.weights, c.scale), energyRoundOff);
    const BendingCorrection d = isometricBendingPbd(x, {1, 1, 1, 1}, c);
    for (const Vector3& dx : d.positions)
      EXPECT_LT(dx.norm(), test::roundOffBound(1e-12));
  }
}

TEST(IsometricBending, GradientMatchesCentralDifferences) {
  const IsometricBendingConstraint c = constraintAt(fold(0), false, 1);
  const std::array<Vector3, 4> x = fold(Real(0.9));
  Vector3 h = Vector3::Zero();
  for (std::size_t i = 0; i < 4; ++i)
    h += c.weights[i] * x[i];
  const Real step = test::finiteDifferenceStep();
  for (std::size_t i = 0; i < 4; ++i)
    for (int axis = 0; axis < 3; ++axis) {
      std::array<Vector3, 4> plus = x, minus = x;
      plus[i](axis) += step;
      minus[i](axis) -= step;
      const Real numeric = (isometricBendingEnergy(plus, c.weights, c.scale) -
                            isometricBendingEnergy(minus, c.weights, c.scale)) /
                           (2 * step);
      EXPECT_NEAR(numeric, c.scale * c.weights[i] * h(axis), test::finiteDifferenceTolerance());
    }
}

TEST(IsometricBending, SymmetricFoldEnergyIsSixOverDSinSquaredHalfAngle) {
  // Closed form: K = (1.2, 0.8, −1, −1)/d (cotangents 0.4/d and 0.6/d at the edge's ends),
  // A₀ + A₁ = d, |H| = (2/d) d sin(φ/2), so C = (3/(2d)) · 4 sin²(φ/2) = (6/d) sin²(φ/2).
  for (Real d : {Real(0.7), Real(1.5)}) {
    const IsometricBendingConstraint c = constraintAt(fold(0, d), false, 1);
    for (Real phi : {Real(0.1), Real(0.5), Real(1.5), Real(3.0)}) {
      const Real expected = 6 / d * std::pow(std::sin(phi / 2), 2);
      // Precision-aware: 1e-12 = 4500 ε relative in double (a few dozen operations on O(1)
      // cotangent weights and coordinates), the same 4500 ε in float.
      EXPECT_NEAR(isometricBendingEnergy(fold(phi, d), c.weights, c.scale), expected,
                  test::roundOffBound(1e-12) * (1 + expected))
          << "d = " << d << ", phi = " << phi;
    }
  }
}

TEST(IsometricBending, CorrectionsConserveMomentumAndReduceTheEnergy) {
  const IsometricBendingConstraint pbd = constraintAt(fold(0), false, 1);
  IsometricBendingConstraint xpbd = constraintAt(fold(0), true, 1e6);
  const std::array<Vector3, 4> x = fold(Real(0.6));
  const std::array<Real, 4> w = {1, 2, Real(0.5), Real(0.25)};
  for (const BendingCorrection& d :
       {isometricBendingPbd(x, w, pbd), isometricBendingXpbd(x, w, xpbd, 1e-2)}) {
    Vector3 momentum = Vector3::Zero();
    std::array<Vector3, 4> after;
    for (std::size_t i = 0; i < 4; ++i) {
      momentum += d.positions[i] / w[i];
      after[i] = x[i] + d.positions[i];
    }
    EXPECT_LT(momentum.norm(), 20 * kEpsilon);  // the gradients sum to zero
    // A Newton step on a quadratic C towards 0 halves it (C = E is quadratic in x: one step of
    // C + ∇C·Δx = 0 lands at C/4 along the gradient); at least halved.
    EXPECT_LT(isometricBendingEnergy(after, pbd.weights, pbd.scale),
              0.5 * isometricBendingEnergy(x, pbd.weights, pbd.scale));
  }
}

TEST(IsometricBending, ClothGetsOneConstraintPerInteriorEdge) {
  // 3 × 3 vertices, 8 triangles: 16 edges, 8 on the border, 8 interior.
  Scene scene;
  TriangleModelDesc cloth;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i)
      cloth.mesh.vertices.push_back(Vector3(Real(0.5) * i, 0, Real(0.5) * j));
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      const int a = 3 * j + i;
      cloth.mesh.triangles.push_back({a, a + 3, a + 4});
      cloth.mesh.triangles.push_back({a, a + 4, a + 1});
    }
  scene.triangleModels.push_back(cloth);
  for (const Vector3& v : cloth.mesh.vertices)
    scene.particles.push_back({v, Vector3::Zero(), 1});
  scene.simulation.clothSimulationMethod = 4;
  for (int bending : {0, 1, 2, 3}) {
    scene.simulation.clothBendingMethod = bending;
    const World world = buildWorld(scene);
    const bool made = bending == 2 || bending == 3;
    ASSERT_EQ(world.constraints.clothBending.size(), made ? 8u : 0u) << bending;
    for (const IsometricBendingConstraint& c : world.constraints.clothBending) {
      EXPECT_EQ(c.xpbd, bending == 3);
      EXPECT_EQ(c.stiffness, bending == 3 ? Real(100) : Real(0.01));  // the seed's forced values
    }
  }
  // Every cloth method that models stretch (1–4: distances, FEM triangles, strain-based
  // triangles) gets bending, as in the seed; 0 (free particles) gets none.
  scene.simulation.clothBendingMethod = 2;
  for (int method : {0, 1, 2, 3, 4}) {
    scene.simulation.clothSimulationMethod = method;
    EXPECT_EQ(buildWorld(scene).constraints.clothBending.size(), method == 0 ? 0u : 8u) << method;
  }
}

// A hinge of two triangles: the edge's particles static, the tips (mass m each) free, no gravity,
// stiff XPBD edges (clothSimulationMethod 4) and XPBD isometric bending (clothBendingMethod 3) of
// stiffness k, released at rest from a symmetric fold. The tips turn about the edge at the radius
// d, θ = φ/2 each; XPBD's potential is ½ k C² with C = (6/d) sin²θ (the test above), the kinetic
// energy m d² θ̇², so θ(t) is a closed orbit of period T = 4 ∫₀^θ₀ dθ √(m d² / (U(θ₀) − U(θ))),
// integrated here independently (θ = θ₀ sin u removes the end point's singularity; Simpson).
Real hingePeriod(Real mass, Real d, Real stiffness, Real theta0) {
  const auto potential = [&](Real theta) {
    const Real c = 6 / d * std::pow(std::sin(theta), 2);
    return stiffness * c * c / 2;
  };
  // Near u = π/2, U(θ₀) − U(θ) ≈ U'(θ₀) θ₀ cos²u / 2: the integrand's limit there is
  // θ₀ √(2 m d² / (U'(θ₀) θ₀)), with U'(θ) = 2 k (6/d)² sin³θ cos θ.
  const auto integrand = [&](Real u) {
    if (u >= kPi / 2) {
      const Real slope =
          2 * stiffness * (36 / (d * d)) * std::pow(std::sin(theta0), 3) * std::cos(theta0);
      return theta0 * std::sqrt(2 * mass * d * d / (slope * theta0));
    }
    const Real theta = theta0 * std::sin(u);
    const Real drop = potential(theta0) - potential(theta);
    return theta0 * std::cos(u) * std::sqrt(mass * d * d / drop);
  };
  const int intervals = 4000;
  const Real h = (kPi / 2) / intervals;
  Real sum = integrand(0) + integrand(kPi / 2);
  for (int i = 1; i < intervals; ++i)
    sum += (i % 2 ? 4 : 2) * integrand(h * i);
  return 4 * sum * h / 3;
}

/// The times at which the XPBD hinge's tip 2 crosses the flat state (T/4, then 3T/4) within
/// `limit` seconds, and the kinetic energy there: two triangles folded by 2θ₀ about a static
/// hinge, inextensible, no gravity, bending stiffness k. `femCutoff` as the scene gives it.
struct HingeSwing {
  std::vector<Real> crossings;
  std::vector<Real> kineticAtCrossing;
};

HingeSwing swingXpbdHinge(Real mass, Real d, Real stiffness, Real theta0, Real limit,
                          std::optional<Real> femCutoff) {
  Scene scene;
  scene.simulation.gravitation = Vector3::Zero();
  scene.simulation.timeStepSize = Real(0.001);
  scene.simulation.subSteps = 10;
  scene.simulation.maxIterations = 4;
  scene.simulation.clothSimulationMethod = 4;
  scene.simulation.cloth_stiffness = Real(1e12);  // α̃ = 10⁻⁴ against Σw = 1: inextensible
  scene.simulation.clothBendingMethod = 3;
  scene.simulation.cloth_bendingStiffness = stiffness;
  scene.simulation.femCutoff = femCutoff;
  TriangleModelDesc cloth;
  const std::array<Vector3, 4> flat = fold(0, d);
  cloth.mesh.vertices.assign(flat.begin(), flat.end());
  cloth.mesh.triangles = {{0, 1, 2}, {1, 0, 3}};
  scene.triangleModels.push_back(cloth);
  for (std::size_t i = 0; i < 4; ++i)
    scene.particles.push_back({flat[i], Vector3::Zero(), i < 2 ? Real(0) : mass});
  World world = buildWorld(scene);
  EXPECT_EQ(world.constraints.clothBending.size(), 1u);
  const std::array<Vector3, 4> folded = fold(2 * theta0, d);
  for (std::size_t i = 0; i < 4; ++i)
    world.bodies.particles.position[i] = folded[i];
  // Tip 2's height z = d sin θ crosses 0 downwards at T/4 and upwards at 3T/4.
  HingeSwing swing;
  Real previous = world.bodies.particles.position[2].z();
  while (world.time < limit && swing.crossings.size() < 2) {
    world.step();
    const Real now = world.bodies.particles.position[2].z();
    if ((previous > 0) != (now > 0)) {
      swing.crossings.push_back(world.time - world.settings.timeStepSize * now / (now - previous));
      const auto& v = world.bodies.particles.velocity;
      swing.kineticAtCrossing.push_back(mass * (v[2].squaredNorm() + v[3].squaredNorm()) / 2);
    }
    previous = now;
  }
  return swing;
}

TEST(IsometricBendingWorld, XpbdHingeSwingsWithTheClosedFormPeriodAndKeepsItsEnergy) {
  const Real mass = 1, d = Real(0.7), stiffness = 10, theta0 = Real(0.4);
  const Real period = hingePeriod(mass, d, stiffness, theta0);
  const Real initialEnergy = stiffness * std::pow(6 / d * std::pow(std::sin(theta0), 2), 2) / 2;
  // femCutoff 0: pbdval's own formulation (the `pbd` method's default, the seed's, is below).
  const HingeSwing swing = swingXpbdHinge(mass, d, stiffness, theta0, period, Real(0));
  const std::vector<Real>& crossings = swing.crossings;
  const std::vector<Real>& kineticAtCrossing = swing.kineticAtCrossing;
  ASSERT_EQ(crossings.size(), 2u);
  std::printf(
      "  XPBD hinge: half period %.6f s (closed form %.6f s), kinetic energy at the "
      "crossings %.6f, %.6f J of %.6f J\n",
      double(crossings[1] - crossings[0]), double(period / 2), double(kineticAtCrossing[0]),
      double(kineticAtCrossing[1]), double(initialEnergy));
  // XPBD's per-substep phase error is O((ω h_s)²) with ω ~ 2π/T ≈ 10 rad/s, h_s = 10⁻⁴, and the
  // crossings interpolated between 1 ms steps err by O((ω h)²) ≈ 10⁻⁴ of the period: 0.5 %.
  EXPECT_NEAR(crossings[1] - crossings[0], period / 2, 0.005 * period);
  EXPECT_NEAR(crossings[0], period / 4, 0.005 * period);
  // At the flat crossing the whole potential is kinetic. The implicit substep dissipates about
  // (ω h_s)² per substep, ≈ ω² h_s t ≈ 10⁻² · t/s in all: 2 % by 3T/4.
  for (Real kinetic : kineticAtCrossing) {
    EXPECT_LT(kinetic, initialEnergy * (1 + 1e-3));  // it never gains (round-off, stretch: 10⁻³)
    EXPECT_GT(kinetic, initialEnergy * (1 - 0.02));
  }
}

// The seed's XPBD isometric bending (the `pbd` method's default, femCutoff 10⁻⁶) takes as its
// constraint ½ xᵀQx with Q = −3/(2(A₀ + A₁)) K Kᵀ (XPBD::init_IsometricBendingConstraint): −½
// times pbdval's energy. An XPBD constraint scaled by c with compliance α̃ is the unscaled one
// with compliance α̃/c²: the seed's bending of stiffness k is pbdval's of stiffness k/4, and the
// hinge swings with the closed-form period of k/4 (docs/seed.md, "XPBD isometric bending scale").
TEST(IsometricBendingWorld, TheSeedsXpbdHingeSwingsAsAQuarterOfItsStiffness) {
  const Real mass = 1, d = Real(0.7), stiffness = 10, theta0 = Real(0.4);
  const Real period = hingePeriod(mass, d, stiffness / 4, theta0);
  const HingeSwing swing = swingXpbdHinge(mass, d, stiffness, theta0, period, std::nullopt);
  ASSERT_EQ(swing.crossings.size(), 2u);
  std::printf("  the seed's XPBD hinge: half period %.6f s (closed form with k/4: %.6f s)\n",
              double(swing.crossings[1] - swing.crossings[0]), double(period / 2));
  // The same error budget as the test above (0.5 % of the period).
  EXPECT_NEAR(swing.crossings[1] - swing.crossings[0], period / 2, 0.005 * period);
  EXPECT_NEAR(swing.crossings[0], period / 4, 0.005 * period);
}

}  // namespace
}  // namespace pbd
