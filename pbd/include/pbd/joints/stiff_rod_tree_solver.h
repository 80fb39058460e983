// Direct solver for a tree of stiff-rod joints (the seed's
// DirectPositionBasedSolverForStiffRodsConstraint; `TreeModels` with solverType 12).
//
// Every joint j of the tree is a StretchBendingTwistingJoint (C_j ∈ ℝ⁶, Jacobians J_jb = [A_b B_b]
// for its dynamic bodies b, compliance α̃_j; stretch_bending_twisting_joint.h). One iteration
// solves the XPBD system of *all* joints at once, linearised at the current poses:
//   M_b Δq_b − Σ_j J_jbᵀ Δλ_j = 0            (each dynamic body b, Δq_b = (Δx_b, Δθ_b))
//   Σ_b J_jb Δq_b + α̃_j Δλ_j = −C_j − α̃_j λ_j  (each joint j)
// with M_b = diag(m_b 𝟙, I_b,world). Written symmetrically, H = [[M, −Jᵀ], [−J, −α̃]], the
// unknowns are 6-vectors on the nodes of a graph whose nodes are the dynamic bodies and the
// joints and whose edges are "joint j acts on body b". For a tree (no closed loop) that graph is
// a forest, and block L D Lᵀ in an order that eliminates children before their parents creates
// no fill-in (Baraff 1996, "Linear-time dynamics using Lagrange multipliers"):
//   factor, i ascending:  D_i = H_ii − Σ_{c child of i} L_cᵀ D_c L_c,  L_i = D_i⁻¹ H_{i,parent(i)}
//   forward, i ascending: b'_i = b_i − Σ_c L_cᵀ b'_c
//   backward, i descending: x_i = D_i⁻¹ b'_i − L_i x_{parent(i)}
// Cost and storage are linear in the number of joints. The order (a breadth-first search from
// the first joint of each connected part, reversed) is computed once at build time; every
// block is preallocated, so an iteration allocates nothing. Then Δx_b, Δθ_b are applied to the
// bodies and λ_j += Δλ_j (λ accumulated over the substep's iterations, reset by beginSubstep).
// On a chain (or any tree) one iteration is the exact solution of the linearised system that
// the per-joint Gauss–Seidel iterations of the iterative solver converge to.
// Reference: Deul, Müller, Bender 2018, "Direct position-based solver for stiff rods",
// CGF 37(6), §5 (eq. 19–28). Difference from the seed: nodes in flat preallocated arrays
// instead of std::list of heap nodes; the node order is a BFS from the first joint (the seed
// roots the tree at a segment); the per-node 6×6 pivots are factorised by LDLᵀ with pivoting.
#pragma once

#include <Eigen/Cholesky>
#include <string>
#include <vector>

#include "pbd/joints/stretch_bending_twisting_joint.h"

namespace pbd {

class StiffRodTreeSolver {
 public:
  using Matrix6 = Eigen::Matrix<Real, 6, 6>;
  using Vector6 = stiff_rod::Vector6;

  /// Builds the solver for `joints` (each of type StiffRod, between two rigid bodies of
  /// `bodies`). Throws std::invalid_argument, naming `name`, when the joints form a closed loop.
  StiffRodTreeSolver(const BodyStates& bodies, const std::vector<JointDesc>& joints,
                     std::string name);

  /// Compliances for substep h; λ = 0.
  void beginSubstep(Real substepSize);
  /// One direct solve of all joints (see above).
  void solvePosition(BodyStates& bodies);

  const std::vector<StretchBendingTwistingJoint>& joints() const { return joints_; }
  const std::vector<Vector6>& multipliers() const { return multipliers_; }
  /// The nodes in elimination order: body index (≥ 0) or −1 − joint index.
  std::vector<int> nodeOrder() const;

 private:
  struct Node {
    int body = -1;           ///< rigid-body index, or −1 for a joint node
    int joint = -1;          ///< index into joints_, or −1 for a body node
    int parent = -1;         ///< node index (> this node's), −1 for a root
    int parentJointEnd = 0;  ///< body node: which end (0, 1) of its parent joint it is
    int jointEnd = 0;        ///< joint node: which end (0, 1) of it its parent body is
  };

  void buildOrder(const BodyStates& bodies);

  std::string name_;
  std::vector<StretchBendingTwistingJoint> joints_;
  std::vector<Node> nodes_;        ///< elimination order: children before parents
  std::vector<Matrix6> diagonal_;  ///< D_i
  std::vector<Eigen::LDLT<Matrix6>> factors_;
  std::vector<Matrix6> toParent_;        ///< H_{i,parent}, then L_i = D_i⁻¹ H_{i,parent}
  std::vector<Vector6> rhs_;             ///< b, b', then the solution x
  std::vector<ConstraintRows<6>> rows_;  ///< C and ∇C of every joint at this iteration
  std::vector<Vector6> multipliers_;     ///< λ_j of this substep
};

}  // namespace pbd
