// Dihedral bending (constraints/dihedral_bending.h): the signed angle against the construction of
// a fold, its gradient against central differences, invariance under rigid motions, momentum,
// the PBD correction's first-order exactness, and the constraints a cloth gets.
#include <gtest/gtest.h>

#include <cmath>

#include "common/tolerances.h"
#include "pbd/constraints/dihedral_bending.h"
#include "pbd/model/world.h"

namespace pbd {
namespace {

const Real kPi = Real(EIGEN_PI);

// The edge from (0,0,0) to (1,0,0); the opposite vertices at distance d over the foot point
// (0.4, 0, 0), x₂ on the +y side and x₃ turned by π + θ about the edge: flat at θ = 0, and the
// dihedral angle is θ by construction.
std::array<Vector3, 4> hinge(Real theta, Real d = Real(0.7)) {
  return {Vector3(0, 0, 0), Vector3(1, 0, 0), Vector3(Real(0.4), d, 0),
          Vector3(Real(0.4), -d * std::cos(theta), -d * std::sin(theta))};
}

TEST(DihedralBending, AngleIsTheFoldAngleWithItsSign) {
  // From N_A = e × (x₂ − x₀) = d ẑ and N_B = (x₃ − x₀) × e: the sign convention is fixed by the
  // construction; what the test pins is |θ| and that opposite folds have opposite signs.
  // Precision-aware tolerance: 1e-14 in double is 45 ε on an O(1) angle (the hinge's sin/cos
  // and the atan2 of two cross products each round by a few ε); the same 45 ε in float.
  const Real angleRoundOff = test::roundOffBound(1e-14);
  for (Real theta : {Real(0), Real(0.3), Real(1.2), Real(2.5), Real(-0.3), Real(-2.5)}) {
    const Real angle = dihedralAngle(hinge(theta));
    EXPECT_NEAR(std::abs(angle), std::abs(theta), angleRoundOff) << theta;
    EXPECT_NEAR(dihedralAngle(hinge(-theta)), -angle, angleRoundOff) << theta;
  }
  // Independent of the radius and of where the opposite vertices stand along the edge.
  std::array<Vector3, 4> x = hinge(Real(0.8), Real(2.0));
  x[2].x() = Real(-0.5);
  x[3].x() = Real(1.7);
  EXPECT_NEAR(std::abs(dihedralAngle(x)), Real(0.8), angleRoundOff);
  // Degenerate: no angle.
  std::array<Vector3, 4> flatTriangle = hinge(Real(0.5));
  flatTriangle[2] = Vector3(Real(0.5), 0, 0);
  EXPECT_TRUE(std::isnan(dihedralAngle(flatTriangle)));
}

TEST(DihedralBending, GradientMatchesCentralDifferencesAndSumsToZero) {
  const Quaternion q(AngleAxis(0.7, Vector3(1, 2, -1).normalized()));
  for (Real theta : {Real(0.2), Real(1.4), Real(-2.2)}) {
    std::array<Vector3, 4> x = hinge(theta);
    for (Vector3& p : x)
      p = q * p + Vector3(Real(0.3), -1, 2);               // a generic pose
    x[3] += Vector3(Real(0.05), Real(-0.02), Real(0.01));  // and an asymmetric stencil
    const std::array<Vector3, 4> g = dihedralAngleGradient(x);
    Vector3 sum = Vector3::Zero();
    for (std::size_t i = 0; i < 4; ++i) {
      sum += g[i];
      for (int axis = 0; axis < 3; ++axis) {
        std::array<Vector3, 4> plus = x, minus = x;
        const Real step = test::finiteDifferenceStep();
        plus[i](axis) += step;
        minus[i](axis) -= step;
        const Real numeric = (dihedralAngle(plus) - dihedralAngle(minus)) / (2 * step);
        EXPECT_NEAR(g[i](axis), numeric, test::finiteDifferenceTolerance())
            << "theta " << theta << ", particle " << i << ", axis " << axis;
      }
    }
    // Translation invariance; round-off of O(1) terms. Precision-aware: 1e-13 in double is
    // 450 ε on the four O(1) gradients, the same 450 ε in float.
    EXPECT_LT(sum.norm(), test::roundOffBound(1e-13));
  }
}

TEST(DihedralBending, RestStateAndItsRigidMotionsNeedNoCorrection) {
  DihedralBendingConstraint c;
  c.restAngle = dihedralAngle(hinge(Real(0.9)));
  const Quaternion q(AngleAxis(2.1, Vector3(-1, 1, 3).normalized()));
  std::array<Vector3, 4> moved = hinge(Real(0.9));
  for (Vector3& p : moved)
    p = q * p + Vector3(4, 5, 6);
  for (const auto& x : {hinge(Real(0.9)), moved}) {
    const BendingCorrection d = dihedralBendingPbd(x, {1, 1, 1, 1}, c);
    // Precision-aware: the residual angle is a few ε of an O(1) angle (moved: also the rotated
    // coordinates of magnitude ≤ 10), 1e-13 = 450 ε in double and the same 450 ε in float.
    for (const Vector3& dx : d.positions)
      EXPECT_LT(dx.norm(), test::roundOffBound(1e-13));
  }
}

TEST(DihedralBending, CorrectionConservesMomentumAndIsExactToFirstOrder) {
  // PBD's step solves the linearised C + ∇C·Δx = 0 exactly, so the remaining angle error is
  // second order in the correction: for a small deviation δ, |C after| = O(δ²).
  const std::array<Real, 4> w = {1, Real(0.5), 2, Real(0.25)};
  DihedralBendingConstraint c;
  c.restAngle = dihedralAngle(hinge(Real(0.6)));
  for (Real delta : {Real(1e-2), Real(1e-3)}) {
    const std::array<Vector3, 4> x = hinge(Real(0.6) + delta);
    const BendingCorrection d = dihedralBendingPbd(x, w, c);
    Vector3 momentum = Vector3::Zero();
    std::array<Vector3, 4> after;
    for (std::size_t i = 0; i < 4; ++i) {
      momentum += d.positions[i] / w[i];
      after[i] = x[i] + d.positions[i];
    }
    // Precision-aware: Σ Δxᵢ/wᵢ cancels exactly up to round-off of corrections ≤ δ ≤ 1e-2,
    // 1e-15 ≈ 4.5 ε·1 in double, the same multiple of ε in float.
    EXPECT_LT(momentum.norm(), test::roundOffBound(1e-15));
    // The angle's curvature along the step is O(1) for this stencil: ≤ 10 δ².
    EXPECT_LT(std::abs(dihedralAngle(after) - c.restAngle), 10 * delta * delta) << delta;
  }
  // Across ±π the error wraps: folds of 3.1 and −3.1 rad are 2π − 6.2 = 0.083 rad apart.
  c.restAngle = dihedralAngle(hinge(Real(3.1)));
  const std::array<Vector3, 4> x = hinge(Real(-3.1));
  const BendingCorrection d = dihedralBendingPbd(x, w, c);
  Real moved = 0;
  for (const Vector3& dx : d.positions)
    moved = std::max(moved, dx.norm());
  EXPECT_LT(moved, Real(0.2));  // a correction of the wrapped 0.083 rad, not of 6.2 rad
  EXPECT_GT(moved, 0);
}

// The seed's form (the `pbd` method's; dihedral_bending.h): its rest angle is the unsigned fold
// angle, and with a flat rest state (φ₀ = 0, where its sign flip by orientation makes C = |θ|
// act as θ) its correction is pbdval's signed one, computed from ∇θ (checked against central
// differences above), up to round-off. With a folded rest state it is not: a fold by −θ₀ is at
// rest for the seed (|−θ₀| = φ₀: C = 0), while pbdval corrects it towards +θ₀.
TEST(DihedralBending, SeedFormIsTheUnsignedAngleWithItsSignFlippedByOrientation) {
  const std::array<Real, 4> w = {1, 2, Real(0.5), Real(0.25)};
  DihedralBendingConstraint seed;
  seed.seedForm = true;
  seed.stiffness = Real(0.8);
  DihedralBendingConstraint own = seed;
  own.seedForm = false;
  seed.restAngle = seedDihedralRestAngle(hinge(0));
  own.restAngle = dihedralAngle(hinge(0));
  // acos near 1: a round-off δ of a few ε in n̂₁·n̂₂ gives √(2δ) ≈ 3·10⁻⁸.
  EXPECT_NEAR(seed.restAngle, 0, 1e-7);
  for (Real theta : {Real(0.3), Real(-0.5), Real(1.2), Real(-2.5)}) {
    EXPECT_NEAR(seedDihedralRestAngle(hinge(theta)), std::abs(theta), 1e-7) << theta;
    const BendingCorrection a = seedDihedralBendingPbd(hinge(theta), w, seed);
    const BendingCorrection b = dihedralBendingPbd(hinge(theta), w, own);
    for (std::size_t i = 0; i < 4; ++i)
      // The rest angle's 3·10⁻⁸ against corrections of O(θ): 10⁻⁷ relative and absolute.
      EXPECT_LT((a.positions[i] - b.positions[i]).norm(), 1e-7 * (1 + b.positions[i].norm()))
          << theta << " " << i;
  }
  seed.restAngle = seedDihedralRestAngle(hinge(Real(0.6)));
  own.restAngle = dihedralAngle(hinge(Real(0.6)));
  const BendingCorrection mirrored = seedDihedralBendingPbd(hinge(Real(-0.6)), w, seed);
  for (const Vector3& dx : mirrored.positions)
    EXPECT_LT(dx.norm(), 1e-7);  // the seed leaves the mirrored fold alone (C ≈ 0)
  Real moved = 0;
  for (const Vector3& dx : dihedralBendingPbd(hinge(Real(-0.6)), w, own).positions)
    moved = std::max(moved, dx.norm());
  EXPECT_GT(moved, 0.1);  // pbdval corrects C = −1.2 rad
  // Both opposite vertices static: no correction in the seed's form (its early return).
  for (const Vector3& dx : seedDihedralBendingPbd(hinge(Real(0.9)), {1, 1, 0, 0}, seed).positions)
    EXPECT_EQ(dx, Vector3::Zero());
}

TEST(DihedralBending, ClothGetsOneConstraintPerInteriorEdgeWithItsRestAngle) {
  // A folded strip of four triangles: 3 interior edges.
  Scene scene;
  TriangleModelDesc cloth;
  cloth.mesh.vertices = {Vector3(0, 0, 0), Vector3(0, 0, 1), Vector3(1, 0, 0),
                         Vector3(1, 0, 1), Vector3(2, 1, 0), Vector3(2, 1, 1)};
  cloth.mesh.triangles = {{0, 1, 2}, {2, 1, 3}, {2, 3, 4}, {4, 3, 5}};
  scene.triangleModels.push_back(cloth);
  for (const Vector3& v : cloth.mesh.vertices)
    scene.particles.push_back({v, Vector3::Zero(), 1});
  scene.simulation.clothSimulationMethod = 1;
  for (int bending : {0, 1, 2, 3}) {
    scene.simulation.clothBendingMethod = bending;
    const World world = buildWorld(scene);
    ASSERT_EQ(world.constraints.clothDihedrals.size(), bending == 1 ? 3u : 0u) << bending;
  }
  scene.simulation.clothBendingMethod = 1;
  // Every cloth method that models stretch (1–4) gets bending, as in the seed; 0 gets none.
  for (int method : {0, 1, 2, 3, 4}) {
    scene.simulation.clothSimulationMethod = method;
    EXPECT_EQ(buildWorld(scene).constraints.clothDihedrals.size(), method == 0 ? 0u : 3u) << method;
  }
  scene.simulation.clothSimulationMethod = 1;
  // The diagonals (1–2 and 3–4) are flat; the crease 2–3 is folded by π/4. pbdval's form
  // (femCutoff 0): atan2, exact to round-off. The seed's (the `pbd` method's default): acos of
  // n̂₁·n̂₂, which turns a round-off δ of a few ε in a dot product near 1 into √(2δ) ≈ 3·10⁻⁸.
  for (const bool seedForm : {false, true}) {
    Scene form = scene;
    if (!seedForm) form.simulation.femCutoff = Real(0);
    const World world = buildWorld(form);
    std::vector<Real> angles;
    for (const DihedralBendingConstraint& c : world.constraints.clothDihedrals) {
      EXPECT_EQ(c.seedForm, seedForm);
      angles.push_back(std::abs(c.restAngle));
      EXPECT_EQ(c.stiffness, Real(0.01));  // the seed's default cloth_bendingStiffness
    }
    const Real tolerance = seedForm ? Real(1e-7) : Real(1e-15);
    EXPECT_NEAR(angles[0], 0, tolerance) << seedForm;
    EXPECT_NEAR(angles[1], kPi / 4, tolerance) << seedForm;
    EXPECT_NEAR(angles[2], 0, tolerance) << seedForm;
  }
  // Held at rest with gravity off, a step leaves every particle where it is.
  scene.simulation.gravitation = Vector3::Zero();
  scene.simulation.cloth_bendingStiffness = 1;
  World stepped = buildWorld(scene);
  stepped.step();
  for (std::size_t i = 0; i < cloth.mesh.vertices.size(); ++i)
    EXPECT_LT((stepped.bodies.particles.position[i] - cloth.mesh.vertices[i]).norm(), 1e-15);
}

}  // namespace
}  // namespace pbd
