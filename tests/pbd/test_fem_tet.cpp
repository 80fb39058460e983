// FEM tets (constraints/fem_tet.h), St. Venant–Kirchhoff with the energy as the constraint,
// solidSimulationMethod 2 (PBD) and 3 (XPBD): the energy of a uniaxial stretch against its
// closed form, no energy or correction at rest and under rigid motions, the PBD and XPBD
// corrections against the same projections built from central differences of U and
// √(2U/E), momentum and energy decrease, the PBD correction's independence of E (the seed's
// semantics), the inversion path; in the world: an apex hanging from a static base settles at
// the closed-form StVK stretch (XPBD) or at g h_s²/(2ⁿ − 1) whatever E (PBD), and the
// constraints a tet model gets from solidSimulationMethod.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "common/tolerances.h"
#include "pbd/constraints/fem_tet.h"
#include "pbd/model/world.h"

namespace pbd {
namespace {

// A generic tet (no symmetry), positively oriented.
const std::array<Vector3, 4> kTet = {Vector3(0.1, -0.2, 0.3), Vector3(1.2, 0.1, -0.1),
                                     Vector3(0.3, 0.9, 0.2), Vector3(0.2, 0.1, 1.1)};

FemTetConstraint constraintAt(const std::array<Vector3, 4>& rest, Real youngsModulus,
                              Real poissonRatio, bool xpbd) {
  FemTetConstraint c;
  c.particles = {0, 1, 2, 3};
  EXPECT_TRUE(femTetRestState(rest, c.inverseRestMatrix, c.restVolume));
  c.youngsModulus = youngsModulus;
  c.poissonRatio = poissonRatio;
  c.xpbd = xpbd;
  return c;
}

std::array<Vector3, 4> transformed(const std::array<Vector3, 4>& x, const Matrix3& a,
                                   const Vector3& t = Vector3::Zero()) {
  std::array<Vector3, 4> y;
  for (std::size_t i = 0; i < 4; ++i)
    y[i] = a * x[i] + t;
  return y;
}

// A deformed, not inverted state of kTet: a general linear map plus a per-vertex perturbation.
std::array<Vector3, 4> deformedTet() {
  Matrix3 a;
  a << 1.1, 0.15, -0.05, 0.05, 0.9, 0.1, -0.1, 0.05, 1.2;
  std::array<Vector3, 4> x = transformed(kTet, a, Vector3(0.3, -0.1, 0.2));
  x[2] += Vector3(0.05, -0.03, 0.04);
  return x;
}

Real signedVolume(const std::array<Vector3, 4>& p) {
  return (p[1] - p[0]).cross(p[2] - p[0]).dot(p[3] - p[0]) / 6;
}

TEST(FemTet, RestStateAndLameParameters) {
  FemTetConstraint c = constraintAt(kTet, 1, Real(0.3), false);
  EXPECT_NEAR(c.restVolume, std::abs(signedVolume(kTet)), 10 * kEpsilon);
  // F at rest is the identity to round-off (D_m D_m⁻¹: a few ε times the condition number).
  EXPECT_LT((femDeformationGradient(kTet, c.inverseRestMatrix) - Matrix3::Identity()).norm(),
            100 * kEpsilon);
  // E = 2.6, ν = 0.3: μ = 2.6/2.6 = 1, λ_L = 0.78/(1.3·0.4) = 1.5 (exact decimals; round-off).
  const LameParameters l = lameParameters(Real(2.6), Real(0.3));
  EXPECT_NEAR(l.mu, 1, 4 * kEpsilon);
  EXPECT_NEAR(l.lambda, Real(1.5), 4 * kEpsilon);
  // A flat tet is degenerate: no rest state.
  std::array<Vector3, 4> flat = kTet;
  flat[3] = (kTet[1] + kTet[2]) / 2;
  Matrix3 inverse;
  Real volume;
  EXPECT_FALSE(femTetRestState(flat, inverse, volume));
}

TEST(FemTet, EnergyOfAUniaxialStretchIsTheClosedForm) {
  // F = diag(1 + e, 1, 1): ε = diag(a, 0, 0), a = ((1 + e)² − 1)/2, ψ = μ a² + ½ λ_L a²
  // = ½ (λ_L + 2μ) a²; U = V₀ ψ. Also under a rotation after the stretch (F = R diag(…)).
  const Quaternion q(AngleAxis(0.7, Vector3(1, -2, 0.5).normalized()));
  for (Real nu : {Real(0), Real(0.3), Real(0.49)})
    for (Real youngs : {Real(1), Real(1e6)})
      for (Real e : {Real(0.3), Real(-0.2)}) {
        const FemTetConstraint c = constraintAt(kTet, youngs, nu, false);
        const LameParameters l = lameParameters(youngs, nu);
        const Real a = ((1 + e) * (1 + e) - 1) / 2;
        const Real expected = c.restVolume * (l.lambda + 2 * l.mu) * a * a / 2;
        const Matrix3 stretch = Vector3(1 + e, 1, 1).asDiagonal();
        for (const Matrix3& map : {stretch, Matrix3(q.toRotationMatrix() * stretch)}) {
          const FemTetEnergy u = femTetEnergy(transformed(kTet, map, Vector3(1, 2, 3)), c);
          EXPECT_FALSE(u.inverted);
          // Round-off of F (a few ε times D_m's condition number) in a sum of O(1) terms.
          EXPECT_NEAR(u.energy, expected, 1e3 * kEpsilon * expected) << nu << " " << e;
        }
      }
}

TEST(FemTet, RestAndRigidMotionsHaveNoEnergyOrCorrection) {
  const Quaternion q(AngleAxis(2.1, Vector3(0.3, 1, -0.4).normalized()));
  const std::array<Real, 4> w = {1, 2, Real(0.5), Real(0.25)};
  for (Real youngs : {Real(1), Real(1e6)}) {
    const FemTetConstraint pbd = constraintAt(kTet, youngs, Real(0.3), false);
    const FemTetConstraint xpbd = constraintAt(kTet, youngs, Real(0.3), true);
    for (const auto& x : {kTet, transformed(kTet, q.toRotationMatrix(), Vector3(-2, 5, 1))}) {
      const FemTetEnergy u = femTetEnergy(x, pbd);
      // F − R is round-off (~100 ε): U ~ E V₀ (100 ε)², ∇U ~ E V₀ 100 ε / L.
      EXPECT_LT(u.energy, youngs * 1e4 * kEpsilon * kEpsilon);
      for (const Vector3& g : u.gradients)
        EXPECT_LT(g.norm(), youngs * 1e3 * kEpsilon);
      // A projection of round-off strain moves by round-off of the tet's size (O(1)).
      for (const FemTetCorrection& d : {femTetPbd(x, w, pbd), femTetXpbd(x, w, xpbd, Real(1e-3))})
        for (const Vector3& p : d.positions)
          EXPECT_LT(p.norm(), 1e3 * kEpsilon);
    }
  }
}

// ∂f/∂x_i by central differences.
template <class F>
std::array<Vector3, 4> centralDifferences(const std::array<Vector3, 4>& x, F f) {
  const Real h = test::finiteDifferenceStep();
  std::array<Vector3, 4> g;
  for (std::size_t i = 0; i < 4; ++i)
    for (int axis = 0; axis < 3; ++axis) {
      std::array<Vector3, 4> plus = x, minus = x;
      plus[i](axis) += h;
      minus[i](axis) -= h;
      g[i](axis) = (f(plus) - f(minus)) / (2 * h);
    }
  return g;
}

TEST(FemTet, GradientAndProjectionsMatchCentralDifferences) {
  const std::array<Vector3, 4> x = deformedTet();
  const std::array<Real, 4> w = {1, 2, Real(0.5), Real(0.25)};
  const Real youngs = 1, nu = Real(0.3), substep = Real(0.01);
  const FemTetConstraint pbd = constraintAt(kTet, youngs, nu, false);
  FemTetConstraint xpbd = constraintAt(kTet, youngs, nu, true);
  // ∇U (E = 1: O(1) derivatives, so the O(1) tolerance applies).
  const auto energy = [&](const std::array<Vector3, 4>& y) { return femTetEnergy(y, pbd).energy; };
  const std::array<Vector3, 4> dU = centralDifferences(x, energy);
  const FemTetEnergy u = femTetEnergy(x, pbd);
  ASSERT_GT(u.energy, 1e-3);
  for (std::size_t i = 0; i < 4; ++i)
    EXPECT_LT((u.gradients[i] - dU[i]).norm(), test::finiteDifferenceTolerance()) << i;
  // The PBD projection from those differences: s = U / Σ w|∇U|², Δx = −s w ∇U.
  Real norm = 0;
  for (std::size_t i = 0; i < 4; ++i)
    norm += w[i] * dU[i].squaredNorm();
  const FemTetCorrection p = femTetPbd(x, w, pbd);
  for (std::size_t i = 0; i < 4; ++i)
    EXPECT_LT((p.positions[i] + u.energy / norm * w[i] * dU[i]).norm(),
              10 * test::finiteDifferenceTolerance())  // s ~ O(1): the error of dU, scaled
        << i;
  // XPBD: C = √(2U/E) and its central differences; the textbook projection with λ ≠ 0 (the
  // second iteration of a substep: the true λ, not the seed's Δλ/C, enters).
  const auto constraint = [&](const std::array<Vector3, 4>& y) {
    return std::sqrt(2 * femTetEnergy(y, xpbd).energy / youngs);
  };
  const std::array<Vector3, 4> dC = centralDifferences(x, constraint);
  const Real c = constraint(x);
  const Real compliance = 1 / (youngs * substep * substep);
  xpbd.multiplier = Real(-0.01);
  Real normC = 0;
  for (std::size_t i = 0; i < 4; ++i)
    normC += w[i] * dC[i].squaredNorm();
  const Real deltaLambda = (-c - compliance * xpbd.multiplier) / (normC + compliance);
  const FemTetCorrection d = femTetXpbd(x, w, xpbd, substep);
  EXPECT_NEAR(d.multiplier, deltaLambda, test::finiteDifferenceTolerance() * std::abs(deltaLambda));
  for (std::size_t i = 0; i < 4; ++i)
    EXPECT_LT((d.positions[i] - w[i] * deltaLambda * dC[i]).norm(),
              test::finiteDifferenceTolerance() * std::abs(deltaLambda))  // relative to Δλ
        << i;
}

TEST(FemTet, CorrectionsConserveMomentumAndReduceTheEnergy) {
  const std::array<Vector3, 4> x = deformedTet();
  const std::array<Real, 4> w = {1, 2, Real(0.5), Real(0.25)};
  for (bool xpbdMethod : {false, true}) {
    const FemTetConstraint c = constraintAt(kTet, 1e4, Real(0.3), xpbdMethod);
    const FemTetCorrection d = xpbdMethod ? femTetXpbd(x, w, c, Real(1e-2)) : femTetPbd(x, w, c);
    Vector3 momentum = Vector3::Zero();
    std::array<Vector3, 4> y;
    for (std::size_t i = 0; i < 4; ++i) {
      momentum += d.positions[i] / w[i];
      y[i] = x[i] + d.positions[i];
    }
    // Σ m_i Δx_i = 0 (the gradients sum to zero): round-off of O(0.1) corrections.
    EXPECT_LT(momentum.norm(), 20 * kEpsilon) << xpbdMethod;
    EXPECT_GT(d.positions[1].norm(), 1e-3);
    const Real before = femTetEnergy(x, c).energy, after = femTetEnergy(y, c).energy;
    std::printf("  %s FEM tet projection: U %.6g -> %.6g\n", xpbdMethod ? "XPBD" : "PBD",
                double(before), double(after));
    EXPECT_LT(after, before);
  }
}

TEST(FemTet, PbdCorrectionDoesNotDependOnYoungsModulus) {
  // The seed's semantics (docs/seed.md#fem-modulus-scale): U and ∇U both scale with E, so s ∇U does
  // not. Only ν matters.
  const std::array<Vector3, 4> x = deformedTet();
  const std::array<Real, 4> w = {1, 2, Real(0.5), Real(0.25)};
  const FemTetCorrection soft = femTetPbd(x, w, constraintAt(kTet, 1, Real(0.3), false));
  const FemTetCorrection hard = femTetPbd(x, w, constraintAt(kTet, 1e9, Real(0.3), false));
  const FemTetCorrection other = femTetPbd(x, w, constraintAt(kTet, 1, Real(0.45), false));
  for (std::size_t i = 0; i < 4; ++i) {
    // Equal up to the round-off of the ratio (a few ε relative).
    EXPECT_LT((soft.positions[i] - hard.positions[i]).norm(), 100 * kEpsilon) << i;
    EXPECT_GT((soft.positions[i] - other.positions[i]).norm(), 1e-4) << i;
  }
}

TEST(FemTet, InvertedTetIsPushedBackTowardsPositiveVolume) {
  // kTet with its last vertex pushed through the opposite face: V < 0.
  std::array<Vector3, 4> x = kTet;
  const Vector3 normal = (kTet[2] - kTet[1]).cross(kTet[3] - kTet[1]).normalized();
  const Real height = (kTet[3] - kTet[0]).dot(normal);  // signed: x₀'s distance beyond the face
  x[0] = kTet[0] + Real(1.4) * height * normal + Vector3(0.05, 0.02, -0.03);
  ASSERT_LT(signedVolume(x), 0);
  const std::array<Real, 4> w = {1, 1, 1, 1};
  for (bool xpbdMethod : {false, true}) {
    const FemTetConstraint c = constraintAt(kTet, 1e6, Real(0.3), xpbdMethod);
    std::array<Vector3, 4> y = x;
    EXPECT_TRUE(femTetEnergy(y, c).inverted);
    int iterations = 0;
    Real volume = signedVolume(y);
    while (signedVolume(y) <= 0 && iterations < 50) {
      const FemTetCorrection d = xpbdMethod ? femTetXpbd(y, w, c, Real(1e-3)) : femTetPbd(y, w, c);
      for (std::size_t i = 0; i < 4; ++i)
        y[i] += d.positions[i];
      ++iterations;
      // Every projection on the inversion path increases the signed volume.
      EXPECT_GT(signedVolume(y), volume) << iterations;
      volume = signedVolume(y);
    }
    std::printf("  %s FEM tet: V = %.4g V0 -> %.4g V0 after %d projections\n",
                xpbdMethod ? "XPBD" : "PBD", double(signedVolume(x) / c.restVolume),
                double(volume / c.restVolume), iterations);
    EXPECT_GT(volume, 0) << xpbdMethod;
    EXPECT_FALSE(femTetEnergy(y, c).inverted);
  }
}

// A tet with a static base (right triangle of legs L in the xz-plane at y = 0) and a free apex
// of mass m at (0, −L, 0), gravity along −y, the FEM constraint alone. Stretching the apex by e L
// along −y gives F = diag(1, 1 + e, 1) (uniaxial), so the apex stays on the y axis.
World hangingApex(int method, Real youngs, int iterations, Real length, Real mass) {
  Scene scene;
  scene.simulation.timeStepSize = Real(0.005);
  scene.simulation.subSteps = 5;
  scene.simulation.maxIterations = iterations;
  scene.simulation.solidSimulationMethod = method;
  scene.simulation.solid_stiffness = youngs;
  // pbdval's FEM without the seed's absolute cut-off: the apex's strains (10⁻⁶ … 10⁻³) keep
  // Σ w|∇C|² below 10⁻⁶, where the seed would not correct at all (docs/methods.md, "femCutoff").
  scene.simulation.femCutoff = 0;
  TetModelDesc solid;
  solid.mesh.vertices = {Vector3(0, 0, 0), Vector3(length, 0, 0), Vector3(0, 0, length),
                         Vector3(0, -length, 0)};
  solid.mesh.tetrahedra = {{0, 1, 2, 3}};
  scene.tetModels.push_back(solid);
  for (int i = 0; i < 4; ++i)
    scene.particles.push_back(
        {solid.mesh.vertices[std::size_t(i)], Vector3::Zero(), i == 3 ? mass : 0});
  return buildWorld(scene);
}

Real meanStretch(World& world, Real from, Real to, Real length) {
  Real sum = 0;
  int count = 0;
  while (world.time < to) {
    world.step();
    if (world.time > from) {
      sum += -world.bodies.particles.position[3].y() / length - 1;
      ++count;
    }
  }
  return sum / count;
}

TEST(FemTetWorld, XpbdApexSettlesAtTheStVKStretch) {
  // Balance at the apex: V₀ (1 + e) M (e + e²/2) / L = m g, M = λ_L + 2μ, V₀ = L³/6:
  //   (1 + e)(e + e²/2) = 6 m g / (M L²) =: r   (linear elasticity: e = r).
  // With E = 10⁴, ν = 0.3, L = 1, m = 1: r = 4.37·10⁻³; ω = √(M V₀/(m L²)) = 47 rad/s, so
  // ω h_s = 0.047 and XPBD's numerical damping (implicit-Euler-like, ~½ (ω h_s)² per substep)
  // leaves ~10⁻³ of the first swing after 6 s: the mean over the last second is the static
  // stretch within 2·10⁻⁴ relative; the StVK term (1.5 r relative = 6.6·10⁻³) is resolved.
  // float's ulp at 1 m (6·10⁻⁸) over the ~450 substeps XPBD takes to correct an error here is
  // of order the 2·10⁻⁴ × 4·10⁻³ m allowed.
  if (sizeof(Real) < 8) GTEST_SKIP() << "the static stretch is resolved for the double build";
  const Real youngs = Real(1e4), nu = Real(0.3), length = 1, mass = 1, g = Real(9.81);
  const LameParameters l = lameParameters(youngs, nu);
  const Real r = 6 * mass * g / ((l.lambda + 2 * l.mu) * length * length);
  // Solve (1 + e)(e + e²/2) = r by Newton from e = r (monotone increasing, convex for e > 0).
  Real e = r;
  for (int k = 0; k < 20; ++k)
    e -= ((1 + e) * (e + e * e / 2) - r) / ((e + e * e / 2) + (1 + e) * (1 + e));
  for (int iterations : {1, 4}) {
    World world = hangingApex(3, youngs, iterations, length, mass);
    ASSERT_EQ(world.constraints.femTets.size(), 1u);
    const Real measured = meanStretch(world, 5, 6, length);
    std::printf("  XPBD FEM apex, %d iterations: stretch %.6g (StVK %.6g, linear %.6g)\n",
                iterations, double(measured), double(e), double(r));
    EXPECT_NEAR(measured, e, 2e-4 * e) << iterations;
    // The apex stays on the axis of symmetry (round-off).
    EXPECT_LT(std::abs(world.bodies.particles.position[3].x()), 1e-12);
  }
}

TEST(FemTetWorld, PbdApexStretchIsSetByIterationsNotByE) {
  // PBD with C = U ≈ ½ k u² (small strain): one projection Δu = −C/C′ = −u/2 halves the
  // displacement, so n iterations keep 2⁻ⁿ of u + g h_s² (the prediction from rest): the fixed
  // point is u = g h_s² / (2ⁿ − 1), whatever E (docs/seed.md#stiffness). The strain is ~10⁻⁵, so
  // the cubic term of U changes this by ~10⁻⁵ relative; the recurrence's roots have modulus
  // 2^(−n/2), so after 1 s nothing of the start remains: 10⁻³ relative allowed.
  // The stretch (10⁻⁶ m … 10⁻⁵ m) is a few float ulps of the apex's 1 m position.
  if (sizeof(Real) < 8) GTEST_SKIP() << "the stretch is below float resolution";
  const Real g = Real(9.81), substep = Real(0.001);
  for (int iterations : {1, 3})
    for (Real youngs : {Real(1), Real(1e6)}) {
      World world = hangingApex(2, youngs, iterations, 1, 1);
      const Real expected = g * substep * substep / (std::pow(Real(2), Real(iterations)) - 1);
      const Real measured = meanStretch(world, 1, Real(1.2), 1);
      std::printf("  PBD FEM apex, E = %g, %d iterations: stretch %.6g (g h^2/(2^n - 1) = %.6g)\n",
                  double(youngs), iterations, double(measured), double(expected));
      EXPECT_NEAR(measured, expected, 1e-3 * expected);
    }
}

TEST(FemTetWorld, SolidsGetFemConstraintsFromMethodsTwoAndThree) {
  // A unit cube of five tets.
  Scene scene;
  TetModelDesc solid;
  for (int k = 0; k < 8; ++k)
    solid.mesh.vertices.push_back(Vector3(Real(k & 1), Real((k >> 1) & 1), Real((k >> 2) & 1)));
  solid.mesh.tetrahedra = {{0, 1, 2, 4}, {1, 3, 2, 7}, {1, 4, 5, 7}, {2, 4, 7, 6}, {1, 2, 4, 7}};
  scene.tetModels.push_back(solid);
  for (const Vector3& v : solid.mesh.vertices)
    scene.particles.push_back({v, Vector3::Zero(), 1});
  for (int method : {0, 1, 2, 3, 4, 5, 6}) {
    scene.simulation.solidSimulationMethod = method;
    const World world = buildWorld(scene);
    const bool made = method == 2 || method == 3;
    ASSERT_EQ(world.constraints.femTets.size(), made ? 5u : 0u) << method;
    Real volume = 0;
    for (const FemTetConstraint& c : world.constraints.femTets) {
      EXPECT_EQ(c.xpbd, method == 3);
      EXPECT_EQ(c.youngsModulus, method == 3 ? Real(1e6) : Real(1));  // the seed's forced E
      EXPECT_EQ(c.poissonRatio, Real(0.3));
      volume += c.restVolume;
    }
    if (made) {
      EXPECT_NEAR(volume, 1, 10 * kEpsilon);  // the five tets fill the unit cube
    }
  }
  // The default method is 2 (FEM PBD), as in the seed.
  EXPECT_EQ(SimulationSettings().solidSimulationMethod, 2);
  // ν outside [0, 0.49]: no constraint (the seed's solve rejects it).
  scene.simulation.solidSimulationMethod = 3;
  scene.simulation.solid_poissonRatio = Real(0.5);
  EXPECT_TRUE(buildWorld(scene).constraints.femTets.empty());
  scene.simulation.solid_poissonRatio = Real(0.3);
  // Tets of four static particles are left out: with 0, 1, 2, 4 static, tet {0, 1, 2, 4} is.
  for (int i : {0, 1, 2, 4})
    scene.particles[std::size_t(i)].mass = 0;
  EXPECT_EQ(buildWorld(scene).constraints.femTets.size(), 4u);
}

TEST(FemTetWorld, XpbdCubeKeepsItsShapeUnderItsOwnWeight) {
  // The cube of five tets (E = 10⁶ forced, 1 kg per vertex) standing on its static bottom face:
  // the load 4 × 9.81 N on a unit face against E = 10⁶ compresses it by ~4·10⁻⁵ (twice that in
  // the first swing); 10⁻³ allowed on the volume. pbdval's FEM, without the seed's absolute
  // cut-off (under it strains of ~10⁻⁴ go uncorrected: 1.2·10⁻³ measured).
  Scene scene;
  scene.simulation.solidSimulationMethod = 3;
  scene.simulation.femCutoff = 0;
  TetModelDesc solid;
  for (int k = 0; k < 8; ++k)
    solid.mesh.vertices.push_back(Vector3(Real(k & 1), Real((k >> 1) & 1), Real((k >> 2) & 1)));
  solid.mesh.tetrahedra = {{0, 1, 2, 4}, {1, 3, 2, 7}, {1, 4, 5, 7}, {2, 4, 7, 6}, {1, 2, 4, 7}};
  scene.tetModels.push_back(solid);
  for (int k = 0; k < 8; ++k)
    scene.particles.push_back(
        {solid.mesh.vertices[std::size_t(k)], Vector3::Zero(), ((k >> 1) & 1) ? Real(1) : Real(0)});
  World world = buildWorld(scene);
  Real worst = 0;
  while (world.time < 1) {
    world.step();
    Real volume = 0;
    for (const FemTetConstraint& c : world.constraints.femTets) {
      std::array<Vector3, 4> p;
      for (std::size_t i = 0; i < 4; ++i)
        p[i] = world.bodies.particles.position[std::size_t(c.particles[i])];
      volume += std::abs(signedVolume(p));
    }
    worst = std::max(worst, std::abs(volume - 1));
  }
  std::printf("  XPBD FEM cube of 5 tets under its own weight: largest volume change %.3g\n",
              double(worst));
  EXPECT_LT(worst, 1e-3);
}

}  // namespace
}  // namespace pbd
