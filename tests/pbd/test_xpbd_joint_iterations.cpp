// XpbdSettings::jointIterations: the joints swept k times per substep (Gauss–Seidel), λ
// continued after the first sweep. For hard rows the sweeps converge to the simultaneous Newton
// step of all joints (SHAKE iterated, Ryckaert, Ciccotti, Berendsen 1977, with the start
// directions), whose residual is second order in the substep's drift; for compliant rows to the
// XPBD solution C + α̃ λ = 0 of the substep (Macklin, Müller, Chentanez 2016, eq. 18: at a
// fixed point of the sweeps every Δλ is zero, i.e. every joint's right-hand side −C − α̃ λ is).
// Numbers are printed for docs/methods.md.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <variant>

#include "common/scene_fixtures.h"
#include "common/tolerances.h"
#include "pbd/model/world.h"

namespace pbd {
namespace {

/// A static anchor (body 0) and `links` boxes 0.4 × 0.1 × 0.1 m hanging from it along +x, joined
/// by joints of `type` (test::appendChain), under pbd.xpbd at h = 5 ms. No body has a collision
/// shape (as in cases/chain_10.json): adjacent links would touch and fight their joints.
Scene chainScene(int links, JointType type, int substeps, JointDirections directions,
                 int iterations) {
  Scene scene;
  scene.simulation.timeStepSize = Real(0.005);
  scene.rigidBodies.push_back(test::boxBody(0, Vector3(0.1, 0.1, 0.1), Vector3(0, 2, 0), 1, false));
  test::appendChain(scene, links, type);
  scene.simulation.stepMethod = StepMethod::Xpbd;
  scene.simulation.xpbd.substeps = substeps;
  scene.simulation.xpbd.jointDirections = directions;
  scene.simulation.xpbd.jointIterations = iterations;
  for (RigidBodyDesc& body : scene.rigidBodies)
    body.collision.type = CollisionObjectType::None;
  return scene;
}

struct ChainRun {
  Real jointError = 0;  ///< max over steps and joints of the linear joint error (m)
  Real drift = 0;       ///< max over steps of h_s² (|a| + (|ω|² + |α|) ℓ), ℓ = 0.2 m (m)
};

/// The double pendulum (two hinged links, released horizontal) for 1 s: its largest joint
/// error at the steps' ends and the largest drift δ a substep's prediction gives a joint (the
/// bound of tests/common/joint_hold.h, for either link: a, ω, α measured step to step, ℓ the
/// half link from the centre of mass to a joint).
ChainRun runDoublePendulum(int iterations, JointDirections directions) {
  constexpr int kSubsteps = 20;
  const Scene scene = chainScene(2, JointType::Hinge, kSubsteps, directions, iterations);
  World world = buildWorld(scene);
  const auto& b = world.bodies.rigid;
  const Real h = scene.simulation.timeStepSize;
  const Real hs = h / kSubsteps;
  const Real lever = Real(0.2);
  ChainRun run;
  for (int n = 0; n < 200; ++n) {
    Vector3 v[3], w[3];
    for (std::size_t i = 1; i < 3; ++i) {
      v[i] = b.velocity[i];
      w[i] = b.angularVelocity[i];
    }
    world.step();
    for (std::size_t i = 1; i < 3; ++i) {
      const Real accel = (b.velocity[i] - v[i]).norm() / h;
      const Real angularAccel = (b.angularVelocity[i] - w[i]).norm() / h;
      run.drift =
          std::max(run.drift,
                   hs * hs * (accel + (b.angularVelocity[i].squaredNorm() + angularAccel) * lever));
    }
    for (const Joint& joint : world.joints)
      run.jointError = std::max(run.jointError, jointError(joint, world.bodies).linear);
  }
  EXPECT_TRUE(b.position[2].allFinite());
  return run;
}

// One sweep leaves the Gauss–Seidel residual of the two coupled hinges: solving the second
// joint moves the first link and reopens the first joint, by a fraction of the second's
// correction — far above the O(δ²/ℓ) a Newton step leaves. Fifty sweeps converge to the
// simultaneous Newton step of both joints, whose residual is O(δ²/ℓ): the bound of
// tests/common/joint_hold.h, max δ/100 (δ ≈ 10⁻⁶ m here, so δ²/ℓ ≈ 10⁻¹¹ m), plus a round-off
// floor of 100 ε |x| for positions of ≈ 2 m. Two sweeps lie in between (the Gauss–Seidel rate
// of this pair: the second joint's correction moves the first joint by less than itself).
// Both directions settings: the sweeps continue along the directions the first one took.
TEST(XpbdJointIterations, SweepsConvergeToTheNewtonStepOfBothJointsOfADoublePendulum) {
  for (JointDirections directions : {JointDirections::Start, JointDirections::Predicted}) {
    const ChainRun one = runDoublePendulum(1, directions);
    const ChainRun two = runDoublePendulum(2, directions);
    const ChainRun many = runDoublePendulum(50, directions);
    const Real roundOff = 100 * kEpsilon * 2;
    const Real newtonBound = many.drift / 100 + roundOff;
    std::printf(
        "  double pendulum 1 s, 20 substeps, %s: max joint error 1 sweep %.3e m, 2 sweeps "
        "%.3e m, 50 sweeps %.3e m (Newton-step bound %.1e m)\n",
        jointDirectionsName(directions), double(one.jointError), double(two.jointError),
        double(many.jointError), double(newtonBound));
    EXPECT_GT(one.jointError, 10 * (one.drift / 100 + roundOff)) << "one sweep is no Newton step";
    EXPECT_LT(two.jointError, one.jointError);
    EXPECT_LE(many.jointError, newtonBound);
  }
}

/// C of every ball joint of `world` and the residual C + α̃ λ of its XPBD row.
struct BallResiduals {
  Real value = 0;     ///< max_j |C_j| (m)
  Real residual = 0;  ///< max_j |C_j + α̃ λ_j| (m)
};

BallResiduals ballResiduals(const World& world, const std::vector<XpbdJointMultipliers>& lambda,
                            Real complianceTilde) {
  BallResiduals r;
  for (std::size_t j = 0; j < world.joints.size(); ++j) {
    const Vector3 c = std::get<BallJoint>(world.joints[j]).positionRows(world.bodies).value;
    r.value = std::max(r.value, c.norm());
    r.residual = std::max(r.residual, (c + complianceTilde * lambda[j].head<3>()).norm());
  }
  return r;
}

// Compliant joints: continued sweeps converge to C + α̃ λ = 0, not to C = 0. Three links (2 kg
// each) with compliant ball joints, α = 2·10⁻⁶ m/N at h_s = 2 ms: α̃ = α/h_s² = 0.5 kg⁻¹, the
// links' inverse mass, so both the stretch left and the coupling are large; pulled apart by
// 1–2 cm, one substep's position pass. One sweep leaves a residual of the order of the
// offsets (each joint solved once, then moved by its neighbour); 200 sweeps converge (the
// Gauss–Seidel rate of K + α̃ on three joints is below 0.9 per sweep, 0.9²⁰⁰ ≈ 10⁻⁹), to a
// round-off floor of 10⁻¹⁰ of the offsets in double (Newton steps on O(1) numbers, 10⁶ ε);
// and the joints stay open by α̃ |λ| — a solve that reset λ in every sweep would close them.
TEST(XpbdJointIterations, ContinuedSweepsConvergeToTheCompliantSolutionNotTheRigidOne) {
  for (JointDirections directions : {JointDirections::Start, JointDirections::Predicted}) {
    Scene scene = chainScene(3, JointType::Ball, 1, directions, 1);
    constexpr Real kCompliance = Real(2e-6);  // m/N
    const Real substep = Real(0.002);
    scene.simulation.xpbd.jointLinearCompliance = kCompliance;
    World world = buildWorld(scene);
    RigidBodyStates& b = world.bodies.rigid;
    b.oldPosition = b.position;
    b.oldRotation = b.rotation;
    // Pull the links apart (and turn the last one) as a prediction would.
    b.position[1] += Vector3(0.01, -0.02, 0.005);
    b.position[2] += Vector3(0.02, -0.01, -0.01);
    b.position[3] += Vector3(0.005, 0.015, 0.01);
    b.rotation[3] =
        (Quaternion(AngleAxis(0.03, Vector3(1, 2, 3).normalized())) * b.rotation[3]).normalized();
    const Real complianceTilde = kCompliance / (substep * substep);
    std::vector<XpbdJointMultipliers> lambda(world.joints.size(), XpbdJointMultipliers::Zero());
    const Real offset = ballResiduals(world, lambda, complianceTilde).value;
    solveJointPositionsXpbd(world.joints, world.xpbd.jointSchedule, world.bodies, substep,
                            world.settings.xpbd, lambda, /*firstSweep=*/true);
    const BallResiduals first = ballResiduals(world, lambda, complianceTilde);
    for (int sweep = 1; sweep < 200; ++sweep)
      solveJointPositionsXpbd(world.joints, world.xpbd.jointSchedule, world.bodies, substep,
                              world.settings.xpbd, lambda, /*firstSweep=*/false);
    const BallResiduals converged = ballResiduals(world, lambda, complianceTilde);
    std::printf(
        "  3 compliant ball joints, %s: offsets %.3e m; |C + a~ lambda| 1 sweep %.3e m, "
        "200 sweeps %.3e m; |C| %.3e m\n",
        jointDirectionsName(directions), double(offset), double(first.residual),
        double(converged.residual), double(converged.value));
    EXPECT_GT(first.residual, 1e-2 * offset);
    EXPECT_LT(converged.residual, test::roundOffBound(1e-10) * offset);
    EXPECT_GT(converged.value, 1e-2 * offset);  // open by α̃ λ, not closed
  }
}

// The sweeps change the result (the setting reaches the solve) and stay bitwise deterministic.
TEST(XpbdJointIterations, TwoSweepsAreBitwiseDeterministicAndDifferFromOne) {
  const auto hash = [](int iterations) {
    World world =
        buildWorld(chainScene(10, JointType::Ball, 20, JointDirections::Start, iterations));
    for (int n = 0; n < 200; ++n)
      world.step();
    return world.stateHash();
  };
  EXPECT_EQ(hash(2), hash(2));
  EXPECT_NE(hash(2), hash(1));
}

// Fewer than one sweep is refused by name when the world is built.
TEST(XpbdJointIterations, FewerThanOneSweepIsRefusedByName) {
  try {
    buildWorld(chainScene(2, JointType::Ball, 20, JointDirections::Start, 0));
    ADD_FAILURE() << "jointIterations = 0 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("jointIterations must be at least 1, got 0"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace pbd
