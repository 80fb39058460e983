// Every joint's analytic constraint Jacobian against central finite differences of its own
// C(x, q), the block K matrix against a dense J M⁻¹ Jᵀ, and the Newton property of one
// projection (quadratic convergence), for all 13 joint types.
#include <gtest/gtest.h>

#include <cmath>

#include "common/scene_fixtures.h"
#include "common/tolerances.h"
#include "pbd/model/world.h"

namespace pbd {
namespace {

// Two dynamic bodies in generic poses, a particle, and one joint of `type` between them.
Scene twoBodyScene(JointType type) {
  Scene s;
  s.rigidBodies.push_back(test::boxBody(0, Vector3(0.3, 0.5, 0.7), Vector3(0, 0, 0), 2, true,
                                        Quaternion(AngleAxis(0.3, Vector3(1, 2, 0).normalized()))));
  s.rigidBodies.push_back(
      test::boxBody(1, Vector3(0.6, 0.2, 0.4), Vector3(0.5, -0.7, 0.2), 3, true,
                    Quaternion(AngleAxis(-0.8, Vector3(0, 1, 3).normalized()))));
  ParticleDesc particle;
  particle.position = Vector3(0.3, -0.4, 0.25);
  particle.mass = Real(0.7);
  s.particles.push_back(particle);

  JointDesc j = test::makeJointDesc(type, 0, 1);
  j.position = Vector3(0.2, -0.3, 0.1);
  j.axis = Vector3(1, 2, 3).normalized();
  j.axis1 = Vector3(1, 2, 3).normalized();
  j.axis2 = j.axis1.cross(Vector3(0, 0, 1)).normalized();
  j.position1 = Vector3(0.1, 0.1, 0.0);
  j.position2 = Vector3(0.6, -0.5, 0.3);
  j.stiffness = 1000;
  // The seed's damper and slider-motor rows leave out the rotations' effect on their linear rows
  // on purpose (they are not the derivative of C; DamperJointModel and VelocityMotorSliderModel
  // in test_seed_fidelity.cpp and the recordings in test_seed_reference.cpp check them): their
  // Jacobians are those of the corrected model.
  if (type == JointType::Damper || type == JointType::TargetPositionMotorSlider ||
      type == JointType::TargetVelocityMotorSlider)
    s.simulation.jointModel = JointModel::Corrected;
  j.target.constant = Real(0.3);
  if (type == JointType::RigidBodyParticleBall) {
    j.body2 = -1;
    j.particle = 0;
  }
  s.joints.push_back(j);
  return s;
}

// Moves both bodies (and the particle) off the constraint by an amount scaled by `size`.
void perturb(BodyStates& b, Real size) {
  const Vector3 shifts[2] = {Vector3(0.3, -0.2, 0.5), Vector3(-0.4, 0.1, 0.2)};
  const Vector3 turns[2] = {Vector3(0.2, 0.5, -0.3), Vector3(-0.6, 0.2, 0.4)};
  for (std::size_t i = 0; i < 2; ++i) {
    b.rigid.position[i] += size * shifts[i];
    b.rigid.rotation[i] =
        (Quaternion(AngleAxis(size * turns[i].norm(), turns[i].normalized())) * b.rigid.rotation[i])
            .normalized();
  }
  b.particles.position[0] += size * Vector3(0.1, 0.3, -0.2);
}

// Rotates body `body` by the world angle vector θ exactly (exp map), or moves end `body`.
void displace(BodyStates& b, int end, const JointEnds& ends, bool angular, int axis, Real eps) {
  const Vector3 delta = eps * Vector3::Unit(axis);
  const int body = end == 0 ? ends.body0 : ends.body1;
  if (body < 0) {  // particle end
    if (!angular) b.particles.position[static_cast<std::size_t>(ends.particle)] += delta;
    return;
  }
  const auto i = static_cast<std::size_t>(body);
  if (angular)
    b.rigid.rotation[i] = (Quaternion(AngleAxis(eps, Vector3::Unit(axis))) * b.rigid.rotation[i]);
  else
    b.rigid.position[i] += delta;
}

class JointJacobian : public ::testing::TestWithParam<int> {};

TEST_P(JointJacobian, MatchesCentralDifferences) {
  const auto type = static_cast<JointType>(GetParam());
  World world = buildWorld(twoBodyScene(type));
  perturb(world.bodies, Real(0.05));
  const Joint& joint = world.joints[0];
  const JointEnds ends = jointEnds(joint);

  std::visit(
      [&](const auto& j) {
        const auto rows = j.positionRows(world.bodies);
        const Real eps = test::finiteDifferenceStep();
        Real largest = 0;
        for (int end = 0; end < 2; ++end) {
          for (int angular = 0; angular < 2; ++angular) {
            const auto& analytic = angular ? rows.angular[static_cast<std::size_t>(end)]
                                           : rows.linear[static_cast<std::size_t>(end)];
            for (int axis = 0; axis < 3; ++axis) {
              BodyStates plus = world.bodies, minus = world.bodies;
              displace(plus, end, ends, angular, axis, eps);
              displace(minus, end, ends, angular, axis, -eps);
              const auto column =
                  ((j.positionRows(plus).value - j.positionRows(minus).value) / (2 * eps)).eval();
              largest = std::max(largest, analytic.col(axis).cwiseAbs().maxCoeff());
              // Central differences with step ε_mach^(1/3) are accurate to ~ε_mach^(2/3)
              // (3.7e-11 in double) on O(1) Jacobians; a wrong term (an O(1) error in an
              // entry) fails by many orders.
              EXPECT_LE((column - analytic.col(axis)).cwiseAbs().maxCoeff(),
                        test::finiteDifferenceTolerance())
                  << jointTypeName(type) << " end " << end << (angular ? " angular" : " linear")
                  << " axis " << axis << "\nFD:\n"
                  << column.transpose() << "\nanalytic:\n"
                  << analytic.col(axis).transpose();
            }
          }
        }
        // The comparison is not vacuous: the Jacobian has O(1) entries.
        EXPECT_GT(largest, 0.1) << jointTypeName(type);
      },
      joint);
}

TEST_P(JointJacobian, EffectiveMassMatchesDenseAssembly) {
  const auto type = static_cast<JointType>(GetParam());
  World world = buildWorld(twoBodyScene(type));
  perturb(world.bodies, Real(0.05));
  const JointEnds ends = jointEnds(world.joints[0]);
  std::visit(
      [&](const auto& j) {
        const auto rows = j.positionRows(world.bodies);
        constexpr int m = std::decay_t<decltype(rows)>::Vector::RowsAtCompileTime;
        // J = [A₀ B₀ A₁ B₁] (m×12), M⁻¹ = blockdiag(w₀𝟙, J₀, w₁𝟙, J₁).
        Eigen::Matrix<Real, m, 12> jacobian;
        jacobian << rows.linear[0], rows.angular[0], rows.linear[1], rows.angular[1];
        Eigen::Matrix<Real, 12, 12> inverseMass = Eigen::Matrix<Real, 12, 12>::Zero();
        std::array<EndInverseMass, 2> endMass;
        endMass[0] = joint_parts::rigidEnd(world.bodies.rigid, ends.body0);
        endMass[1] = ends.body1 >= 0
                         ? joint_parts::rigidEnd(world.bodies.rigid, ends.body1)
                         : EndInverseMass{world.bodies.particles.inverseMass[0], Matrix3::Zero()};
        for (int e = 0; e < 2; ++e) {
          inverseMass.block<3, 3>(6 * e, 6 * e) =
              endMass[static_cast<std::size_t>(e)].linear * Matrix3::Identity();
          inverseMass.block<3, 3>(6 * e + 3, 6 * e + 3) =
              endMass[static_cast<std::size_t>(e)].angular;
        }
        const Eigen::Matrix<Real, m, m> dense = jacobian * inverseMass * jacobian.transpose();
        const Eigen::Matrix<Real, m, 1> zero = Eigen::Matrix<Real, m, 1>::Zero();
        const auto blocks = effectiveMassMatrix(rows, endMass, zero);
        // Same sums in a different order: agreement to a few hundred ulps of the entries.
        EXPECT_LE((blocks - dense).cwiseAbs().maxCoeff(),
                  256 * kEpsilon * dense.cwiseAbs().maxCoeff())
            << jointTypeName(type);
      },
      world.joints[0]);
}

// One projection is a Newton step on C: the residual after it is O(|C₀|²). Halving the
// violation (scale η → η/2 ... 1e-2 → 1e-3) must shrink the residual ~η², i.e. the observed
// order log(r₁/r₂)/log(η₁/η₂) ≈ 2; a wrong Jacobian gives order ≤ 1. Compliant joints
// (spring, damper, the stiff rod's bending rows) take partial XPBD steps by design and are
// excluded.
TEST_P(JointJacobian, OneProjectionConvergesQuadratically) {
  const auto type = static_cast<JointType>(GetParam());
  if (type == JointType::RigidBodySpring || type == JointType::Damper ||
      type == JointType::StiffRod)
    GTEST_SKIP();
  Real residual[2];
  // Violations well above round-off in either precision.
  const Real sizes[2] = {sizeof(Real) == 8 ? Real(1e-2) : Real(1e-1),
                         sizeof(Real) == 8 ? Real(1e-3) : Real(2e-2)};
  for (int k = 0; k < 2; ++k) {
    World world = buildWorld(twoBodyScene(type));
    // Position motors start 0.3 (rad or m) away from their target: put body 1 on the target
    // first, so that the violation is the perturbation's.
    const Vector3 axis = Vector3(1, 2, 3).normalized(), pivot(0.2, -0.3, 0.1);
    auto& b = world.bodies.rigid;
    if (type == JointType::TargetAngleMotorHinge) {
      const Quaternion turn(AngleAxis(Real(0.3), axis));
      b.position[1] = pivot + turn * (b.position[1] - pivot);
      b.rotation[1] = turn * b.rotation[1];
    } else if (type == JointType::TargetPositionMotorSlider) {
      b.position[1] += Real(0.3) * axis;
    }
    perturb(world.bodies, sizes[k]);
    std::visit(
        [&](auto& j) {
          j.beginSubstep(Real(1e-3));
          j.solvePosition(world.bodies, Real(1e-3));
          residual[k] = j.positionRows(world.bodies).value.norm();
        },
        world.joints[0]);
  }
  const Real order = std::log(residual[0] / residual[1]) / std::log(sizes[0] / sizes[1]);
  EXPECT_GT(order, 1.8) << jointTypeName(type) << " residuals " << residual[0] << " "
                        << residual[1];
}

INSTANTIATE_TEST_SUITE_P(AllJointTypes, JointJacobian, ::testing::Range(0, kJointTypeCount),
                         [](const ::testing::TestParamInfo<int>& param) {
                           return std::string(jointTypeName(static_cast<JointType>(param.param)));
                         });

// The velocity pass of the velocity motors solves a linear system in v exactly: after one
// solve the motor's velocity rows meet their targets to round-off (a 6×6 solve on O(1)
// values: 1000 ε). The slider in the corrected model (twoBodyScene); the seed's angular rows
// do not close in one solve (VelocityMotorSliderModel in test_seed_fidelity.cpp).
TEST(VelocityMotors, OneVelocitySolveMeetsTheTargetRate) {
  for (JointType type :
       {JointType::TargetVelocityMotorHinge, JointType::TargetVelocityMotorSlider}) {
    Scene scene = twoBodyScene(type);
    scene.rigidBodies[0].angularVelocity = Vector3(0.3, -1, 2);
    scene.rigidBodies[1].velocity = Vector3(1, 2, -0.5);
    World world = buildWorld(scene);
    std::visit([&](auto& j) { j.solveVelocity(world.bodies); }, world.joints[0]);
    const auto& b = world.bodies.rigid;
    const Vector3 axis0 =
        b.rotation[0] * (b.rotation[0].conjugate() * Vector3(1, 2, 3).normalized());
    const Vector3 relativeOmega = b.angularVelocity[1] - b.angularVelocity[0];
    if (type == JointType::TargetVelocityMotorHinge) {
      // ω₁ − ω₀ = ω* a  (the bodies have not rotated yet, so a is the scene axis)
      EXPECT_LE((relativeOmega - Real(0.3) * axis0).norm(), 1000 * kEpsilon);
    } else {
      EXPECT_LE(relativeOmega.norm(), 1000 * kEpsilon);
      // Body 1's centre moves relative to body 0's material point there at v* along a.
      const Vector3 anchorVelocity =
          b.velocity[0] + b.angularVelocity[0].cross(b.position[1] - b.position[0]);
      EXPECT_LE(((b.velocity[1] - anchorVelocity) - Real(0.3) * axis0).norm(), 1000 * kEpsilon);
    }
  }
}

}  // namespace
}  // namespace pbd
