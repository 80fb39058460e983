// FEM triangles (constraints/fem_triangle.h), clothSimulationMethod 2: the Green strain and the
// energy of known in-plane deformations against the orthotropic plane-stress closed forms, zero
// energy and no correction at rest and under 3D rigid motions (the rest triangle in a general
// plane), the gradients against central differences, momentum, the correction reducing C, the
// seed's scale invariance (docs/seed.md#fem-modulus-scale); in the world: one constraint per
// triangle for method 2 only, and a cloth pinned at one edge whose stretch falls with the iteration
// count.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "common/edge_stretch.h"
#include "common/tolerances.h"
#include "pbd/constraints/fem_triangle.h"
#include "pbd/model/world.h"

namespace pbd {
namespace {

using Matrix2x2 = Eigen::Matrix<Real, 2, 2>;

// A reciprocal orthotropic material (ν_xy/E_x = ν_yx/E_y = 0.15).
const Real kEx = 2, kEy = Real(0.5), kG = Real(0.7), kNuXY = Real(0.3), kNuYX = Real(0.075);

// The rest triangle in material coordinates (x̂ across the first edge, ŷ along it): the first
// edge on the y axis, the third vertex at x > 0. Area ½ |1.2 · 0.9| = 0.54.
const std::array<Vector2, 3> kMaterial = {Vector2(0, 0), Vector2(0, Real(1.2)),
                                          Vector2(Real(0.9), Real(0.4))};
const Real kArea = Real(0.54);

// The rest triangle placed in 3D by R (x̂ ↦ R e_x, ŷ ↦ R e_y: the normal of (x₁ − x₀) × (x₂ − x₀)
// is −R e_z, and n̂ × ŷ = R e_x) and t: a general plane.
const Quaternion kRestRotation(AngleAxis(Real(0.7), Vector3(1, 2, Real(-0.5)).normalized()));
const Vector3 kRestShift(Real(0.3), -1, 2);

// The material points deformed by the in-plane gradient f, then moved rigidly by (q, t).
std::array<Vector3, 3> deformed(const Matrix2x2& f, const Quaternion& q = kRestRotation,
                                const Vector3& t = kRestShift) {
  std::array<Vector3, 3> x;
  for (std::size_t i = 0; i < 3; ++i) {
    const Vector2 p = f * kMaterial[i];
    x[i] = q * Vector3(p.x(), p.y(), 0) + t;
  }
  return x;
}

FemTriangleConstraint constraint(Real scale = 1) {
  FemTriangleConstraint c;
  c.particles = {0, 1, 2};
  EXPECT_TRUE(femTriangleRest(deformed(Matrix2x2::Identity()), c.area, c.restInverse));
  c.stiffness = orthotropicStiffness(scale * kEx, scale * kEy, scale * kG, kNuXY, kNuYX);
  return c;
}

Matrix2x2 gradientOf(Real fxx, Real fxy, Real fyx, Real fyy) {
  Matrix2x2 f;
  f << fxx, fxy, fyx, fyy;
  return f;
}

// Round-off of a few dozen O(1) operations: 100 ε relative.
const Real kRoundOff = 100 * kEpsilon;

TEST(FemTriangle, StiffnessIsTheInverseOfTheOrthotropicCompliance) {
  const OrthotropicStiffness k = orthotropicStiffness(kEx, kEy, kG, kNuXY, kNuYX);
  // Compliance (plane stress): ε_xx = σ_xx/E_x − ν_yx σ_yy/E_y, ε_yy = −ν_xy σ_xx/E_x + σ_yy/E_y.
  Matrix2x2 compliance;
  compliance << 1 / kEx, -kNuYX / kEy, -kNuXY / kEx, 1 / kEy;
  Matrix2x2 stiffness;
  stiffness << k.xx, k.xy, k.xy, k.yy;
  EXPECT_LT((stiffness * compliance - Matrix2x2::Identity()).norm(), kRoundOff);
  EXPECT_EQ(k.shear, kG);
}

TEST(FemTriangle, EnergyOfKnownDeformationsMatchesTheClosedForms) {
  const FemTriangleConstraint c = constraint();
  EXPECT_NEAR(c.area, kArea, kRoundOff);
  const Real d = 1 - kNuXY * kNuYX;
  const Real cxx = kEx / d, cyy = kEy / d, cxy = kEx * kNuYX / d;
  const Quaternion moved(AngleAxis(Real(2.1), Vector3(Real(-0.3), 1, Real(0.8)).normalized()));
  for (Real e : {Real(-0.2), Real(0.01), Real(0.3)}) {
    // Uniaxial stretch along x: E_xx = e + e²/2, ψ = ½ c_xx E_xx².
    const Real exx = e + e * e / 2;
    for (const Quaternion& q : {kRestRotation, moved}) {
      const auto x = deformed(gradientOf(1 + e, 0, 0, 1), q);
      const Matrix2x2 strain = femTriangleStrain(x, c);
      EXPECT_NEAR(strain(0, 0), exx, kRoundOff);
      EXPECT_NEAR(strain(0, 1), 0, kRoundOff);
      EXPECT_NEAR(strain(1, 1), 0, kRoundOff);
      const Real expected = kArea * cxx * exx * exx / 2;
      EXPECT_NEAR(femTriangleEnergy(x, c), expected, kRoundOff * (1 + expected)) << e;
    }
    // Uniaxial stretch along y: ψ = ½ c_yy E_yy².
    const Real yy = kArea * cyy * exx * exx / 2;
    EXPECT_NEAR(femTriangleEnergy(deformed(gradientOf(1, 0, 0, 1 + e)), c), yy,
                kRoundOff * (1 + yy));
    // Biaxial (1 + e, 1 − e/2): ψ = ½ c_xx E_xx² + c_xy E_xx E_yy + ½ c_yy E_yy².
    const Real eyy = -e / 2 + e * e / 8;
    const Real biaxial = kArea * (cxx * exx * exx / 2 + cxy * exx * eyy + cyy * eyy * eyy / 2);
    EXPECT_NEAR(femTriangleEnergy(deformed(gradientOf(1 + e, 0, 0, 1 - e / 2), moved), c), biaxial,
                kRoundOff * (1 + biaxial));
    // Simple shear x += g y: FᵀF = [[1, g], [g, 1 + g²]], E_xy = g/2, E_yy = g²/2:
    // ψ = ½ c_yy g⁴/4 + G g²/4 (the seed's shear term G E_xy²).
    const Real g = e;
    const Real shear = kArea * (cyy * g * g * g * g / 8 + kG * g * g / 4);
    EXPECT_NEAR(femTriangleEnergy(deformed(gradientOf(1, g, 0, 1), moved), c), shear,
                kRoundOff * (1 + shear));
  }
}

TEST(FemTriangle, RestStateAndRigidMotionsHaveNoEnergyAndNoCorrection) {
  const FemTriangleConstraint c = constraint();
  const std::array<Real, 3> w = {1, 2, Real(0.5)};
  // Rotations about axes in, across and out of the rest plane, and translations.
  const std::vector<Quaternion> rotations = {
      kRestRotation, Quaternion(AngleAxis(Real(1.9), Vector3(0, 1, 0))) * kRestRotation,
      Quaternion(AngleAxis(Real(-2.5), Vector3(1, Real(0.2), Real(-3)).normalized())),
      Quaternion(AngleAxis(Real(3.0), kRestRotation * Vector3(0, 0, 1)))};
  for (const Quaternion& q : rotations)
    for (const Vector3& t : {kRestShift, Vector3(-5, 4, Real(0.5))}) {
      const auto x = deformed(Matrix2x2::Identity(), q, t);
      // E is round-off, ~10 ε (O(1) coordinates); C ~ A c E².
      EXPECT_LT(femTriangleEnergy(x, c), 1e4 * kEpsilon * kEpsilon);
      // The correction C/|∇C|² ∇C is of the order of E times the edge lengths.
      for (const Vector3& dx : femTrianglePbd(x, w, c))
        EXPECT_LT(dx.norm(), 1e3 * kEpsilon);
    }
}

TEST(FemTriangle, GradientMatchesCentralDifferences) {
  const FemTriangleConstraint c = constraint();
  // A generic deformation with out-of-plane motion.
  std::array<Vector3, 3> x = deformed(gradientOf(Real(1.1), Real(0.2), Real(-0.15), Real(0.9)));
  x[2] += Vector3(Real(0.05), Real(-0.1), Real(0.2));
  const std::array<Vector3, 3> g = femTriangleGradients(x, c);
  const Real step = test::finiteDifferenceStep();
  for (std::size_t i = 0; i < 3; ++i)
    for (int axis = 0; axis < 3; ++axis) {
      std::array<Vector3, 3> plus = x, minus = x;
      plus[i](axis) += step;
      minus[i](axis) -= step;
      const Real numeric = (femTriangleEnergy(plus, c) - femTriangleEnergy(minus, c)) / (2 * step);
      EXPECT_NEAR(numeric, g[i](axis), test::finiteDifferenceTolerance()) << i << " " << axis;
    }
  EXPECT_LT((g[0] + g[1] + g[2]).norm(), kRoundOff);  // translation invariance
}

TEST(FemTriangle, CorrectionConservesMomentumAndReducesTheEnergy) {
  const FemTriangleConstraint c = constraint();
  const std::array<Real, 3> w = {1, 2, Real(0.5)};
  for (const Matrix2x2& f : {gradientOf(Real(1.1), 0, 0, 1), gradientOf(1, Real(0.3), 0, 1),
                             gradientOf(Real(1.05), Real(0.1), Real(-0.05), Real(0.92))}) {
    std::array<Vector3, 3> x = deformed(f);
    const Real initial = femTriangleEnergy(x, c);
    std::vector<Real> energies = {initial};
    for (int projection = 0; projection < 50; ++projection) {
      const std::array<Vector3, 3> d = femTrianglePbd(x, w, c);
      Vector3 momentum = Vector3::Zero();
      for (std::size_t i = 0; i < 3; ++i) {
        momentum += d[i] / w[i];
        x[i] += d[i];
      }
      // Σ ∇_iC = 0 up to round-off of O(|Δx|) terms.
      EXPECT_LT(momentum.norm(), kRoundOff);
      energies.push_back(femTriangleEnergy(x, c));
      // Decreasing until C reaches its round-off floor (E ~ 10 ε: C ~ 10⁴ ε²).
      const Real previous = energies[energies.size() - 2];
      EXPECT_TRUE(energies.back() < previous || previous < 1e4 * kEpsilon * kEpsilon) << projection;
    }
    std::printf("  FEM triangle: C %.3e after 1 projection, %.3e after 50 (of %.3e)\n",
                double(energies[1]), double(energies.back()), double(initial));
    // Near rest C is quadratic in the displacement δ and a projection leaves
    // C' = ¼ (δᵀHδ)(uᵀHu)/(δᵀHu)² C (u = W H δ): at least ¼, 1 only if u ⟂_H δ. Linear
    // convergence; 10⁻⁶ after 50 steps allows a mean factor of 0.76 per step.
    EXPECT_LT(energies.back(), 1e-6 * initial);
  }
}

TEST(FemTriangle, CorrectionDoesNotDependOnTheModuliScale) {
  // docs/seed.md#fem-modulus-scale: C and ∇C scale with the moduli,
  // the correction C ∇C/|∇C|² does not.
  const std::array<Real, 3> w = {1, Real(0.5), 2};
  const auto x = deformed(gradientOf(Real(1.1), Real(0.2), Real(-0.15), Real(0.9)));
  const auto base = femTrianglePbd(x, w, constraint(1));
  // A power of two scales every intermediate exactly: bitwise the same.
  const auto binary = femTrianglePbd(x, w, constraint(1024));
  // Any other scale: round-off.
  const auto decimal = femTrianglePbd(x, w, constraint(Real(1e3)));
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(binary[i], base[i]);
    EXPECT_LT((decimal[i] - base[i]).norm(), kRoundOff * base[i].norm());
  }
  EXPECT_GT(base[0].norm(), 1e-3);  // a real correction
}

TEST(FemTriangle, DegenerateRestTriangleIsRejected) {
  Real area = 0;
  Matrix2x2 restInverse;
  EXPECT_FALSE(
      femTriangleRest({Vector3(0, 0, 0), Vector3(1, 1, 0), Vector3(2, 2, 0)}, area, restInverse));
  EXPECT_FALSE(
      femTriangleRest({Vector3(1, 0, 0), Vector3(1, 0, 0), Vector3(2, 2, 0)}, area, restInverse));
}

// An n × n grid of side 1 in the xz plane (y = 0), two triangles per cell.
Scene clothScene(int n, int method) {
  Scene scene;
  TriangleModelDesc cloth;
  const Real h = Real(1) / (n - 1);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      cloth.mesh.vertices.push_back(Vector3(h * i, 0, h * j));
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const int a = n * j + i;
      cloth.mesh.triangles.push_back({a, a + n, a + n + 1});
      cloth.mesh.triangles.push_back({a, a + n + 1, a + 1});
    }
  scene.triangleModels.push_back(cloth);
  for (const Vector3& v : cloth.mesh.vertices)
    scene.particles.push_back({v, Vector3::Zero(), 1});
  scene.simulation.clothSimulationMethod = method;
  return scene;
}

