// The ball joint's direct point-constraint solve (point_constraint.h) against an independent
// computation: the generic block solver of constraint_rows.h on the same rows (setPointRows),
// with both ends dynamic, one end static, and with compliance and an accumulated multiplier.
#include <gtest/gtest.h>

#include "common/tolerances.h"
#include "common/two_bodies.h"
#include "pbd/joints/joint_parts.h"
#include "pbd/joints/point_constraint.h"

namespace pbd {
namespace {

// The same projection through the generic m-row path.
Vector3 genericProjection(RigidBodyStates& b, const Vector3& a0, const Vector3& a1, Real compliance,
                          const Vector3& lambda) {
  const Vector3 c0 = b.position[0] + b.rotation[0] * a0;
  const Vector3 c1 = b.position[1] + b.rotation[1] * a1;
  ConstraintRows<3> rows;
  joint_parts::setPointRows(rows, 0, b.position[0], c0, b.position[1], c1);
  const Vector3 rowCompliance = Vector3::Constant(compliance);
  return joint_parts::projectPositions(b, 0, 1, rows, rowCompliance, lambda);
}

void expectSameProjection(bool firstDynamic, Real compliance, const Vector3& lambda) {
  const Vector3 a0(0.25, -0.1, 0.4), a1(-0.3, 0.2, 0.05);
  RigidBodyStates direct = test::twoTurnedBodies(firstDynamic);
  RigidBodyStates generic = test::twoTurnedBodies(firstDynamic);
  const Vector3 directMultiplier = projectPointConstraint(direct, 0, 1, a0, a1, compliance, lambda);
  const Vector3 genericMultiplier = genericProjection(generic, a0, a1, compliance, lambda);
  // Both solve the same 3×3 system (K's condition number here is below 10³) in a different
  // order of operations: they agree to round-off, κ·ε ≈ 10⁻¹³, allowed 10⁻¹¹ in double.
  // Precision-aware: 10⁻¹¹ = 100 κ ε with κ ≤ 10³ (45000 ε), the same multiple of ε in float.
  const Real tolerance = test::roundOffBound(1e-11);
  EXPECT_LT((directMultiplier - genericMultiplier).norm(), tolerance * genericMultiplier.norm());
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_LT((direct.position[i] - generic.position[i]).norm(), tolerance) << "body " << i;
    EXPECT_LT((direct.rotation[i].coeffs() - generic.rotation[i].coeffs()).norm(), tolerance)
        << "body " << i;
  }
  EXPECT_GT(genericMultiplier.norm(), 0.01);  // the poses are far from the constraint
}

TEST(PointConstraint, MatchesTheGenericBlockSolveWithBothEndsDynamic) {
  expectSameProjection(true, 0, Vector3::Zero());
}

TEST(PointConstraint, MatchesTheGenericBlockSolveWithAStaticEnd) {
  expectSameProjection(false, 0, Vector3::Zero());
}

TEST(PointConstraint, MatchesTheGenericBlockSolveWithComplianceAndMultiplier) {
  expectSameProjection(true, Real(0.05), Vector3(0.3, -0.1, 0.2));
}

TEST(PointConstraint, TwoStaticEndsAreNotMoved) {
  RigidBodyStates b = test::twoTurnedBodies(false);
  b.inverseMass[1] = 0;
  b.inverseInertia[1].setZero();
  const RigidBodyStates before = b;
  const Vector3 multiplier =
      projectPointConstraint(b, 0, 1, Vector3(0.1, 0, 0), Vector3(0, 0.2, 0));
  EXPECT_EQ(multiplier, Vector3::Zero());
  EXPECT_EQ(b.position, before.position);
}

TEST(PointConstraint, OneHardProjectionOfASmallErrorLeavesOnlyASecondOrderResidual) {
  // Newton's step on C(x, q): C after one projection is O(|C before|²) (the rotation update is
  // linearised). Halving the error must divide the residual by about 4 (at least 3).
  auto residualAfter = [](Real offset) {
    RigidBodyStates b = test::twoTurnedBodies(true);
    const Vector3 a0(0.25, -0.1, 0.4);
    const Vector3 c0 = b.position[0] + b.rotation[0] * a0;
    const Vector3 a1 =
        b.rotation[1].conjugate() * (c0 + offset * Vector3(0.3, -0.5, 0.2) - b.position[1]);
    projectPointConstraint(b, 0, 1, a0, a1);
    return ((b.position[1] + b.rotation[1] * a1) - (b.position[0] + b.rotation[0] * a0)).norm();
  };
  const Real coarse = residualAfter(Real(1e-2)), fine = residualAfter(Real(5e-3));
  EXPECT_GT(coarse / fine, 3.0);
  EXPECT_LT(coarse, 1e-3);
}

}  // namespace
}  // namespace pbd
