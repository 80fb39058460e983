// Generic rigid-body constraints (constraints/generic_rigid_constraint.h): the central-difference
// Jacobian against analytic gradients (a distance between body-fixed points, a relative
// orientation); C = 0 gives no correction; the projection moves with a rigid motion of the scene
// and conserves linear and angular momentum for a C invariant under rigid motions; singular K
// gives no correction; the construction limits. In a World: a generic ball joint makes a rigid
// compound pendulum of the closed-form period and follows the library's BallJoint (both step
// methods), with and without the user's gradient; a compliant generic constraint is a spring of
// stiffness 1/α (XPBD step) and its λ accumulates over the seed step's iterations. The
// allocation-free step is in test_world.cpp (GenericRigidConstraintWorld.StepAllocatesNothing).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "common/scene_fixtures.h"
#include "common/tolerances.h"
#include "pbd/constraints/generic_rigid_constraint.h"
#include "pbd/joints/joint_parts.h"
#include "pbd/math/quaternion.h"
#include "pbd/model/world.h"

namespace pbd {
namespace {

constexpr Real kPi = Real(3.14159265358979323846);

Vector3 bodyPoint(const GenericRigidPoses& p, int i, const Vector3& anchor) {
  return p.position[std::size_t(i)] + p.rotation[std::size_t(i)] * anchor;
}

// C = |p₁ − p₀| − L between the body-fixed points pᵢ = xᵢ + Rᵢ aᵢ. With n = (p₁ − p₀)/|p₁ − p₀|,
// rᵢ = Rᵢ aᵢ and δpᵢ = δxᵢ + δθᵢ × rᵢ: ∂C/∂x₀ = −n, ∂C/∂θ₀ = −r₀ × n, ∂C/∂x₁ = n, ∂C/∂θ₁ = r₁ × n.
struct PointDistance {
  Vector3 anchor0, anchor1;
  Real length;
  void operator()(const GenericRigidPoses& p, GenericRigidValue& c) const {
    c(0) = (bodyPoint(p, 1, anchor1) - bodyPoint(p, 0, anchor0)).norm() - length;
  }
};
struct PointDistanceGradient {
  Vector3 anchor0, anchor1;
  void operator()(const GenericRigidPoses& p, GenericRigidJacobian& j) const {
    const Vector3 r0 = p.rotation[0] * anchor0, r1 = p.rotation[1] * anchor1;
    const Vector3 n = (p.position[1] + r1 - p.position[0] - r0).normalized();
    j.block<1, 3>(0, 0) = -n.transpose();
    j.block<1, 3>(0, 3) = -r0.cross(n).transpose();
    j.block<1, 3>(0, 6) = n.transpose();
    j.block<1, 3>(0, 9) = r1.cross(n).transpose();
  }
};

// Three components over three bodies, each invariant under a common rigid motion:
//   C₀ = |p₁ − p₀| − L                      (as above)
//   C₁ = v₁·v₂ − c,  vᵢ = Rᵢ uᵢ              ∂/∂θ₁ = v₁ × v₂, ∂/∂θ₂ = v₂ × v₁ (δvᵢ = δθᵢ × vᵢ)
//   C₂ = (p₂ − p₀)·v₁ − e,  d = p₂ − p₀      ∂/∂x₀ = −v₁, ∂/∂θ₀ = −r₀ × v₁, ∂/∂θ₁ = v₁ × d,
//                                           ∂/∂x₂ = v₁, ∂/∂θ₂ = r₂ × v₁
struct ThreeBodyShape {
  Vector3 a0, a1, a2, u1, u2;
  Real length, cosine, offset;
  void operator()(const GenericRigidPoses& p, GenericRigidValue& c) const {
    const Vector3 p0 = bodyPoint(p, 0, a0), p1 = bodyPoint(p, 1, a1), p2 = bodyPoint(p, 2, a2);
    const Vector3 v1 = p.rotation[1] * u1, v2 = p.rotation[2] * u2;
    c(0) = (p1 - p0).norm() - length;
    c(1) = v1.dot(v2) - cosine;
    c(2) = (p2 - p0).dot(v1) - offset;
  }
};
struct ThreeBodyShapeGradient {
  Vector3 a0, a1, a2, u1, u2;
  void operator()(const GenericRigidPoses& p, GenericRigidJacobian& j) const {
    const Vector3 r0 = p.rotation[0] * a0, r1 = p.rotation[1] * a1, r2 = p.rotation[2] * a2;
    const Vector3 p0 = p.position[0] + r0, p1 = p.position[1] + r1, p2 = p.position[2] + r2;
    const Vector3 v1 = p.rotation[1] * u1, v2 = p.rotation[2] * u2;
    const Vector3 n = (p1 - p0).normalized(), d = p2 - p0;
    j.block<1, 3>(0, 0) = -n.transpose();
    j.block<1, 3>(0, 3) = -r0.cross(n).transpose();
    j.block<1, 3>(0, 6) = n.transpose();
    j.block<1, 3>(0, 9) = r1.cross(n).transpose();
    j.block<1, 3>(1, 9) = v1.cross(v2).transpose();
    j.block<1, 3>(1, 15) = v2.cross(v1).transpose();
    j.block<1, 3>(2, 0) = -v1.transpose();
    j.block<1, 3>(2, 3) = -r0.cross(v1).transpose();
    j.block<1, 3>(2, 9) = v1.cross(d).transpose();
    j.block<1, 3>(2, 12) = v1.transpose();
    j.block<1, 3>(2, 15) = r2.cross(v1).transpose();
  }
};

const Vector3 kA0(0.2, -0.1, 0.3), kA1(-0.3, 0.25, 0.1), kA2(0.1, 0.1, -0.35);
const Vector3 kU1 = Vector3(1, 0.5, -0.2).normalized(), kU2 = Vector3(-0.3, 1, 0.4).normalized();

GenericRigidConstraint shapeConstraint(bool analytic, Real length = Real(0.9),
                                       Real cosine = Real(0.2), Real offset = Real(0.3)) {
  return GenericRigidConstraint(
      {0, 1, 2}, 3, ThreeBodyShape{kA0, kA1, kA2, kU1, kU2, length, cosine, offset},
      analytic ? GenericRigidGradientFunction(ThreeBodyShapeGradient{kA0, kA1, kA2, kU1, kU2})
               : GenericRigidGradientFunction());
}

/// Three bodies in general poses (positions below 1 m: the finite-difference step is ε^(1/3)).
GenericRigidPoses threePoses() {
  GenericRigidPoses p;
  p.position[0] = Vector3(0.1, 0.4, -0.2);
  p.position[1] = Vector3(0.8, -0.3, 0.5);
  p.position[2] = Vector3(-0.5, 0.6, 0.7);
  p.rotation[0] = quaternionFromAxisAngle(Vector3(1, 2, 3).normalized(), Real(0.7));
  p.rotation[1] = quaternionFromAxisAngle(Vector3(-2, 1, 0.5).normalized(), Real(2.1));
  p.rotation[2] = quaternionFromAxisAngle(Vector3(0.3, -1, 1).normalized(), Real(-1.2));
  return p;
}

/// Masses 1, 2, 0.5 kg with distinct principal moments, world inverse inertias R D⁻¹ Rᵀ.
struct ThreeBodies {
  std::array<Real, 3> mass{1, 2, Real(0.5)};
  std::array<Vector3, 3> inertia{Vector3(0.1, 0.2, 0.3), Vector3(0.05, 0.4, 0.25),
                                 Vector3(0.3, 0.1, 0.15)};
  Matrix3 worldInertia(const GenericRigidPoses& p, int i) const {
    const Matrix3 r = p.rotation[std::size_t(i)].toRotationMatrix();
    return r * inertia[std::size_t(i)].asDiagonal() * r.transpose();
  }
  GenericRigidInverseMasses inverse(const GenericRigidPoses& p) const {
    GenericRigidInverseMasses w{};
    for (int i = 0; i < 3; ++i) {
      const Matrix3 r = p.rotation[std::size_t(i)].toRotationMatrix();
      w[std::size_t(i)] = {1 / mass[std::size_t(i)],
                           r * inertia[std::size_t(i)].cwiseInverse().asDiagonal() * r.transpose()};
    }
    return w;
  }
};

TEST(GenericRigidConstraint, FiniteDifferenceJacobianMatchesTheAnalyticGradient) {
  const GenericRigidPoses poses = threePoses();
  GenericRigidJacobian exact, approximate;
  shapeConstraint(true).jacobian(poses, exact);
  shapeConstraint(false).jacobian(poses, approximate);
  const Real error = (exact - approximate).cwiseAbs().maxCoeff();
  std::printf("  central differences vs analytic: max entry error %.2e (entries up to %.2f)\n",
              double(error), double(exact.cwiseAbs().maxCoeff()));
  // Central differences with h = ε^(1/3) (positions below 1 m, angles about 0): truncation
  // (h²/6) C''' plus cancellation ε |C| / h, each about ε^(2/3) for C, its derivatives and
  // lever arms of order 1 m — within the shared tolerance 100 ε^(2/3).
  EXPECT_LE(error, test::finiteDifferenceTolerance());
  // ... and it is the finite differences' error, not an exact copy.
  EXPECT_GT(error, 0);
  // The unused block (rows ≥ dim, columns ≥ 6N) stays zero.
  EXPECT_TRUE(approximate.bottomRows(3).isZero(0));
  EXPECT_TRUE(approximate.rightCols(6).isZero(0));
  // The analytic gradient's convention, checked independently of the library's differences:
  // central differences over rotations by ±φ about each world axis (Eigen's AngleAxis, applied
  // on the left) and over ±φ shifts of the centres of mass, φ = ε^(1/3): the same error budget,
  // 100 ε^(2/3).
  const Real phi = test::finiteDifferenceStep();
  const GenericRigidConstraint shape = shapeConstraint(true);
  for (int i = 0; i < 3; ++i)
    for (int c = 0; c < 6; ++c) {
      GenericRigidPoses plus = poses, minus = poses;
      const auto b = std::size_t(i);
      if (c < 3) {
        plus.position[b](c) += phi;
        minus.position[b](c) -= phi;
      } else {
        const Vector3 axis = Vector3::Unit(c - 3);
        plus.rotation[b] = quaternionFromAxisAngle(axis, phi) * poses.rotation[b];
        minus.rotation[b] = quaternionFromAxisAngle(axis, -phi) * poses.rotation[b];
      }
      GenericRigidValue above, below;
      shape.evaluate(plus, above);
      shape.evaluate(minus, below);
      const Eigen::Matrix<Real, 3, 1> slope = (above.head(3) - below.head(3)) / (2 * phi);
      EXPECT_NEAR((slope - exact.col(6 * i + c).head(3)).norm(), 0,
                  test::finiteDifferenceTolerance())
          << "body " << i << " coordinate " << c;
    }
}

TEST(GenericRigidConstraint, SatisfiedConstraintGivesNoCorrection) {
  const GenericRigidPoses poses = threePoses();
  // The rest values at these poses: C = 0 by construction (the same arithmetic).
  const Vector3 p0 = bodyPoint(poses, 0, kA0), p1 = bodyPoint(poses, 1, kA1),
                p2 = bodyPoint(poses, 2, kA2);
  const Vector3 v1 = poses.rotation[1] * kU1, v2 = poses.rotation[2] * kU2;
  const ThreeBodies bodies;
  for (bool analytic : {true, false})
    for (Real complianceTilde : {Real(0), Real(3)}) {
      const GenericRigidConstraint c =
          shapeConstraint(analytic, (p1 - p0).norm(), v1.dot(v2), (p2 - p0).dot(v1));
      GenericRigidValue value;
      c.evaluate(poses, value);
      ASSERT_TRUE(value.head(3).isZero(0));
      const GenericRigidCorrection correction = genericRigidProjection(
          c, poses, bodies.inverse(poses), complianceTilde, GenericRigidValue::Zero());
      // K is regular: the solve ran and K⁻¹ 0 = 0 exactly.
      ASSERT_TRUE(correction.applied);
      for (std::size_t i = 0; i < 3; ++i) {
        EXPECT_EQ(correction.linear[i], Vector3::Zero());
        EXPECT_EQ(correction.angular[i], Vector3::Zero());
      }
      EXPECT_EQ(correction.multiplier, GenericRigidValue::Zero());
    }
}

/// L-changes of one projection: Σ mᵢ Δxᵢ and Σ (mᵢ xᵢ × Δxᵢ + I_w,ᵢ Δθᵢ).
std::pair<Vector3, Vector3> momentumChange(const ThreeBodies& b, const GenericRigidPoses& p,
                                           const GenericRigidCorrection& c) {
  Vector3 linear = Vector3::Zero(), angular = Vector3::Zero();
  for (int i = 0; i < 3; ++i) {
    const auto k = std::size_t(i);
    linear += b.mass[k] * c.linear[k];
    angular += b.mass[k] * p.position[k].cross(c.linear[k]) + b.worldInertia(p, i) * c.angular[k];
  }
  return {linear, angular};
}

TEST(GenericRigidConstraint, RigidMotionInvariantConstraintConservesMomentum) {
  const GenericRigidPoses poses = threePoses();
  const ThreeBodies bodies;
  for (bool analytic : {true, false}) {
    // The rest values (0.9 m, 0.2, 0.3 m) are not those of these poses: a large violation.
    const GenericRigidCorrection c = genericRigidProjection(
        shapeConstraint(analytic), poses, bodies.inverse(poses), 0, GenericRigidValue::Zero());
    ASSERT_TRUE(c.applied);
    const auto [linear, angular] = momentumChange(bodies, poses, c);
    Real scale = 0;  // the size of the individual terms
    for (std::size_t i = 0; i < 3; ++i)
      scale = std::max(scale, bodies.mass[i] * c.linear[i].norm());
    std::printf(
        "  momentum (%s): |sum m dx| = %.2e, |sum m x x dx + I dtheta| = %.2e "
        "(terms up to %.2e)\n",
        analytic ? "analytic" : "central differences", double(linear.norm()),
        double(angular.norm()), double(scale));
    ASSERT_GT(scale, 0.01);  // the projection did move the bodies
    // Exact identities for the analytic J (Σ J_x = 0, Σ J_θ − J_x [x]× = 0): round-off of a few
    // sums of O(scale) terms (64 ε · scale). With central differences the identities hold to
    // the Jacobian's error 100 ε^(2/3) times |Δλ| ≤ ~10 scale (conservatively).
    const Real tolerance =
        analytic ? 64 * kEpsilon * scale : 10 * scale * test::finiteDifferenceTolerance();
    EXPECT_NEAR(linear.norm(), 0, tolerance) << analytic;
    EXPECT_NEAR(angular.norm(), 0, tolerance) << analytic;
  }
  // The poses actually written (normalise(q + ½ (0, Δθ) q) is a rotation by 2 atan(|Δθ|/2) =
  // |Δθ| (1 − |Δθ|²/12 + …)): for a tiny violation (10⁻⁶ m, 10⁻⁶), the rotation vectors of the
  // written poses conserve the angular momentum to the third-order term, |I Δθ| |Δθ|²/12,
  // far below round-off here; we allow round-off of the poses (16 ε of |x| ~ 1 m) times m.
  // In float a 10⁻⁶ violation is a few ulps of the poses: double only.
  if (sizeof(Real) < 8) return;
  GenericRigidValue rest;
  shapeConstraint(true).evaluate(poses, rest);
  const Real tiny = Real(1e-6);
  const GenericRigidConstraint nearlySatisfied = shapeConstraint(
      true, rest(0) + Real(0.9) - tiny, rest(1) + Real(0.2) + tiny, rest(2) + Real(0.3) - tiny);
  const GenericRigidCorrection c = genericRigidProjection(
      nearlySatisfied, poses, bodies.inverse(poses), 0, GenericRigidValue::Zero());
  ASSERT_TRUE(c.applied);
  RigidBodyStates states;
  states.resize(3);
  Vector3 angular = Vector3::Zero();
  for (std::size_t i = 0; i < 3; ++i) {
    states.position[i] = poses.position[i];
    states.rotation[i] = poses.rotation[i];
    states.inverseMass[i] = 1 / bodies.mass[i];
    joint_parts::applyPositionCorrection(states, int(i), c.linear[i], c.angular[i]);
    const AngleAxis turn(withPositiveScalar(states.rotation[i] * poses.rotation[i].conjugate()));
    const Vector3 rotationVector = turn.angle() * turn.axis();
    angular += bodies.mass[i] * poses.position[i].cross(states.position[i] - poses.position[i]) +
               bodies.worldInertia(poses, int(i)) * rotationVector;
  }
  EXPECT_GT(c.angular[1].norm(), 1e-8);  // the bodies did turn
  EXPECT_NEAR(angular.norm(), 0, 16 * kEpsilon * 2);
}

TEST(GenericRigidConstraint, CorrectionsMoveWithARigidMotionOfTheScene) {
  // Translating all bodies by t and rotating them by Q about the origin maps every correction
  // by Q (linear and angular alike) — the projection is frame-independent for a C invariant
  // under rigid motions.
  const GenericRigidPoses poses = threePoses();
  const Quaternion q = quaternionFromAxisAngle(Vector3(0.4, -1, 0.6).normalized(), Real(0.9));
  const Vector3 t(0.3, -0.2, 0.1);
  GenericRigidPoses moved = poses;
  for (std::size_t i = 0; i < 3; ++i) {
    moved.position[i] = q * poses.position[i] + t;
    moved.rotation[i] = q * poses.rotation[i];
  }
  const ThreeBodies bodies;
  for (bool analytic : {true, false}) {
    const GenericRigidConstraint c = shapeConstraint(analytic);
    const GenericRigidCorrection here =
        genericRigidProjection(c, poses, bodies.inverse(poses), 0, GenericRigidValue::Zero());
    const GenericRigidCorrection there =
        genericRigidProjection(c, moved, bodies.inverse(moved), 0, GenericRigidValue::Zero());
    ASSERT_TRUE(here.applied && there.applied);
    // Analytic: round-off of O(0.1) corrections through a 3 × 3 solve (1000 ε, generous for
    // K's condition number of ~10²). Central differences: their error along the world axes is
    // not equivariant, 100 ε^(2/3) of the O(1) Jacobian entries times |Δλ| of O(1).
    const Real tolerance = analytic ? 1000 * kEpsilon : 10 * test::finiteDifferenceTolerance();
    for (std::size_t i = 0; i < 3; ++i) {
      EXPECT_NEAR((there.linear[i] - q * here.linear[i]).norm(), 0, tolerance) << analytic;
      EXPECT_NEAR((there.angular[i] - q * here.angular[i]).norm(), 0, tolerance) << analytic;
    }
    // The multipliers are scalars of C: unchanged.
    EXPECT_NEAR((there.multiplier - here.multiplier).norm(), 0, tolerance) << analytic;
  }
}

TEST(GenericRigidConstraint, OneSolveOfALinearConstraintIsExactAndComplianceScalesIt) {
  // C = y₀ − 1 on one body (y₀ its centre of mass's y; q not read): linear, so one hard solve
  // lands on C = 0: Δy = 1 − y. With compliance, K = 1/m + α̃ and Δλ = −C/(1/m + α̃) (closed form).
  auto value = [](const GenericRigidPoses& p, GenericRigidValue& c) {
    c(0) = p.position[0].y() - 1;
  };
  GenericRigidPoses poses;
  poses.position[0] = Vector3(0.2, 0.3, -0.1);
  GenericRigidInverseMasses w{};
  w[0] = {Real(0.5), Matrix3::Identity()};
  for (Real complianceTilde : {Real(0), Real(2)}) {
    const GenericRigidCorrection c =
        genericRigidProjection(GenericRigidConstraint({0}, 1, value), poses, w, complianceTilde,
                               GenericRigidValue::Zero());
    ASSERT_TRUE(c.applied);
    const Real multiplier = Real(0.7) / (Real(0.5) + complianceTilde);
    // Central differences of a linear C: cancellation only, ε^(2/3) relative (100 ε^(2/3)).
    EXPECT_NEAR(c.multiplier(0), multiplier, test::finiteDifferenceTolerance());
    EXPECT_NEAR((c.linear[0] - Vector3(0, Real(0.5) * multiplier, 0)).norm(), 0,
                test::finiteDifferenceTolerance());
    // No rotation: ∂C/∂θ is exactly zero (C does not read q).
    EXPECT_EQ(c.angular[0], Vector3::Zero());
  }
}

void expectNoCorrection(const GenericRigidCorrection& c) {
  EXPECT_FALSE(c.applied);
  for (std::size_t i = 0; i < std::size_t(kGenericRigidMaxBodies); ++i) {
    EXPECT_EQ(c.linear[i], Vector3::Zero());
    EXPECT_EQ(c.angular[i], Vector3::Zero());
  }
  EXPECT_EQ(c.multiplier, GenericRigidValue::Zero());
}

TEST(GenericRigidConstraint, SingularSystemGivesNoCorrectionAndNoNaN) {
  const GenericRigidPoses poses = threePoses();
  // Every body static: K = 0 (even with a compliance: nothing can move).
  for (bool analytic : {true, false})
    for (Real complianceTilde : {Real(0), Real(1)})
      expectNoCorrection(genericRigidProjection(shapeConstraint(analytic), poses,
                                                GenericRigidInverseMasses{}, complianceTilde,
                                                GenericRigidValue::Zero()));
  // Redundant components C₁ = 2 C₀: K of rank 1 (a zero pivot, to round-off with the analytic
  // gradient and to the square of the central differences' error without it).
  auto redundant = [](const GenericRigidPoses& p, GenericRigidValue& c) {
    c(0) = p.position[0].x() + (p.rotation[0] * Vector3::UnitY()).z() - 1;
    c(1) = 2 * c(0);
  };
  auto redundantGradient = [](const GenericRigidPoses& p, GenericRigidJacobian& j) {
    const Vector3 v = p.rotation[0] * Vector3::UnitY();
    j(0, 0) = 1;
    j.block<1, 3>(0, 3) = v.cross(Vector3::UnitZ()).transpose();  // δv = δθ × v
    j.row(1) = 2 * j.row(0);
  };
  const ThreeBodies bodies;
  for (bool analytic : {true, false})
    expectNoCorrection(genericRigidProjection(
        GenericRigidConstraint({0}, 2, redundant,
                               analytic ? GenericRigidGradientFunction(redundantGradient)
                                        : GenericRigidGradientFunction()),
        poses, bodies.inverse(poses), 0, GenericRigidValue::Zero()));
  // A NaN value, and a constant C (zero gradient).
  auto notANumber = [](const GenericRigidPoses&, GenericRigidValue& c) { c(0) = std::nan(""); };
  auto constant = [](const GenericRigidPoses&, GenericRigidValue& c) { c(0) = 1; };
  expectNoCorrection(genericRigidProjection(GenericRigidConstraint({0}, 1, notANumber), poses,
                                            bodies.inverse(poses), 0, GenericRigidValue::Zero()));
  expectNoCorrection(genericRigidProjection(GenericRigidConstraint({0}, 1, constant), poses,
                                            bodies.inverse(poses), 0, GenericRigidValue::Zero()));
}

/// The message of the std::invalid_argument thrown by `make` ("" if none).
template <typename F>
std::string invalidArgumentMessage(F make) {
  try {
    make();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(GenericRigidConstraint, LimitsAreCheckedAtConstructionWithClearMessages) {
  auto value = [](const GenericRigidPoses&, GenericRigidValue& c) { c.setZero(); };
  const auto has = [](const std::string& message, const std::string& part) {
    return message.find(part) != std::string::npos;
  };
  std::string m = invalidArgumentMessage([&] {
    GenericRigidConstraint({0, 1, 2, 3, 4}, 1, value);
  });
  EXPECT_TRUE(has(m, "5 bodies; 1 to 4 are supported")) << m;
  m = invalidArgumentMessage([&] { GenericRigidConstraint({}, 1, value); });
  EXPECT_TRUE(has(m, "0 bodies")) << m;
  m = invalidArgumentMessage([&] { GenericRigidConstraint({0}, 7, value); });
  EXPECT_TRUE(has(m, "7 components; 1 to 6 are supported")) << m;
  m = invalidArgumentMessage([&] { GenericRigidConstraint({0}, 0, value); });
  EXPECT_TRUE(has(m, "0 components")) << m;
  m = invalidArgumentMessage([&] { GenericRigidConstraint({0}, 1, GenericRigidValueFunction()); });
  EXPECT_TRUE(has(m, "no value function")) << m;
  m = invalidArgumentMessage([&] { GenericRigidConstraint({2, 2}, 1, value); });
  EXPECT_TRUE(has(m, "body 2 appears twice")) << m;
  m = invalidArgumentMessage([&] { GenericRigidConstraint({-1}, 1, value); });
  EXPECT_TRUE(has(m, "negative body index -1")) << m;
  m = invalidArgumentMessage([&] { GenericRigidConstraint({0}, 1, value, {}, Real(1.5)); });
  EXPECT_TRUE(has(m, "stiffness")) << m;
  m = invalidArgumentMessage([&] { GenericRigidConstraint({0}, 1, value, {}, 1, Real(-1)); });
  EXPECT_TRUE(has(m, "compliance")) << m;
  EXPECT_TRUE(has(m, "generic rigid-body constraint")) << m;  // every message names the family
  EXPECT_NO_THROW(GenericRigidConstraint({0, 1, 2, 3}, 6, value));  // the limits themselves
  // A body index beyond the world's: std::out_of_range from the solve, nothing moved.
  std::vector<GenericRigidConstraint> constraints{GenericRigidConstraint(
      {0, 5}, 1,
      [](const GenericRigidPoses& p, GenericRigidValue& c) { c(0) = p.position[0].x() - 1; })};
  RigidBodyStates states;
  states.resize(2);
  EXPECT_THROW(solveGenericRigidConstraints(constraints, states, Real(0.001), true),
               std::out_of_range);
}

// --- In a World ----------------------------------------------------------------------------

constexpr Real kGravity = Real(9.81);
const Vector3 kPivot(0, 2, 0);

/// A static box (index 0) at the pivot and a 0.1 × 0.4 × 0.1 m box of 0.4 kg (index 1) whose
/// centre of mass is d = 1 m from the pivot, θ₀ off the vertical in the x–y plane; with a
/// BallJoint at the pivot if `ballJoint`. h = 5 ms, 5 substeps (h_s = 1 ms) in both steps.
Scene pendulumScene(StepMethod stepMethod, Real theta0, bool ballJoint) {
  Scene s;
  s.simulation.stepMethod = stepMethod;
  s.simulation.timeStepSize = Real(0.005);
  s.simulation.subSteps = 5;
  s.simulation.xpbd.substeps = 5;
  s.rigidBodies.push_back(test::boxBody(0, Vector3(0.2, 0.2, 0.2), kPivot, 1, false));
  s.rigidBodies.push_back(test::boxBody(
      1, Vector3(0.1, 0.4, 0.1), kPivot + Vector3(std::sin(theta0), -std::cos(theta0), 0), 100));
  if (ballJoint) {
    JointDesc j = test::makeJointDesc(JointType::Ball, 0, 1);
    j.position = kPivot;
    s.joints.push_back(j);
  }
  return s;
}

/// C = c₁ − c₀ ∈ R³, cᵢ = xᵢ + Rᵢ aᵢ (the ball joint's rows, joint_parts::setPointRows):
/// ∂C/∂x₀ = −𝟙, ∂C/∂θ₀ = [r₀]×, ∂C/∂x₁ = 𝟙, ∂C/∂θ₁ = −[r₁]×.
struct BallValue {
  Vector3 anchor0, anchor1;
  void operator()(const GenericRigidPoses& p, GenericRigidValue& c) const {
    c.head<3>() = bodyPoint(p, 1, anchor1) - bodyPoint(p, 0, anchor0);
  }
};
struct BallGradient {
  Vector3 anchor0, anchor1;
  void operator()(const GenericRigidPoses& p, GenericRigidJacobian& j) const {
    j.block<3, 3>(0, 0) = -Matrix3::Identity();
    j.block<3, 3>(0, 3) = crossMatrix(p.rotation[0] * anchor0);
    j.block<3, 3>(0, 6) = Matrix3::Identity();
    j.block<3, 3>(0, 9) = -crossMatrix(p.rotation[1] * anchor1);
  }
};

/// A generic ball joint at `point` between bodies 0 and 1 of `world` (anchors from the poses).
GenericRigidConstraint genericBall(const World& world, const Vector3& point, bool analytic) {
  const RigidBodyStates& b = world.bodies.rigid;
  const Vector3 a0 = b.rotation[0].conjugate() * (point - b.position[0]);
  const Vector3 a1 = b.rotation[1].conjugate() * (point - b.position[1]);
  return GenericRigidConstraint({0, 1}, 3, BallValue{a0, a1},
                                analytic ? GenericRigidGradientFunction(BallGradient{a0, a1})
                                         : GenericRigidGradientFunction());
}

struct SwingRecord {
  Real period = 0;
  Real worstJointError = 0;  ///< max |C| after a step
  Real jointErrorBound = 0;  ///< max δ/100 (see below) plus round-off
};

/// Steps `world` for `steps` steps; the period from the zero crossings of the angle (linearly
/// interpolated); the joint error |C| after every step against the substep bound of
/// common/joint_hold.h: the prediction moves the joint off by δ = h_s² (|a| + (|ω|² + |α|) ℓ)
/// (a, ω, α measured from body 1's motion), a Newton projection with the exact Jacobian leaves
/// O(δ²/ℓ) ≪ δ/100.
SwingRecord swing(World& world, int steps, const GenericRigidConstraint& joint) {
  const auto& b = world.bodies.rigid;
  const Real h = world.settings.timeStepSize;
  const Real hs =
      h / Real(world.settings.stepMethod == StepMethod::Xpbd ? world.settings.xpbd.substeps
                                                             : world.settings.subSteps);
  const Real lever = (b.position[1] - kPivot).norm();
  SwingRecord record;
  std::vector<Real> crossings;
  Real previousAngle = std::atan2(b.position[1].x() - kPivot.x(), kPivot.y() - b.position[1].y());
  Real maxDelta = 0;
  for (int n = 0; n < steps; ++n) {
    const Vector3 v = b.velocity[1], omega = b.angularVelocity[1];
    const Real t0 = world.time;
    world.step();
    const Real angle = std::atan2(b.position[1].x() - kPivot.x(), kPivot.y() - b.position[1].y());
    if ((previousAngle > 0) != (angle > 0))
      crossings.push_back(t0 + (world.time - t0) * previousAngle / (previousAngle - angle));
    previousAngle = angle;
    const Real accel = (b.velocity[1] - v).norm() / h;
    const Real angularAccel = (b.angularVelocity[1] - omega).norm() / h;
    maxDelta = std::max(maxDelta, hs * hs * (accel + (omega.squaredNorm() + angularAccel) * lever));
    GenericRigidPoses poses;
    for (std::size_t i = 0; i < 2; ++i) {
      poses.position[i] = b.position[i];
      poses.rotation[i] = b.rotation[i];
    }
    GenericRigidValue c;
    joint.evaluate(poses, c);
    record.worstJointError = std::max(record.worstJointError, c.head<3>().norm());
  }
  // Round-off floor as in common/joint_hold.h: positions of ~2 m carry ~100 ε |x| per step.
  record.jointErrorBound = maxDelta / 100 + 100 * kEpsilon * 2;
  if (crossings.size() >= 2)
    record.period =
        2 * (crossings.back() - crossings.front()) / static_cast<Real>(crossings.size() - 1);
  return record;
}

// A rigid compound pendulum on a generic ball joint: small-angle period
//   T = 2π √(I_p / (m g d)),  I_p = I_zz + m d²  (I_zz = m (0.1² + 0.4²)/12, d = 1 m),
// released at θ₀ = 0.02 rad (the finite-amplitude correction θ₀²/16 = 2.5·10⁻⁵ of T). The
// steps' own phase error: both are first-order projections after an explicit prediction, whose
// period error is O((ω h_s)²) = 10⁻⁵ at ω = 3.1 rad/s, h_s = 1 ms; crossings interpolated
// linearly between 5 ms steps near θ = 0, where θ(t) is nearly linear (third order: 10⁻⁷). We
// allow 10⁻⁴ of T. The same scene with the library's BallJoint solves the same equations
// (K = Σ J W Jᵀ, Δλ = −K⁻¹C): with the analytic gradient the trajectories differ by round-off
// only, which a non-chaotic pendulum accumulates at most linearly — bound steps · 1000 ε (the
// two solves round differently: pivoted LDLᵀ vs the direct 3 × 3 of point_constraint.h, with
// positions of 2 m); with central differences, by the Jacobian's error 100 ε^(2/3) per step
// times the correction (≤ 10⁻⁵ m), accumulated linearly — bound steps · 100 ε^(2/3) (generous).
TEST(GenericRigidConstraintWorld, BallJointPendulumHasTheCompoundPeriodAndFollowsBallJoint) {
  if (sizeof(Real) < 8) GTEST_SKIP() << "period to 1e-4 over 2000 steps: double only";
  const Real theta0 = Real(0.02);
  const int steps = 2000;  // 10 s, about 5 periods
  for (StepMethod stepMethod : {StepMethod::Seed, StepMethod::Xpbd}) {
    World reference = buildWorld(pendulumScene(stepMethod, theta0, true));
    World exact = buildWorld(pendulumScene(stepMethod, theta0, false));
    World approximate = buildWorld(pendulumScene(stepMethod, theta0, false));
    exact.constraints.genericRigidConstraints.push_back(genericBall(exact, kPivot, true));
    approximate.constraints.genericRigidConstraints.push_back(
        genericBall(approximate, kPivot, false));
    const auto& b = exact.bodies.rigid;
    const Real m = b.mass[1], d = (b.position[1] - kPivot).norm();
    const Real inertiaPivot = b.inertiaWorld(1)(2, 2) + m * d * d;
    const Real expectedPeriod = 2 * kPi * std::sqrt(inertiaPivot / (m * kGravity * d));
    ASSERT_NEAR(m, 0.4, 1e-12);
    ASSERT_NEAR(d, 1, 1e-12);

    const SwingRecord exactSwing =
        swing(exact, steps, exact.constraints.genericRigidConstraints[0]);
    const SwingRecord approximateSwing =
        swing(approximate, steps, approximate.constraints.genericRigidConstraints[0]);
    for (int n = 0; n < steps; ++n)
      reference.step();
    const char* name = stepMethod == StepMethod::Seed ? "seed" : "xpbd";
    const Real exactDeviation = (b.position[1] - reference.bodies.rigid.position[1]).norm();
    const Real approximateDeviation =
        (approximate.bodies.rigid.position[1] - reference.bodies.rigid.position[1]).norm();
    const Real gradientDeviation = (approximate.bodies.rigid.position[1] - b.position[1]).norm();
    std::printf(
        "  generic ball pendulum (%s): T = %.6f s, closed form %.6f s (%.2e), joint "
        "error %.2e m (bound %.2e m), vs BallJoint %.2e m (gradient) %.2e m (central "
        "differences), with vs without gradient %.2e m\n",
        name, double(exactSwing.period), double(expectedPeriod),
        double(exactSwing.period / expectedPeriod - 1), double(exactSwing.worstJointError),
        double(exactSwing.jointErrorBound), double(exactDeviation), double(approximateDeviation),
        double(gradientDeviation));
    EXPECT_NEAR(exactSwing.period, expectedPeriod, Real(1e-4) * expectedPeriod) << name;
    EXPECT_NEAR(approximateSwing.period, expectedPeriod, Real(1e-4) * expectedPeriod) << name;
    EXPECT_LE(exactSwing.worstJointError, exactSwing.jointErrorBound) << name;
    EXPECT_LE(approximateSwing.worstJointError, approximateSwing.jointErrorBound) << name;
    EXPECT_LE(exactDeviation, steps * 1000 * kEpsilon) << name;
    EXPECT_LE(approximateDeviation, steps * test::finiteDifferenceTolerance()) << name;
    EXPECT_LE(gradientDeviation, steps * test::finiteDifferenceTolerance()) << name;
    // It swung: the body crossed the vertical about ten times.
    EXPECT_GT(exactSwing.period, 0) << name;
  }
}

// A compliant generic constraint C = x − 1 (x the body's centre-of-mass coordinate; linear) on a
// free 1 kg box without gravity, started at C = 0 with v₀ = 0.1 m/s: a spring of stiffness
// k = 1/α, here ω = 2π rad/s. One XPBD solve per substep of a linear constraint is implicit
// Euler, period 2π h_s / atan(ω h_s) (10⁻⁶ relative at h_s = 0.25 ms), and λ/h_s² = −C/α after
// every substep (C + α̃ λ = 0 exactly for a linear C). In the seed's step with 4 iterations λ
// accumulates: the later iterations find C + α̃ λ = 0 and change nothing, so the trajectory is
// that of 1 iteration (with λ reset between iterations each would add about −C/α̃ again: a
// spring about 4× as stiff, far outside the bound below).
Scene freeBoxScene(StepMethod stepMethod, int iterations) {
  Scene s;
  s.simulation.stepMethod = stepMethod;
  s.simulation.timeStepSize = Real(0.005);
  s.simulation.subSteps = 20;
  s.simulation.xpbd.substeps = 20;
  s.simulation.maxIterations = iterations;
  s.simulation.gravitation = Vector3::Zero();
  RigidBodyDesc box = test::boxBody(0, Vector3::Constant(Real(0.1)), Vector3(1, 0, 0), 1000);
  box.velocity = Vector3(Real(0.1), 0, 0);
  s.rigidBodies.push_back(box);
  return s;
}

TEST(GenericRigidConstraintWorld, CompliantConstraintIsASpringAndItsMultiplierAccumulates) {
  if (sizeof(Real) < 8) GTEST_SKIP() << "25 um per substep at x = 1 m: float round-off";
  const Real omega = 2 * kPi, mass = 1;
  const Real alpha = 1 / (mass * omega * omega);
  auto value = [](const GenericRigidPoses& p, GenericRigidValue& c) {
    c(0) = p.position[0].x() - 1;
  };
  auto gradient = [](const GenericRigidPoses&, GenericRigidJacobian& j) { j(0, 0) = 1; };
  World xpbd = buildWorld(freeBoxScene(StepMethod::Xpbd, 1));
  ASSERT_NEAR(xpbd.bodies.rigid.mass[0], mass, 1e-12);
  xpbd.constraints.genericRigidConstraints.emplace_back(std::vector<int>{0}, 1, value, gradient, 1,
                                                        alpha);
  const Real hs = Real(0.005) / 20;
  std::vector<Real> crossings;
  Real previous = 0, worstForceError = 0;
  for (int n = 0; n < 400; ++n) {  // 2 s
    const Real t0 = xpbd.time;
    xpbd.step();
    const Real c = xpbd.bodies.rigid.position[0].x() - 1;
    if (n > 0 && (previous > 0) != (c > 0))
      crossings.push_back(t0 + (xpbd.time - t0) * previous / (previous - c));
    previous = c;
    const Real force = xpbd.constraints.genericRigidConstraints[0].multiplier()(0) / (hs * hs);
    worstForceError = std::max(worstForceError, std::abs(force + c / alpha));
  }
  ASSERT_GE(crossings.size(), 3u);
  const Real period =
      2 * (crossings.back() - crossings.front()) / static_cast<Real>(crossings.size() - 1);
  const Real expected = 2 * kPi * hs / std::atan(omega * hs);
  const Real amplitudeForce = (1 / alpha) * Real(0.1) / omega;  // k A
  std::printf(
      "  compliant generic constraint: T = %.7f s (implicit Euler %.7f s), force error "
      "%.2e of k A\n",
      double(period), double(expected), double(worstForceError / amplitudeForce));
  // The crossing interpolation between 5 ms steps: O((ω h)²) = 10⁻³ of a quarter period at
  // worst, averaged over the crossings; 10⁻⁴ of T (as the compliant distance joint's test).
  EXPECT_NEAR(period, expected, Real(1e-4) * expected);
  // λ/h² = −C/α: round-off of C ~ 16 mm computed from x = 1 m (a few ε |x| = 60 ε of A) and of
  // λ through K (1000 ε of k A, as in test_xpbd_joints.cpp).
  EXPECT_LE(worstForceError, 1000 * kEpsilon * amplitudeForce);

  // The seed's step: 1 and 4 iterations give the same trajectory (λ accumulates), up to the
  // round-off of the extra, vanishing corrections (≤ 16 ε |x| per iteration, 3 · 20 · 400 of
  // them, linearly: 4·10⁵ · 16 ε).
  World once = buildWorld(freeBoxScene(StepMethod::Seed, 1));
  World fourTimes = buildWorld(freeBoxScene(StepMethod::Seed, 4));
  once.constraints.genericRigidConstraints.emplace_back(std::vector<int>{0}, 1, value, gradient, 1,
                                                        alpha);
  fourTimes.constraints.genericRigidConstraints.emplace_back(std::vector<int>{0}, 1, value,
                                                             gradient, 1, alpha);
  Real deviation = 0;  // the largest, over the run (at 2 s a 4× stiffer spring is back in phase)
  for (int n = 0; n < 400; ++n) {
    once.step();
    fourTimes.step();
    deviation = std::max(deviation, std::abs(once.bodies.rigid.position[0].x() -
                                             fourTimes.bodies.rigid.position[0].x()));
  }
  std::printf("  seed step, 1 vs 4 iterations: at most %.2e m apart\n", double(deviation));
  EXPECT_LE(deviation, Real(4e5) * 16 * kEpsilon);
  // It oscillated: the box is not where free flight would have taken it (1.2 m).
  EXPECT_LT(std::abs(once.bodies.rigid.position[0].x() - 1), Real(0.02));
}

}  // namespace
}  // namespace pbd