TEST(FemTriangleWorld, ClothGetsOneConstraintPerTriangleForMethodTwoOnly) {
  Scene scene = clothScene(3, 2);
  for (int method : {0, 1, 2, 3, 4}) {
    scene.simulation.clothSimulationMethod = method;
    const World world = buildWorld(scene);
    EXPECT_EQ(world.constraints.femTriangles.size(), method == 2 ? 8u : 0u) << method;
  }
  scene.simulation.clothSimulationMethod = 2;
  scene.simulation.cloth_xxStiffness = 3;
  scene.simulation.cloth_yyStiffness = 2;
  scene.simulation.cloth_xyStiffness = Real(0.25);
  scene.simulation.cloth_xyPoissonRatio = Real(0.2);
  scene.simulation.cloth_yxPoissonRatio = Real(0.1);
  // Each modulus from its own key (the seed's setters write xx into yy and xy: §5.3 #4).
  const OrthotropicStiffness k = buildWorld(scene).constraints.femTriangles[0].stiffness;
  const OrthotropicStiffness expected =
      orthotropicStiffness(3, 2, Real(0.25), Real(0.2), Real(0.1));
  EXPECT_EQ(k.xx, expected.xx);
  EXPECT_EQ(k.yy, expected.yy);
  EXPECT_EQ(k.xy, expected.xy);
  EXPECT_EQ(k.shear, Real(0.25));
  // A triangle of static particles gets none: make vertices 0, 1, 3, 4 static (triangles
  // (0, 3, 4) and (0, 4, 1) of the first cell).
  for (int i : {0, 1, 3, 4})
    scene.particles[std::size_t(i)].mass = 0;
  EXPECT_EQ(buildWorld(scene).constraints.femTriangles.size(), 6u);
}

