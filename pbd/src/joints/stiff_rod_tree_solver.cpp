#include "pbd/joints/stiff_rod_tree_solver.h"

#include <algorithm>
#include <map>
#include <stdexcept>

namespace pbd {

StiffRodTreeSolver::StiffRodTreeSolver(const BodyStates& bodies,
                                       const std::vector<JointDesc>& joints, std::string name)
    : name_(std::move(name)) {
  joints_.reserve(joints.size());
  for (const JointDesc& desc : joints)
    joints_.emplace_back(bodies, desc);
  buildOrder(bodies);
  const std::size_t n = nodes_.size();
  diagonal_.assign(n, Matrix6::Zero());
  factors_.resize(n);
  toParent_.assign(n, Matrix6::Zero());
  rhs_.assign(n, Vector6::Zero());
  rows_.resize(joints_.size());
  multipliers_.assign(joints_.size(), Vector6::Zero());
}

void StiffRodTreeSolver::buildOrder(const BodyStates& bodies) {
  // Graph nodes: joints 0..J−1 (with at least one dynamic end), then dynamic bodies.
  const int jointCount = static_cast<int>(joints_.size());
  std::map<int, int> bodyNode;  // body index → graph node
  std::vector<int> graphBody;   // graph node − J → body index
  std::vector<std::vector<int>> adjacent(joints_.size());
  std::vector<bool> active(joints_.size(), false);
  for (int j = 0; j < jointCount; ++j) {
    const JointEnds ends = joints_[std::size_t(j)].ends();
    for (int body : {ends.body0, ends.body1}) {
      if (!bodies.rigid.isDynamic(static_cast<std::size_t>(body))) continue;
      auto it = bodyNode.find(body);
      if (it == bodyNode.end()) {
        it = bodyNode.emplace(body, jointCount + static_cast<int>(graphBody.size())).first;
        graphBody.push_back(body);
        adjacent.emplace_back();
      }
      adjacent[std::size_t(j)].push_back(it->second);
      adjacent[std::size_t(it->second)].push_back(j);
      active[std::size_t(j)] = true;
    }
  }
  // Breadth-first search from the first unvisited joint of every connected part.
  const std::size_t graphSize = adjacent.size();
  std::vector<int> parent(graphSize, -1), order;
  std::vector<bool> visited(graphSize, false);
  for (int root = 0; root < jointCount; ++root) {
    if (visited[std::size_t(root)] || !active[std::size_t(root)]) continue;
    std::size_t head = order.size();
    order.push_back(root);
    visited[std::size_t(root)] = true;
    for (; head < order.size(); ++head) {
      const int node = order[head];
      for (int next : adjacent[std::size_t(node)]) {
        if (next == parent[std::size_t(node)]) continue;
        if (visited[std::size_t(next)]) {
          throw std::invalid_argument(
              name_ +
              ": the stiff-rod joints form a closed loop (the direct solver needs a "
              "tree); use the iterative solver (solverType 0)");
        }
        visited[std::size_t(next)] = true;
        parent[std::size_t(next)] = node;
        order.push_back(next);
      }
    }
  }
  // Elimination order: the reversed search order (children before parents).
  std::vector<int> position(graphSize, -1);
  for (std::size_t k = 0; k < order.size(); ++k)
    position[std::size_t(order[order.size() - 1 - k])] = static_cast<int>(k);
  nodes_.assign(order.size(), Node{});
  for (int g : order) {
    Node& node = nodes_[std::size_t(position[std::size_t(g)])];
    const int p = parent[std::size_t(g)];
    node.parent = p < 0 ? -1 : position[std::size_t(p)];
    if (g < jointCount) {
      node.joint = g;
      if (p >= 0) {
        const int body = graphBody[std::size_t(p - jointCount)];
        node.jointEnd = joints_[std::size_t(g)].ends().body0 == body ? 0 : 1;
      }
    } else {
      node.body = graphBody[std::size_t(g - jointCount)];
      if (p >= 0) node.parentJointEnd = joints_[std::size_t(p)].ends().body0 == node.body ? 0 : 1;
    }
  }
}

std::vector<int> StiffRodTreeSolver::nodeOrder() const {
  std::vector<int> order;
  for (const Node& node : nodes_)
    order.push_back(node.body >= 0 ? node.body : -1 - node.joint);
  return order;
}

void StiffRodTreeSolver::beginSubstep(Real substepSize) {
  for (StretchBendingTwistingJoint& joint : joints_)
    joint.beginSubstep(substepSize);
  for (Vector6& lambda : multipliers_)
    lambda.setZero();
}

void StiffRodTreeSolver::solvePosition(BodyStates& bodies) {
  RigidBodyStates& b = bodies.rigid;
  for (std::size_t j = 0; j < joints_.size(); ++j)
    rows_[j] = joints_[j].positionRows(bodies);
  // Assemble H's blocks and b on the nodes.
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    const Node& node = nodes_[i];
    Matrix6& d = diagonal_[i];
    if (node.body >= 0) {  // M_b = diag(m 𝟙, R diag(I) Rᵀ); b = 0
      const auto k = static_cast<std::size_t>(node.body);
      const Matrix3 rotation = b.rotation[k].toRotationMatrix();
      d.setZero();
      d.topLeftCorner<3, 3>().diagonal().setConstant(b.mass[k]);
      d.bottomRightCorner<3, 3>() = rotation * b.inertia[k].asDiagonal() * rotation.transpose();
      rhs_[i].setZero();
      if (node.parent >= 0) {  // H_{b,j} = −J_jbᵀ
        const ConstraintRows<6>& rows = rows_[std::size_t(nodes_[std::size_t(node.parent)].joint)];
        const auto end = static_cast<std::size_t>(node.parentJointEnd);
        toParent_[i].topRows<3>() = -rows.linear[end].transpose();
        toParent_[i].bottomRows<3>() = -rows.angular[end].transpose();
      }
    } else {  // −α̃_j; b = C_j + α̃_j ∘ λ_j
      const auto j = static_cast<std::size_t>(node.joint);
      const Vector6& alpha = joints_[j].compliance();
      d = -Matrix6(alpha.asDiagonal());
      rhs_[i] = rows_[j].value + alpha.cwiseProduct(multipliers_[j]);
      if (node.parent >= 0) {  // H_{j,b} = −J_jb
        const auto end = static_cast<std::size_t>(node.jointEnd);
        toParent_[i].leftCols<3>() = -rows_[j].linear[end];
        toParent_[i].rightCols<3>() = -rows_[j].angular[end];
      }
    }
  }
  // Factor and forward substitution, children before parents.
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    factors_[i].compute(diagonal_[i]);
    const int parent = nodes_[i].parent;
    if (parent < 0) continue;
    const auto p = static_cast<std::size_t>(parent);
    const Matrix6 coupling = toParent_[i];                          // H_{i,p}
    toParent_[i] = factors_[i].solve(coupling);                     // L_i = D_i⁻¹ H_{i,p}
    diagonal_[p].noalias() -= coupling.transpose() * toParent_[i];  // L_iᵀ D_i L_i
    rhs_[p].noalias() -= toParent_[i].transpose() * rhs_[i];
  }
  // Back substitution, parents before children.
  for (std::size_t k = nodes_.size(); k-- > 0;) {
    Vector6 x = factors_[k].solve(rhs_[k]);
    if (nodes_[k].parent >= 0) x.noalias() -= toParent_[k] * rhs_[std::size_t(nodes_[k].parent)];
    rhs_[k] = x;
  }
  if (!std::all_of(rhs_.begin(), rhs_.end(), [](const Vector6& x) { return x.allFinite(); }))
    return;  // a singular system (no dynamic end in a part): no correction
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    const Node& node = nodes_[i];
    if (node.body >= 0)
      joint_parts::applyPositionCorrection(b, node.body, rhs_[i].head<3>(), rhs_[i].tail<3>());
    else
      multipliers_[std::size_t(node.joint)] += rhs_[i];
  }
}

}  // namespace pbd
