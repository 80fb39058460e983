// Every joint of the library as an XPBD constraint (the `pbd.xpbd` method).
//
// The joints' geometry is the one the `pbd` method uses: each joint type states its rows
// C ∈ ℝᵐ and Jacobians (A_k = ∂C/∂x_k, B_k = ∂C/∂θ_k) in its own header, and positionRows()
// evaluates them (point rows c₁ − c₀, axis rows n·(c₁ − c₀), distance rows ‖c₁ − c₀‖ − L,
// rotation rows vec(e) of the joint frames' relative rotation, motor targets included).
// What XPBD adds is compliance and the multiplier: once per substep (h the substep size),
//   K = Σ_k (w_k A_k A_kᵀ + B_k J_k B_kᵀ) + diag(α̃),  α̃_r = α_r / h²,
//   Δλ = K⁻¹ (−C − α̃ ∘ λ),  λ += Δλ,  Δx_k = w_k A_kᵀ Δλ,  Δθ_k = J_k B_kᵀ Δλ
// (Macklin, Müller, Chentanez 2016, eq. 18, with all rows of a joint solved together as in
// constraint_rows.h; Müller et al. 2020 solve the positional and the angular part of a joint
// as two scalar constraints along the correction's direction — the block solve is the same
// projection when both parts are hard and couples them exactly when they are not).
// λ is reset at the start of every substep (one position iteration per substep); with
// XpbdSettings::jointIterations = k > 1 the joints are swept k times per substep (before the
// other constraints and the contacts), λ continued after the first sweep: for hard rows each
// sweep is a further Gauss–Seidel pass of the same Newton steps (SHAKE iterated, Ryckaert,
// Ciccotti, Berendsen 1977, with JointDirections::Start), for compliant rows the sweeps
// converge to the XPBD solution C + α̃ λ = 0 of the substep (Macklin et al. 2016, §4).
//
// Compliance α_r of row r, by family:
//   rotation rows (no linear Jacobian): C = sin(θ/2) ≈ θ/2, so ½ k_θ θ² = ½ (4 k_θ) C² and
//     α_r = jointAngularCompliance / 4 (jointAngularCompliance in rad/(N m));
//   every other row: jointLinearCompliance (m/N);
//   rigid-body spring: its row 1/k (k from the scene); damper joint: its axial row 1/k;
//   a spring with k = 0 exerts nothing and is skipped;
//   stiff-rod joints: their own rows' compliances (stretch_bending_twisting_joint.h).
// Drives: the target-angle and target-position motors are position rows (their targets in C);
// the velocity motors drive their relative velocity in the velocity pass of every substep
// (their solveVelocity, a hard velocity constraint). The seed's joints have no limits.
// Nothing here allocates.
#pragma once

#include <vector>

#include "pbd/joints/joint.h"

namespace pbd {

/// λ of one joint (rows beyond the joint's kRows unused).
using XpbdJointMultipliers = Eigen::Matrix<Real, 6, 1>;

/// The joints of World::joints arranged once for the substep's loops, so that a joint costs
/// no more per substep than its own work (bench/callgrind_step.py on chain_100,
/// docs/benchmarks.md#the-xpbd-substep-at-its-operation-count-issue-30):
///   - ball joints (the chains) are stored by type, their bodies and principal-frame anchors in
///     one contiguous array solved by a typed loop that calls the point-constraint solve
///     directly (no variant dispatch, no per-joint reload of the joint's frames);
///   - the joints' order is kept: the position pass walks runs of consecutive joints of one
///     kind (ball joints in the typed loop, the others through the variant), so the Gauss–Seidel
///     order and every result are those of one loop over World::joints;
///   - the motor targets and the velocity pass visit only the joints that have them (the
///     velocity motors and the target motors), not every joint for an empty call.
struct XpbdJointSchedule {
  struct Ball {
    int body0 = -1;
    int body1 = -1;
    Vector3 anchor0 = Vector3::Zero();  ///< in body0's principal frame
    Vector3 anchor1 = Vector3::Zero();
  };
  /// Joints [begin, end) of World::joints, all ball joints (solved from `balls`, starting at
  /// `firstBall`) or none.
  struct Run {
    std::size_t begin = 0;
    std::size_t end = 0;
    bool ball = false;
    std::size_t firstBall = 0;
  };
  std::vector<Ball> balls;
  std::vector<Run> runs;
  std::vector<std::size_t> withTarget;        ///< joints whose updateTarget does something
  std::vector<std::size_t> withVelocityPass;  ///< joints whose solveVelocity does something
};

/// The schedule of `joints` (called once, when the world is built; allocates).
XpbdJointSchedule scheduleJointsXpbd(const std::vector<Joint>& joints);

/// Every joint with a target takes its set point for time `time` (the substep's end).
void updateJointTargetsXpbd(std::vector<Joint>& joints, const XpbdJointSchedule& schedule,
                            Real time);

/// One Gauss–Seidel sweep of the substep's position iteration: every joint of `joints` in
/// order, its λ (`multipliers[j]`, sized like `joints`) accumulated by one XPBD projection (see
/// above) — reset to zero first when `firstSweep` (the substep's first sweep), continued in the
/// XpbdSettings::jointIterations − 1 sweeps after it. Through `schedule` (scheduleJointsXpbd
/// of the same joints).
void solveJointPositionsXpbd(std::vector<Joint>& joints, const XpbdJointSchedule& schedule,
                             BodyStates& bodies, Real substepSize, const XpbdSettings& settings,
                             std::vector<XpbdJointMultipliers>& multipliers,
                             bool firstSweep = true);

/// The joints' velocity pass, in order (velocity motors; nothing for the others, which are
/// not visited).
void solveJointVelocitiesXpbd(std::vector<Joint>& joints, const XpbdJointSchedule& schedule,
                              BodyStates& bodies);

}  // namespace pbd