TEST(FemTriangleWorld, PinnedClothStaysBoundedAndStretchesLessWithMoreIterations) {
  // A 1 m cloth of 6 × 6 particles (1 kg each) pinned along its z = 0 edge falls under gravity
  // for 1 s. More iterations project the FEM constraints more often per substep, so the cloth
  // must stretch less (PBD's stiffness is set by the iteration count: research §3.4).
  std::vector<Real> stretch;
  for (int iterations : {1, 4}) {
    Scene scene = clothScene(6, 2);
    scene.simulation.clothBendingMethod = 0;
    scene.simulation.maxIterations = iterations;
    // pbdval's FEM without the seed's absolute cut-off: below Σ w|∇C|² = 10⁻⁶ (edge strains
    // of ~10⁻², here) the seed leaves the triangles alone, whatever the iteration count.
    scene.simulation.femCutoff = 0;
    for (int i = 0; i < 6; ++i)
      scene.particles[std::size_t(i)].mass = 0;
    World world = buildWorld(scene);
    ASSERT_EQ(world.constraints.femTriangles.size(), 50u);
    Real worst = 0;
    while (world.time < 1) {
      world.step();
      for (const Vector3& p : world.bodies.particles.position) {
        ASSERT_TRUE(p.allFinite());
        // Bounded: no particle farther from the pinned edge than twice the cloth's length.
        ASSERT_LT(Vector2(p.y(), p.z()).norm(), 2);
      }
      worst = std::max(worst, test::maxTriangleEdgeStretch(world, scene));
    }
    stretch.push_back(worst);
    // The pinned particles stay.
    for (int i = 0; i < 6; ++i)
      EXPECT_EQ(world.bodies.particles.position[std::size_t(i)],
                scene.particles[std::size_t(i)].position);
  }
  std::printf("  FEM cloth: largest edge stretch in 1 s: %.3e (1 iteration), %.3e (4)\n",
              double(stretch[0]), double(stretch[1]));
  EXPECT_LT(stretch[1], stretch[0]);
}

}  // namespace
}  // namespace pbd
