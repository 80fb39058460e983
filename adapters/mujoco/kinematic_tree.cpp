#include "adapters/mujoco/kinematic_tree.h"

#include <numeric>
#include <queue>

namespace pbdval::mujoco {
namespace {

using pbd::JointType;

/// Joint types only a MuJoCo joint can express (no equality constraint closes them).
bool treeOnly(JointType type) {
  switch (type) {
    case JointType::BallOnLine:
    case JointType::Universal:
    case JointType::Slider:
    case JointType::Damper:
    case JointType::TargetAngleMotorHinge:
    case JointType::TargetVelocityMotorHinge:
    case JointType::TargetPositionMotorSlider:
    case JointType::TargetVelocityMotorSlider:
      return true;
    default:
      return false;
  }
}

bool closesLoops(JointType type) {
  return type == JointType::Ball || type == JointType::Hinge;
}

/// Union-find over graph nodes; all static bodies share node 0 (the world).
class Components {
 public:
  explicit Components(const pbd::Scene& scene) : node_(scene.rigidBodies.size()) {
    int next = 1;
    for (std::size_t i = 0; i < node_.size(); ++i)
      node_[i] = scene.rigidBodies[i].isDynamic ? next++ : 0;
    root_.resize(std::size_t(next));
    std::iota(root_.begin(), root_.end(), 0);
  }
  int find(int body) { return findNode(node_[std::size_t(body)]); }
  bool unite(int a, int b) {
    const int ra = find(a), rb = find(b);
    if (ra == rb) return false;
    root_[std::size_t(std::max(ra, rb))] = std::min(ra, rb);  // the world stays its own root
    return true;
  }

 private:
  int findNode(int n) {
    while (root_[std::size_t(n)] != n)
      n = root_[std::size_t(n)] = root_[std::size_t(root_[std::size_t(n)])];
    return n;
  }
  std::vector<int> node_;
  std::vector<int> root_;
};

std::string loopMessage(const pbd::JointDesc& j) {
  return j.jsonPath + ": closes a kinematic loop, and MuJoCo has no equality constraint for a " +
         pbd::jointTypeName(j.type) +
         " joint (only ball and hinge joints can close loops in this adapter)";
}

/// Picks the forest edges: tree-only types first, then ball and hinge joints.
void chooseRoles(const pbd::Scene& scene, KinematicTree& tree) {
  Components components(scene);
  for (int pass = 0; pass < 2; ++pass) {
    for (std::size_t k = 0; k < scene.joints.size(); ++k) {
      const pbd::JointDesc& j = scene.joints[k];
      const bool candidate = pass == 0 ? treeOnly(j.type) : closesLoops(j.type);
      if (!candidate) continue;
      const bool bothStatic = !scene.rigidBodies[std::size_t(j.body1)].isDynamic &&
                              !scene.rigidBodies[std::size_t(j.body2)].isDynamic;
      if (bothStatic)
        tree.roles[k] = JointRole::StaticOnly;
      else if (components.unite(j.body1, j.body2))
        tree.roles[k] = JointRole::Tree;
      else if (closesLoops(j.type))
        tree.roles[k] = JointRole::LoopClosure;
      else
        tree.unsupported.push_back(loopMessage(j));
    }
  }
}

void classifyForces(const pbd::Scene& scene, KinematicTree& tree) {
  for (std::size_t k = 0; k < scene.joints.size(); ++k) {
    const pbd::JointDesc& j = scene.joints[k];
    if (j.type == JointType::RigidBodyParticleBall) {
      tree.unsupported.push_back(j.jsonPath + ": MuJoCo has no particles in this adapter");
      continue;
    }
    if (j.type != JointType::Distance && j.type != JointType::RigidBodySpring) continue;
    const bool bothStatic = !scene.rigidBodies[std::size_t(j.body1)].isDynamic &&
                            !scene.rigidBodies[std::size_t(j.body2)].isDynamic;
    tree.roles[k] = bothStatic                      ? JointRole::StaticOnly
                    : j.type == JointType::Distance ? JointRole::DistanceTendon
                                                    : JointRole::SpringTendon;
  }
}

/// MJCF nests child bodies inside their parents, and MuJoCo's XML parser (tinyxml2) refuses
/// documents nested deeper than 100 elements. Bodies deeper than this start a new tree (a free
/// body) when the joint to their parent can close a loop; that joint becomes an equality
/// constraint instead.
constexpr int kMaxTreeDepth = 64;

/// Breadth-first from the static bodies, then from the first body of every remaining group.
void orientTree(const pbd::Scene& scene, KinematicTree& tree) {
  const std::size_t n = scene.rigidBodies.size();
  std::vector<std::vector<int>> incident(n);
  for (std::size_t k = 0; k < scene.joints.size(); ++k)
    if (tree.roles[k] == JointRole::Tree) {
      incident[std::size_t(scene.joints[k].body1)].push_back(int(k));
      incident[std::size_t(scene.joints[k].body2)].push_back(int(k));
    }
  std::vector<bool> placed(n, false);
  std::vector<int> depth(n, 0);
  std::vector<int> cut;  // bodies that start a new tree because of the depth limit
  auto grow = [&](int root) {
    std::queue<int> queue;
    queue.push(root);
    placed[std::size_t(root)] = true;
    depth[std::size_t(root)] = 0;
    while (!queue.empty()) {
      const int body = queue.front();
      queue.pop();
      tree.order.push_back(body);
      for (int k : incident[std::size_t(body)]) {
        const pbd::JointDesc& j = scene.joints[std::size_t(k)];
        const int child = j.body1 == body ? j.body2 : j.body1;
        if (placed[std::size_t(child)]) continue;
        if (depth[std::size_t(body)] + 1 > kMaxTreeDepth && closesLoops(j.type)) {
          tree.roles[std::size_t(k)] = JointRole::LoopClosure;
          cut.push_back(child);
          continue;
        }
        placed[std::size_t(child)] = true;
        depth[std::size_t(child)] = depth[std::size_t(body)] + 1;
        tree.parent[std::size_t(child)] = body;
        tree.parentJoint[std::size_t(child)] = k;
        tree.reversed[std::size_t(child)] = child == j.body1;
        queue.push(child);
      }
    }
  };
  for (std::size_t i = 0; i < n; ++i)
    if (!scene.rigidBodies[i].isDynamic) grow(int(i));
  for (std::size_t c = 0; c < cut.size(); ++c)  // (grow may append more cuts)
    if (!placed[std::size_t(cut[c])]) {
      tree.freeRoot[std::size_t(cut[c])] = true;
      grow(cut[c]);
    }
  for (std::size_t i = 0; i < n; ++i)
    if (!placed[i]) {
      tree.freeRoot[i] = true;
      grow(int(i));
    }
}

}  // namespace

std::vector<int> KinematicTree::children(int body) const {
  std::vector<int> result;
  for (int i : order)
    if (parent[std::size_t(i)] == body) result.push_back(i);
  return result;
}

KinematicTree planKinematicTree(const pbd::Scene& scene) {
  KinematicTree tree;
  const std::size_t n = scene.rigidBodies.size();
  tree.parent.assign(n, -1);
  tree.parentJoint.assign(n, -1);
  tree.reversed.assign(n, false);
  tree.freeRoot.assign(n, false);
  tree.roles.assign(scene.joints.size(), JointRole::Unsupported);
  chooseRoles(scene, tree);
  classifyForces(scene, tree);
  orientTree(scene, tree);
  return tree;
}

}  // namespace pbdval::mujoco
