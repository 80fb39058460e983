#include "pbd/model/world.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>

#include "pbd/step/step_controller.h"
#include "pbd/step/xpbd_step.h"

namespace pbd {
namespace {

void addRigidBodies(const Scene& scene, RigidBodyStates& b) {
  b.resize(scene.rigidBodies.size());
  for (std::size_t i = 0; i < scene.rigidBodies.size(); ++i) {
    const RigidBodyDesc& desc = scene.rigidBodies[i];
    const MassProperties& mp = desc.massProperties;
    b.position[i] = desc.initialCenterOfMass();
    b.rotation[i] = desc.initialPrincipalRotation();
    b.velocity[i] = desc.velocity;
    b.angularVelocity[i] = desc.angularVelocity;
    b.oldPosition[i] = b.lastPosition[i] = b.position[i];
    b.oldRotation[i] = b.lastRotation[i] = b.rotation[i];
    b.mass[i] = mp.mass;
    b.inertia[i] = mp.principalInertia;
    b.principalInScene[i] = mp.principalRotation;
    b.centerOfMassInScene[i] = mp.centerOfMass;
    const bool dynamic = desc.isDynamic && mp.mass > 0;
    b.inverseMass[i] = dynamic ? Real(1) / mp.mass : Real(0);
    b.inverseInertia[i] = dynamic ? Vector3(mp.principalInertia.cwiseInverse()) : Vector3::Zero();
    if (!dynamic) {
      b.velocity[i].setZero();
      b.angularVelocity[i].setZero();
    }
  }
}

void addParticles(const Scene& scene, ParticleStates& p) {
  p.resize(scene.particles.size());
  for (std::size_t i = 0; i < scene.particles.size(); ++i) {
    const ParticleDesc& desc = scene.particles[i];
    p.position[i] = p.oldPosition[i] = p.lastPosition[i] = desc.position;
    p.mass[i] = desc.mass;
    p.inverseMass[i] = desc.mass > 0 ? Real(1) / desc.mass : Real(0);
    p.velocity[i] = desc.mass > 0 ? desc.velocity : Vector3::Zero();
  }
}

void addRodSegments(const Scene& scene, SegmentStates& segments) {
  std::size_t count = 0;
  for (const LineModelDesc& model : scene.lineModels)
    count += model.segmentCount();
  segments.resize(count);
  for (const LineModelDesc& model : scene.lineModels)
    for (std::size_t k = 0; k < model.segmentCount(); ++k) {
      const std::size_t s = std::size_t(model.firstSegment) + k;
      segments.rotation[s] = segments.oldRotation[s] = model.frames[k];
      segments.inverseMass[s] = model.segmentInverseMass(k);
    }
}

template <typename T>
void hashBytes(std::uint64_t& hash, const T& value) {
  unsigned char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  for (unsigned char byte : bytes) {
    hash ^= byte;
    hash *= 1099511628211ull;  // FNV-1a 64-bit prime
  }
}

template <typename Vectors>
void hashVectors(std::uint64_t& hash, const Vectors& values) {
  for (const auto& v : values)
    for (Eigen::Index k = 0; k < v.size(); ++k)
      hashBytes(hash, v(k));
}

/// Stiff-rod joints of a tree with the direct solver are solved by its StiffRodTreeSolver.
bool solvedByTreeSolver(const Scene& scene, const JointDesc& desc) {
  if (desc.type != JointType::StiffRod || desc.stiffRod.tree < 0) return false;
  if (static_cast<std::size_t>(desc.stiffRod.tree) >= scene.stiffRodTrees.size())
    throw std::invalid_argument("stiff-rod joint " + desc.jsonPath + ": tree index " +
                                std::to_string(desc.stiffRod.tree) + " is not in the scene");
  return scene.stiffRodTrees[static_cast<std::size_t>(desc.stiffRod.tree)].solver ==
         StiffRodSolver::Direct;
}

}  // namespace

std::vector<int> colouredJointOrder(const std::vector<JointEnds>& ends, std::size_t bodyCount) {
  // Bodies and particles get separate slots (the seed shares one index space, which only adds
  // colours). used[g] marks the slots taken in group g.
  std::vector<std::vector<bool>> used;
  std::vector<std::vector<int>> groups;
  auto slots = [&](const JointEnds& e) {
    std::vector<std::size_t> s;
    if (e.body0 >= 0) s.push_back(static_cast<std::size_t>(e.body0));
    if (e.body1 >= 0) s.push_back(static_cast<std::size_t>(e.body1));
    if (e.particle >= 0) s.push_back(bodyCount + static_cast<std::size_t>(e.particle));
    return s;
  };
  std::size_t slotCount = bodyCount;
  for (const JointEnds& e : ends)
    if (e.particle >= 0) slotCount = std::max(slotCount, bodyCount + std::size_t(e.particle) + 1);

  for (std::size_t j = 0; j < ends.size(); ++j) {
    const auto s = slots(ends[j]);
    std::size_t g = 0;
    for (; g < groups.size(); ++g) {
      bool free = true;
      for (std::size_t slot : s)
        free = free && !used[g][slot];
      if (free) break;
    }
    if (g == groups.size()) {
      groups.emplace_back();
      used.emplace_back(slotCount, false);
    }
    groups[g].push_back(static_cast<int>(j));
    for (std::size_t slot : s)
      used[g][slot] = true;
  }
  std::vector<int> order;
  for (const auto& group : groups)
    order.insert(order.end(), group.begin(), group.end());
  return order;
}

World buildWorld(const Scene& scene, const std::string& gridCacheFolder) {
  CollisionShapeOptions options;
  options.gridCacheFolder = gridCacheFolder;
  options.minimumGridPadding = 2 * scene.simulation.contactTolerance;
  return buildWorld(scene, options);
}

World buildWorld(const Scene& scene, const CollisionShapeOptions& options) {
  World world;
  world.settings = scene.simulation;
  addRigidBodies(scene, world.bodies.rigid);
  addParticles(scene, world.bodies.particles);
  addRodSegments(scene, world.bodies.segments);

  std::vector<Joint> created;
  std::vector<JointEnds> ends;
  created.reserve(scene.joints.size());
  std::vector<int> sceneIndex;
  // The seed's step colours the joints in the seed's list order: its SceneLoaderDemo adds them
  // by block — ball, ball-on-line, hinge, universal, slider, rigid-body–particle, the four
  // motors, damper, spring, distance (the scene's own order within a block). The order decides
  // the colour groups and so the Gauss–Seidel order.
  std::vector<std::size_t> listOrder(scene.joints.size());
  for (std::size_t k = 0; k < listOrder.size(); ++k)
    listOrder[k] = k;
  if (scene.simulation.stepMethod == StepMethod::Seed) {
    const auto seedRank = [](JointType type) {
      switch (type) {
        case JointType::Damper:
          return 10;
        case JointType::RigidBodySpring:
          return 11;
        case JointType::Distance:
          return 12;
        case JointType::TargetAngleMotorHinge:
        case JointType::TargetVelocityMotorHinge:
        case JointType::TargetPositionMotorSlider:
        case JointType::TargetVelocityMotorSlider:
          return static_cast<int>(type) - 3;  // 6 … 9, after the rigid-body–particle joint
        default:
          return static_cast<int>(type);
      }
    };
    std::stable_sort(listOrder.begin(), listOrder.end(), [&](std::size_t a, std::size_t b) {
      return seedRank(scene.joints[a].type) < seedRank(scene.joints[b].type);
    });
  }
  for (std::size_t k : listOrder) {
    JointDesc desc = scene.joints[k];
    if (solvedByTreeSolver(scene, desc)) continue;
    desc.model = jointModelFor(scene.simulation);
    created.push_back(makeJoint(world.bodies, desc));
    ends.push_back(jointEnds(created.back()));
    sceneIndex.push_back(static_cast<int>(k));
  }
  for (int index : colouredJointOrder(ends, world.bodies.rigid.size())) {
    world.joints.push_back(std::move(created[static_cast<std::size_t>(index)]));
    world.jointSceneIndex.push_back(sceneIndex[static_cast<std::size_t>(index)]);
  }
  for (const StiffRodTreeDesc& tree : scene.stiffRodTrees) {
    if (tree.solver != StiffRodSolver::Direct) continue;
    std::vector<JointDesc> treeJoints;
    for (int j : tree.joints)
      treeJoints.push_back(scene.joints[static_cast<std::size_t>(j)]);
    world.stiffRodTrees.emplace_back(world.bodies, treeJoints, tree.jsonPath);
  }
  world.constraints = ConstraintFamilies::fromScene(scene);
  // The seed's step solves the cloth and solid elements in PositionBasedDynamics' colour order.
  if (scene.simulation.stepMethod == StepMethod::Seed) world.constraints.orderAsTheSeed(scene);
  world.fluids = buildFluids(scene);
  world.collision = CollisionDetector(scene, options);
  world.materials = ContactMaterials(scene);
  world.contacts.reserve(world.collision);
  world.tetContacts.reserve(world.collision.tetContacts());
  prepareXpbd(world, scene);
  return world;
}

void World::step() {
  if (settings.stepMethod == StepMethod::Xpbd)
    stepWorldXpbd(*this);
  else
    stepWorld(*this);
}

SceneFrameState World::sceneFrameState(std::size_t body) const {
  const RigidBodyStates& b = bodies.rigid;
  return {b.position[body], (b.rotation[body] * b.principalInScene[body].conjugate()).normalized(),
          b.velocity[body], b.angularVelocity[body]};
}

std::uint64_t World::stateHash() const {
  std::uint64_t hash = 14695981039346656037ull;  // FNV-1a 64-bit offset basis
  const RigidBodyStates& b = bodies.rigid;
  hashVectors(hash, b.position);
  for (const Quaternion& q : b.rotation)
    for (Eigen::Index k = 0; k < 4; ++k)
      hashBytes(hash, q.coeffs()(k));
  hashVectors(hash, b.velocity);
  hashVectors(hash, b.angularVelocity);
  hashVectors(hash, bodies.particles.position);
  hashVectors(hash, bodies.particles.velocity);
  for (const Quaternion& q : bodies.segments.rotation)
    for (Eigen::Index k = 0; k < 4; ++k)
      hashBytes(hash, q.coeffs()(k));
  hashVectors(hash, bodies.segments.angularVelocity);
  return hash;
}

}  // namespace pbd
