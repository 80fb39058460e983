// Stiff rods of rigid segments (Deul, Müller, Bender 2018): the per-joint constraint
// (joints/stretch_bending_twisting_joint.h) and the direct tree solver
// (joints/stiff_rod_tree_solver.h). Unit checks (finite differences, rest, rigid motion,
// momentum, the tree LDLᵀ against a dense solve) and world checks against closed forms: a
// cantilever under its weight (discrete rod and Euler–Bernoulli), a tip torque (T L / (G J)),
// the direct solver against converged Gauss–Seidel, a Y-shaped tree, steel at h = 1e-3.
// Measured numbers are printed for docs/methods.md.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <variant>
#include <vector>

#include "common/stiff_rod_scenes.h"
#include "common/tolerances.h"
#include "pbd/model/world.h"

namespace pbd {
namespace {

using test::RodMaterial;
using Vector6 = stiff_rod::Vector6;

constexpr Real kGravity = Real(9.81);

/// Moves every dynamic body by `size` times a fixed pseudo-random translation and rotation.
void perturb(BodyStates& b, Real size) {
  for (std::size_t i = 0; i < b.rigid.size(); ++i) {
    if (!b.rigid.isDynamic(i)) continue;
    const Real s = Real(i + 1);
    const Vector3 shift(std::sin(1.3 * s), std::cos(2.1 * s), std::sin(0.7 * s + 1));
    const Vector3 turn(std::cos(1.7 * s), std::sin(2.9 * s + 2), std::cos(0.3 * s));
    b.rigid.position[i] += size * Real(0.1) * shift;
    b.rigid.rotation[i] =
        (Quaternion(AngleAxis(size * turn.norm(), turn.normalized())) * b.rigid.rotation[i])
            .normalized();
  }
}

/// The per-joint constraints of every joint of `scene` on `bodies`.
std::vector<StretchBendingTwistingJoint> jointsOf(const Scene& scene, const BodyStates& bodies) {
  std::vector<StretchBendingTwistingJoint> joints;
  for (const JointDesc& desc : scene.joints)
    joints.emplace_back(bodies, desc);
  return joints;
}

Real maxPoseDifference(const RigidBodyStates& a, const RigidBodyStates& b) {
  Real d = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    d = std::max(d, (a.position[i] - b.position[i]).norm());
    d = std::max(d, a.rotation[i].angularDistance(b.rotation[i]));
  }
  return d;
}

Real maxPoseChange(const RigidBodyStates& after, const RigidBodyStates& before) {
  return maxPoseDifference(after, before);
}

// --- The constraint alone ------------------------------------------------------------------

// Two segments at an angle and twisted (rest Darboux vector ≠ 0), then moved off the rest pose:
// the analytic ∇C of all six rows against central differences of C.
TEST(StiffRodJoint, JacobianMatchesCentralDifferences) {
  RodMaterial m;
  Scene s;
  const Vector3 d0 = Vector3(1, 0.2, 0).normalized(), d1 = Vector3(0.6, 0.5, 0.4).normalized();
  s.rigidBodies.push_back(test::rodSegment(0, Vector3::Zero(), d0, Real(0.3), m, true));
  s.rigidBodies.back().rotation =
      (s.rigidBodies.back().rotation * Quaternion(AngleAxis(Real(0.4), Vector3::UnitY())))
          .normalized();
  s.rigidBodies.push_back(test::rodSegment(1, Real(0.3) * d0, d1, Real(0.3), m, true));
  s.joints.push_back(test::rodJoint(0, 0, 1, Real(0.3) * d0, Real(0.3), m));
  s.joints.back().stiffRod.tree = -1;  // no TreeModel: a per-joint constraint
  World world = buildWorld(s);
  perturb(world.bodies, Real(0.2));
  const StretchBendingTwistingJoint joint(buildWorld(s).bodies, s.joints[0]);
  const auto rows = joint.positionRows(world.bodies);
  EXPECT_GT(rows.value.tail<3>().norm(), Real(0.1));  // bent away from rest: a real test
  const Real eps = test::finiteDifferenceStep();
  for (int body = 0; body < 2; ++body)
    for (int angular = 0; angular < 2; ++angular)
      for (int axis = 0; axis < 3; ++axis) {
        BodyStates plus = world.bodies, minus = world.bodies;
        for (auto [states, sign] : {std::pair{&plus, Real(1)}, std::pair{&minus, Real(-1)}}) {
          auto& r = states->rigid;
          if (angular)
            r.rotation[std::size_t(body)] = Quaternion(AngleAxis(sign * eps, Vector3::Unit(axis))) *
                                            r.rotation[std::size_t(body)];
          else
            r.position[std::size_t(body)] += sign * eps * Vector3::Unit(axis);
        }
        const Vector6 column =
            (joint.positionRows(plus).value - joint.positionRows(minus).value) / (2 * eps);
        const auto& analytic =
            angular ? rows.angular[std::size_t(body)] : rows.linear[std::size_t(body)];
        // Central differences, step ε^(1/3): error ~ε^(2/3) times the O(1..10) entries (the
        // Darboux rows carry 2/L = 6.7).
        EXPECT_LE((column - analytic.col(axis)).cwiseAbs().maxCoeff(),
                  10 * test::finiteDifferenceTolerance())
            << "body " << body << " angular " << angular << " axis " << axis;
      }
}

// At the rest pose C = 0 and neither the joint nor the tree solver moves anything.
TEST(StiffRodJoint, NoCorrectionAtRest) {
  const Scene s = test::cantileverScene(3, 1, RodMaterial{}, StiffRodSolver::Iterative);
  World world = buildWorld(s);
  auto joints = jointsOf(s, world.bodies);
  const BodyStates before = world.bodies;
  for (auto& joint : joints) {
    // C is built from poses of O(1) m and 2/L = 6: a few ulps of those.
    EXPECT_LE(joint.positionRows(world.bodies).value.cwiseAbs().maxCoeff(), 64 * kEpsilon);
    joint.beginSubstep(Real(1e-3));
    joint.solvePosition(world.bodies, Real(1e-3));
  }
  // A correction of a round-off C: round-off.
  EXPECT_LE(maxPoseChange(world.bodies.rigid, before.rigid), 64 * kEpsilon);
  StiffRodTreeSolver tree(before, s.joints, "tree");
  BodyStates direct = before;
  tree.beginSubstep(Real(1e-3));
  tree.solvePosition(direct);
  EXPECT_LE(maxPoseChange(direct.rigid, before.rigid), 64 * kEpsilon);
}

// Moving the whole rod rigidly changes no Darboux row and only rotates the point rows.
TEST(StiffRodJoint, InvariantUnderRigidMotion) {
  const Scene s = test::cantileverScene(3, 1, RodMaterial{}, StiffRodSolver::Iterative);
  World world = buildWorld(s);
  const auto joints = jointsOf(s, world.bodies);
  perturb(world.bodies, Real(0.1));
  BodyStates moved = world.bodies;
  const Quaternion turn(AngleAxis(Real(1.1), Vector3(1, -2, 0.5).normalized()));
  const Vector3 shift(0.3, -1.2, 2.5);
  for (std::size_t i = 0; i < moved.rigid.size(); ++i) {
    moved.rigid.position[i] = turn * moved.rigid.position[i] + shift;
    moved.rigid.rotation[i] = (turn * moved.rigid.rotation[i]).normalized();
  }
  for (const auto& joint : joints) {
    const Vector6 a = joint.positionRows(world.bodies).value;
    const Vector6 b = joint.positionRows(moved).value;
    EXPECT_GT(a.tail<3>().norm(), Real(0.01));  // a bent state: the check is not vacuous
    // Rounding of a rotation of O(1) poses: 100 ulps.
    EXPECT_LE((b.tail<3>() - a.tail<3>()).norm(), 100 * kEpsilon * (1 + a.norm()));
    EXPECT_LE((b.head<3>() - turn * a.head<3>()).norm(), 100 * kEpsilon * 4);
  }
}

// Corrections are internal: Σ m Δx = 0 always; with the joint points coincident (bodies turned
// about their joint), also the angular momentum change Σ (I Δθ + x × m Δx) = 0.
TEST(StiffRodJoint, CorrectionsConserveMomentum) {
  RodMaterial m;
  Scene s = test::cantileverScene(3, 1, m, StiffRodSolver::Direct);
  s.rigidBodies[0].isDynamic = true;  // all dynamic: nothing external
  for (int solver = 0; solver < 2; ++solver) {
    World world = buildWorld(s);
    auto& r = world.bodies.rigid;
    // Turn each segment about its own joint point with body 0: joint points stay coincident
    // for the first joint; translate nothing.
    const Quaternion bend(AngleAxis(Real(0.05), Vector3(0.2, 0.3, 1).normalized()));
    const Vector3 pivot = s.joints[0].position;
    for (std::size_t i = 1; i < r.size(); ++i) {
      r.position[i] = pivot + bend * (r.position[i] - pivot);
      r.rotation[i] = (bend * r.rotation[i]).normalized();
    }
    const RigidBodyStates before = r;
    if (solver == 0) {
      auto joints = jointsOf(s, buildWorld(s).bodies);
      joints[0].beginSubstep(Real(1e-3));
      joints[0].solvePosition(world.bodies, Real(1e-3));
    } else {
      StiffRodTreeSolver tree(buildWorld(s).bodies, s.joints, "tree");
      tree.beginSubstep(Real(1e-3));
      tree.solvePosition(world.bodies);
    }
    Vector3 linear = Vector3::Zero(), angular = Vector3::Zero();
    Real scale = 0;
    for (std::size_t i = 0; i < r.size(); ++i) {
      const Vector3 dx = r.position[i] - before.position[i];
      const Quaternion dq = r.rotation[i] * before.rotation[i].conjugate();
      const Vector3 dtheta = 2 * dq.vec() * (dq.w() < 0 ? -1 : 1);
      const Matrix3 rot = before.rotation[i].toRotationMatrix();
      const Matrix3 inertia = rot * r.inertia[i].asDiagonal() * rot.transpose();
      linear += r.mass[i] * dx;
      angular += inertia * dtheta + before.position[i].cross(r.mass[i] * dx);
      scale = std::max(scale, r.mass[i] * dx.norm());
    }
    EXPECT_GT(scale, 0) << solver;
    // Linear: exact in the solve (A₀ = −A₁), to round-off of the corrections.
    EXPECT_LE(linear.norm(), 1e3 * kEpsilon * scale) << solver;
    // Angular: exact for the linearised correction; the quaternion update's normalisation
    // shortens Δθ by O(|Δθ|²) ≈ (0.05)² relative: 1 % of the correction's size.
    EXPECT_LE(angular.norm(), Real(0.01) * scale) << solver;
  }
}

// --- The tree solver ------------------------------------------------------------------------

/// Dense matrices in the library's precision (Real: double, or float in the float build).
using DenseMatrix = Eigen::Matrix<Real, Eigen::Dynamic, Eigen::Dynamic>;
using DenseVector = Eigen::Matrix<Real, Eigen::Dynamic, 1>;

/// Positions after one dense solve of (J M⁻¹ Jᵀ + α̃) Δλ = −C (λ = 0), independently assembled.
BodyStates denseOneIteration(const Scene& s, const BodyStates& start, Real h) {
  const World fresh = buildWorld(s);  // rest data captured at the scene's initial poses
  auto rest = jointsOf(s, fresh.bodies);
  const RigidBodyStates& r = start.rigid;
  const int nb = int(r.size()), nj = int(rest.size());
  DenseMatrix jacobian = DenseMatrix::Zero(6 * nj, 6 * nb);
  DenseMatrix inverseMass = DenseMatrix::Zero(6 * nb, 6 * nb);
  DenseVector rhs(6 * nj), alpha(6 * nj);
  for (int j = 0; j < nj; ++j) {
    rest[std::size_t(j)].beginSubstep(h);
    const auto rows = rest[std::size_t(j)].positionRows(start);
    const JointEnds ends = rest[std::size_t(j)].ends();
    const int body[2] = {ends.body0, ends.body1};
    for (int e = 0; e < 2; ++e) {
      jacobian.block(6 * j, 6 * body[e], 6, 3) = rows.linear[std::size_t(e)];
      jacobian.block(6 * j, 6 * body[e] + 3, 6, 3) = rows.angular[std::size_t(e)];
    }
    rhs.segment<6>(6 * j) = -rows.value;
    alpha.segment<6>(6 * j) = rest[std::size_t(j)].compliance();
  }
  for (int b = 0; b < nb; ++b) {
    const EndInverseMass w = joint_parts::rigidEnd(r, b);
    inverseMass.block(6 * b, 6 * b, 3, 3) = w.linear * Matrix3::Identity();
    inverseMass.block(6 * b + 3, 6 * b + 3, 3, 3) = w.angular;
  }
  const DenseMatrix system =
      jacobian * inverseMass * jacobian.transpose() + DenseMatrix(alpha.asDiagonal());
  const DenseVector lambda = system.ldlt().solve(rhs);
  const DenseVector dq = inverseMass * jacobian.transpose() * lambda;
  BodyStates out = start;
  for (int b = 0; b < nb; ++b)
    joint_parts::applyPositionCorrection(out.rigid, b, dq.segment<3>(6 * b),
                                         dq.segment<3>(6 * b + 3));
  return out;
}

// One iteration of the tree LDLᵀ is the exact solve of the linearised system: the same poses as
// a dense factorisation of J M⁻¹ Jᵀ + α̃, for a chain and for a Y-shaped tree.
TEST(StiffRodTreeSolver, OneIterationEqualsDenseSolve) {
  // Double-only: the bound is the system's conditioning times ε, κ ≈ 1e6 (below); with float's
  // ε = 1.2e-7 that is 0.12 of the correction itself, so no precision-aware bound says
  // anything about the two factorisations agreeing.
  if (sizeof(Real) < 8)
    GTEST_SKIP() << "needs double precision: kappa ~ 1e6 times float eps 1.2e-7 is 12 % of the "
                    "correction, so the conditioning bound is meaningless";
  RodMaterial m;
  const Real h = Real(1e-3);
  for (const Scene& s : {test::cantileverScene(6, 1, m, StiffRodSolver::Direct),
                         test::yTreeScene(3, Real(0.1), m, StiffRodSolver::Direct)}) {
    World world = buildWorld(s);
    StiffRodTreeSolver tree(world.bodies, s.joints, "tree");
    perturb(world.bodies, Real(1e-3));
    const BodyStates start = world.bodies;
    const BodyStates dense = denseOneIteration(s, start, h);
    tree.beginSubstep(h);
    tree.solvePosition(world.bodies);
    const Real change = maxPoseChange(world.bodies.rigid, start.rigid);
    EXPECT_GT(change, Real(1e-5));
    // Two factorisations of the same system: agreement to its conditioning (κ ≈ 1e6 here:
    // stretch compliance 1e-4 against 1/m ≈ 30) times ε, relative to the correction.
    const Real difference = maxPoseDifference(world.bodies.rigid, dense.rigid);
    EXPECT_LE(difference, Real(1e-8) * change) << s.rigidBodies.size() << " bodies";
    std::printf("  tree vs dense, %zu segments: correction %.3e, difference %.3e\n",
                s.rigidBodies.size(), double(change), double(difference));
  }
}

// The direct solver's one iteration against Gauss–Seidel iterations of the per-joint
// constraints converged (2000 sweeps): both solve the same XPBD system; they differ only by the
// linearisation (GS re-linearises at every projection), which is second order in the
// correction. Shrinking the perturbation 10× must shrink the difference ~100×.
TEST(StiffRodTreeSolver, OneIterationMatchesConvergedGaussSeidel) {
  RodMaterial m;
  const Scene s = test::cantileverScene(5, 1, m, StiffRodSolver::Direct);
  const Real h = Real(1e-3);
  Real difference[2], correction[2];
  const Real sizes[2] = {Real(1e-2), Real(1e-3)};
  for (int k = 0; k < 2; ++k) {
    World world = buildWorld(s);
    auto joints = jointsOf(s, world.bodies);
    StiffRodTreeSolver tree(world.bodies, s.joints, "tree");
    perturb(world.bodies, sizes[k]);
    const BodyStates start = world.bodies;
    BodyStates iterative = start;
    for (auto& joint : joints)
      joint.beginSubstep(h);
    for (int sweep = 0; sweep < 2000; ++sweep)
      for (auto& joint : joints)
        joint.solvePosition(iterative, h);
    tree.beginSubstep(h);
    tree.solvePosition(world.bodies);
    difference[k] = maxPoseDifference(world.bodies.rigid, iterative.rigid);
    correction[k] = maxPoseChange(iterative.rigid, start.rigid);
    std::printf("  perturbation %.0e: correction %.3e, direct(1) vs GS(2000) %.3e\n",
                double(sizes[k]), double(correction[k]), double(difference[k]));
  }
  const Real order = std::log(difference[0] / difference[1]) / std::log(sizes[0] / sizes[1]);
  EXPECT_GT(order, Real(1.8));  // second order (2); a wrong solve would be order ≤ 1
  // Second order: about correction × rotation angle; the perturbation turns segments by up to
  // 2 × size rad. Bound: twice that product.
  EXPECT_LE(difference[1], 2 * correction[1] * (2 * sizes[1]));
}

// The node order is built once; a closed loop is refused.
TEST(StiffRodTreeSolver, RefusesClosedLoops) {
  RodMaterial m;
  Scene s = test::cantileverScene(3, 1, m, StiffRodSolver::Direct);
  s.joints.push_back(test::rodJoint(9, 1, 3, Vector3(1, 0, 0), Real(1) / 3, m));
  World world = buildWorld(test::cantileverScene(3, 1, m, StiffRodSolver::Direct));
  EXPECT_THROW(StiffRodTreeSolver(world.bodies, s.joints, "TreeModels[0]"), std::invalid_argument);
}

// --- World: static deflection ---------------------------------------------------------------

/// Relaxes `s` to its static equilibrium: after every step the velocities are zeroed, so the
/// step's fixed point is the equilibrium of gravity (and torques) with the joints (the XPBD
/// system with λ = −C/α̃ is then exactly force balance). Returns the world.
World relax(const Scene& s, int steps, const Vector3& tipTorque = Vector3::Zero()) {
  World world = buildWorld(s);
  auto& r = world.bodies.rigid;
  r.torque.back() = tipTorque;
  for (int n = 0; n < steps; ++n) {
    world.step();
    for (std::size_t i = 0; i < r.size(); ++i) {
      r.velocity[i].setZero();
      r.angularVelocity[i].setZero();
    }
  }
  return world;
}

// A cantilever of N rigid segments clamped at x = 0 under its weight q = ρ A g. Joint k
// (at x_k = (k−1)ℓ) is a rotational spring E I / ℓ carrying the moment of the n = N−k+1
// segments beyond it, M = m g ℓ n²/2; the tip deflection is therefore exactly
//   δ_N = (m g ℓ³ / (2 E I)) (N (N+1)/2)²
// (small angles), which tends to Euler–Bernoulli's q L⁴ / (8 E I) as (1 + 1/N)².
TEST(StiffRodWorld, CantileverUnderWeightMatchesDiscreteAndEulerBernoulli) {
  RodMaterial m;  // E = 10 GPa, r = 1 cm, ρ = 1000: δ/L ≈ 0.5 %
  const Real length = 1;
  const Real ei = m.youngsModulus * test::secondMomentOfArea(m.radius);
  const Real q = m.density * Real(EIGEN_PI) * m.radius * m.radius * kGravity;
  const Real eulerBernoulli = q * length * length * length * length / (8 * ei);
  Real previousError = 1;
  for (int n : {4, 8, 16, 32}) {
    const Scene s = test::cantileverScene(n, length, m, StiffRodSolver::Direct);
    World world = relax(s, 200);
    const Real l = length / Real(n);
    const Real deflection = -test::segmentTip(world, n, l).y();
    const Real mass = world.bodies.rigid.mass[1];
    const Real half = Real(n) * Real(n + 1) / 2;
    const Real discrete = mass * kGravity * l * l * l / (2 * ei) * half * half;
    // Small-angle terms: joint angles ≤ q L³/(6 E I) ≈ 7e-3 rad, relative (7e-3)² ≈ 5e-5;
    // 1e-3 leaves room and still catches a wrong stiffness (the N dependence is 2/N).
    EXPECT_NEAR(deflection / discrete, 1, 1e-3) << n;
    const Real error = deflection / eulerBernoulli - 1;
    // The discretisation error is (1 + 1/N)² − 1 = 2/N + 1/N².
    EXPECT_NEAR(error, 2 / Real(n) + 1 / Real(n * n), 2e-3) << n;
    EXPECT_LT(error, previousError) << n;
    previousError = error;
    std::printf("  N = %2d: tip %.6e m, discrete %.6e, Euler-Bernoulli %.6e, error %.4f\n", n,
                double(deflection), double(discrete), double(eulerBernoulli), double(error));
  }
}

// The iterative solver (Gauss–Seidel over the per-joint constraints, k iterations per step)
// relaxes to a softer state than the equilibrium unless the sweeps converge: its λ starts at 0
// every substep and k sweeps recover only part of the force (Deul et al. 2018's motivation for
// the direct solver). The excess deflection must fall as k grows and vanish when converged.
TEST(StiffRodWorld, IterativeSolverApproachesTheEquilibriumAsIterationsGrow) {
  RodMaterial m;
  const int n = 4;
  const Real l = Real(0.25);
  const World direct = relax(test::cantileverScene(n, 1, m, StiffRodSolver::Direct), 200);
  const Real reference = -test::segmentTip(direct, n, l).y();
  Real previous = 1e30, excessAt100 = 0;
  for (int iterations : {10, 100, 1000}) {
    const World iterative = relax(
        test::cantileverScene(n, 1, m, StiffRodSolver::Iterative, Real(0.05), iterations), 200);
    ASSERT_EQ(iterative.stiffRodTrees.size(), 0u);
    ASSERT_EQ(iterative.joints.size(), std::size_t(n));
    const Real excess = -test::segmentTip(iterative, n, l).y() / reference - 1;
    std::printf("  %4d iterations: tip deflection / direct - 1 = %.3e\n", iterations,
                double(excess));
    EXPECT_GT(excess, -1e-4) << iterations;  // never stiffer than the equilibrium (round-off)
    EXPECT_LT(excess, previous) << iterations;
    if (iterations == 100) excessAt100 = excess;
    previous = excess;
  }
  // Gauss–Seidel converges linearly, error ∝ ρᵏ: from 100 to 1000 sweeps the excess must shrink
  // by far more than the 10× a merely sublinear trend would give (measured: 9.1 → 0.042).
  EXPECT_LT(previous, excessAt100 / 10);
}

// A tip torque T about the rod axis: every joint twists by φ with (K_y/ℓ) sin φ = T,
// K_y = 2 G I = G J, so the tip turns by N asin(T ℓ / (G J)) ≈ T L / (G J).
TEST(StiffRodWorld, TipTorqueTwistsByTLOverGJ) {
  RodMaterial m;
  const int n = 8;
  const Real length = 1, l = length / n;
  Scene s = test::cantileverScene(n, length, m, StiffRodSolver::Direct, Real(1e-4));
  s.simulation.gravitation.setZero();
  const Real gj = m.torsionModulus * 2 * test::secondMomentOfArea(m.radius);
  const Real torque = Real(1e-4) * gj / length;  // a twist of 1e-4 rad
  const World world = relax(s, 400, torque * Vector3::UnitX());
  const Quaternion clamp = world.sceneFrameState(0).rotation;
  const Quaternion tip = world.sceneFrameState(std::size_t(n)).rotation;
  const Quaternion relative = clamp.conjugate() * tip;  // local y = rod axis
  const Real twist = 2 * std::atan2(relative.y(), relative.w());
  const Real expected = Real(n) * std::asin(torque * l / gj);
  std::printf("  twist %.6e rad, N asin(T l/GJ) %.6e, T L/(G J) %.6e\n", double(twist),
              double(expected), double(torque * length / gj));
  // The relaxation's fixed point is exact up to the second-order change of the Jacobian over a
  // step's predicted rotation (h² T / I ≈ 3e-5 rad): 1e-4 relative.
  EXPECT_NEAR(twist / expected, 1, 1e-4);
  // No bending: the tip stays on the axis (round-off of O(1) positions, 1e-12). Precision-aware:
  // 1e-12 = 4500 ε of 1 m in double, the same multiple of ε in float.
  EXPECT_LE(std::abs(test::segmentTip(world, n, l).y()), test::roundOffBound(1e-12));
}

// --- World: trees and stability -------------------------------------------------------------

// The Y-shaped tree under gravity with the direct solver: the zero-stretch constraint holds,
// the arms sag symmetrically, and the motion stays bounded.
TEST(StiffRodWorld, YTreeWithDirectSolverHoldsAndStaysSymmetric) {
  RodMaterial m;
  const Scene s = test::yTreeScene(3, Real(0.1), m, StiffRodSolver::Direct);
  World world = buildWorld(s);
  ASSERT_EQ(world.stiffRodTrees.size(), 1u);
  ASSERT_EQ(world.joints.size(), 0u);
  Real worstPoint = 0;
  for (int step = 0; step < 1000; ++step) {
    world.step();
    for (const auto& joint : world.stiffRodTrees[0].joints())
      worstPoint = std::max(worstPoint, joint.error(world.bodies).linear);
  }
  const auto& r = world.bodies.rigid;
  const std::size_t tipA = 5, tipB = 8;  // the last segment of each arm
  ASSERT_TRUE(r.position[tipA].allFinite());
  // Mirror symmetry z → −z of the scene: the arms' tips differ only in the sign of z (to
  // round-off accumulated over 1000 steps of O(1) numbers: 1e-9 m).
  EXPECT_NEAR(r.position[tipA].y(), r.position[tipB].y(), 1e-9);
  EXPECT_NEAR(r.position[tipA].z(), -r.position[tipB].z(), 1e-9);
  EXPECT_LT(r.position[tipA].y(), 0);  // it sags
  // The point constraint has compliance 1e-10 m/N: the joint forces (≈ 1 N) open it by
  // ~1e-10 m; 1e-8 m bounds that and the linearisation error of one iteration per step.
  // Precision-aware: a gap is the difference of two joint points, each a position plus a
  // rotated offset on coordinates ≤ 1 m (~8 roundings each): at least 16 ε · 1 m (3.5e-15 m
  // in double, where 1e-8 m is kept; 1.9e-6 m in float, whose ulp at 0.3 m is 3e-8 m).
  EXPECT_LE(worstPoint, std::max(Real(1e-8), 16 * kEpsilon * 1));
  std::printf("  Y tree: tip y %.4e m, worst joint gap %.3e m\n", double(r.position[tipA].y()),
              double(worstPoint));
}

/// Kinetic + gravitational + elastic (bending and twisting) energy.
Real totalEnergy(const World& world) {
  const auto& r = world.bodies.rigid;
  Real e = 0;
  for (std::size_t i = 0; i < r.size(); ++i) {
    if (!r.isDynamic(i)) continue;
    const Matrix3 rot = r.rotation[i].toRotationMatrix();
    const Matrix3 inertia = rot * r.inertia[i].asDiagonal() * rot.transpose();
    e += Real(0.5) * r.mass[i] * r.velocity[i].squaredNorm() +
         Real(0.5) * r.angularVelocity[i].dot(inertia * r.angularVelocity[i]) -
         r.mass[i] * world.settings.gravitation.dot(r.position[i]);
  }
  for (const auto& tree : world.stiffRodTrees)
    for (const auto& joint : tree.joints())
      e += joint.elasticEnergy(world.bodies);
  for (const Joint& joint : world.joints)
    if (const auto* rod = std::get_if<StretchBendingTwistingJoint>(&joint))
      e += rod->elasticEnergy(world.bodies);
  return e;
}

// Steel (E = 209 GPa, G = 79 GPa, ρ = 7800) at h = 1e-3 and 3 iterations (the seed's Wilberforce
// settings), released straight under gravity: no blow-up. With the direct solver the energy
// never exceeds its start and the tip stays within twice the static deflection (a suddenly
// applied load on an undamped linear structure overshoots to at most 2×); the iterative solver
// is far softer at 3 iterations (see IterativeSolverApproachesTheEquilibrium…) and is only
// required to stay bounded (|tip| < the rod's length).
TEST(StiffRodWorld, SteelRodIsStableAtMillisecondSteps) {
  RodMaterial steel{Real(209e9), Real(79e9), Real(7800), Real(0.01)};
  const int n = 10;
  const Real length = 1, l = length / n;
  for (StiffRodSolver solver : {StiffRodSolver::Direct, StiffRodSolver::Iterative}) {
    const Scene s = test::cantileverScene(n, length, steel, solver, Real(1e-3), 3);
    World world = buildWorld(s);
    const bool direct = solver == StiffRodSolver::Direct;
    const Real ei = steel.youngsModulus * test::secondMomentOfArea(steel.radius);
    const Real q = steel.density * Real(EIGEN_PI) * steel.radius * steel.radius * kGravity;
    const Real half = Real(n) * Real(n + 1) / 2;
    const Real staticTip = q * l * l * l * l / (2 * ei) * half * half;  // the discrete rod
    const Real startEnergy = totalEnergy(world);
    Real maxTip = 0, maxEnergyGain = 0;
    for (int step = 0; step < 2000; ++step) {
      world.step();
      maxTip = std::max(maxTip, std::abs(test::segmentTip(world, n, l).y()));
      maxEnergyGain = std::max(maxEnergyGain, totalEnergy(world) - startEnergy);
    }
    ASSERT_TRUE(world.bodies.rigid.position.back().allFinite());
    if (direct) {
      EXPECT_LE(maxTip, 2 * staticTip);
      EXPECT_GT(maxTip, Real(0.5) * staticTip);  // it did load the rod
    } else {
      EXPECT_LT(maxTip, length);
    }
    // PBD's implicit update only dissipates; 1e-6 J is round-off on energies of O(10) J (the
    // potential m g y of 10 segments of 0.25 kg at |y| ≤ 1 m). Only with the direct solver: 3
    // unconverged sweeps realise a far softer rod than the nominal K, so the nominal bending
    // energy of its deeper sag is no energy of the scheme (measured: +36 J).
    if (direct) {
      EXPECT_LE(maxEnergyGain, Real(1e-6));
    }
    std::printf("  steel %s: max tip %.3e m (static %.3e), max energy gain %.3e J\n",
                direct ? "direct" : "iterative", double(maxTip), double(staticTip),
                double(maxEnergyGain));
  }
}

// The XPBD step (pbd.xpbd) solves the tree with the same compliances: the cantilever relaxes to
// the same discrete static deflection.
TEST(StiffRodWorld, XpbdStepReachesTheDiscreteDeflection) {
  RodMaterial m;
  const int n = 8;
  {
    const StiffRodSolver solver = StiffRodSolver::Direct;  // GS at one sweep per substep: see above
    Scene s = test::cantileverScene(n, 1, m, solver);
    s.simulation.stepMethod = StepMethod::Xpbd;
    s.simulation.xpbd.substeps = 1;
    World world = relax(s, 200);
    const Real l = Real(1) / n;
    const Real ei = m.youngsModulus * test::secondMomentOfArea(m.radius);
    const Real half = Real(n) * Real(n + 1) / 2;
    const Real discrete =
        world.bodies.rigid.mass[1] * kGravity * l * l * l / (2 * ei) * half * half;
    const Real deflection = -test::segmentTip(world, n, l).y();
    // As CantileverUnderWeight: small-angle terms ≤ 5e-5.
    EXPECT_NEAR(deflection / discrete, 1, 1e-3);
  }
}

}  // namespace
}  // namespace pbd
