// World: the complete state of one PBD simulation — bodies and particles (structure of
// arrays), joints in solve order, settings and time. No globals: several worlds can live and
// step side by side. Built once from a Scene; stepping allocates nothing.
#pragma once

#include <cstdint>
#include <vector>

#include "pbd/collision/collision_detection.h"
#include "pbd/constraints/constraint_families.h"
#include "pbd/contacts/contact_set.h"
#include "pbd/contacts/particle_tet_contact.h"
#include "pbd/fluids/fluid_model.h"
#include "pbd/joints/joint.h"
#include "pbd/joints/stiff_rod_tree_solver.h"
#include "pbd/model/body_states.h"
#include "pbd/model/scene.h"
#include "pbd/step/xpbd_step.h"

namespace pbd {

/// A rigid body's state in its scene frame (the frame of its geometry file).
struct SceneFrameState {
  Vector3 centerOfMass = Vector3::Zero();        ///< world
  Quaternion rotation = Quaternion::Identity();  ///< scene frame → world
  Vector3 velocity = Vector3::Zero();            ///< of the centre of mass, world
  Vector3 angularVelocity = Vector3::Zero();     ///< world
};

struct World {
  SimulationSettings settings;
  BodyStates bodies;
  std::vector<Joint> joints;         ///< in solve order (greedy colouring of the scene order)
  std::vector<int> jointSceneIndex;  ///< joints[k] is Scene::joints[jointSceneIndex[k]]
  /// Stiff-rod trees with the direct solver (Scene::stiffRodTrees with StiffRodSolver::Direct),
  /// solved after the joints in every position iteration; their joints are not in `joints`.
  std::vector<StiffRodTreeSolver> stiffRodTrees;
  /// The constraint families (constraints/constraint_families.h): particle distances, cloth
  /// triangles and bending, tet volumes and elements, shape matching, Cosserat rods and the
  /// user's generic constraints (rigid and particle; added in C++ after buildWorld), swept in the
  /// list's order after the joints and the stiff-rod trees in every position iteration.
  ConstraintFamilies constraints;
  /// Position-based fluids (fluids/fluid_model.h), one per scene FluidModel: solved in every
  /// substep after the other particle constraints, XSPH after the velocity update.
  std::vector<Fluid> fluids;
  CollisionDetector collision;  ///< shapes, surface samples, hierarchies, broad phase
  ContactMaterials materials;   ///< friction and restitution per pair
  ContactSet contacts;          ///< the contacts of the last step
  /// Particle–tet contacts between tet models (contacts/particle_tet_contact.h): those of the
  /// last detection (seed model: after the last step's substeps; else the last substep's).
  ParticleTetContactSet tetContacts;
  XpbdState xpbd;  ///< the XPBD step's contacts and multipliers
  Real time = 0;
  std::int64_t stepCount = 0;

  /// Advances by one settings.timeStepSize: the seed's step (step/step_controller.h) or, with
  /// settings.stepMethod == StepMethod::Xpbd, the XPBD step (step/xpbd_step.h).
  void step();

  SceneFrameState sceneFrameState(std::size_t body) const;
  /// FNV-1a hash of the raw bits of every position, rotation (rod segments' too) and velocity:
  /// equal hashes for bitwise-equal states (the determinism check).
  std::uint64_t stateHash() const;
};

/// Builds the world from a scene: bodies in their principal frames, particles, joints
/// initialised at the scene's initial poses and ordered for the solver, collision shapes
/// (type-5 grids from the cache in `gridCacheFolder`, or built in memory when it is empty,
/// padded by at least 2 × contactTolerance) and contact buffers. Throws std::invalid_argument,
/// naming the body, for collision parameters that describe no shape.
World buildWorld(const Scene& scene, const std::string& gridCacheFolder = {});
/// The same with explicit collision-shape options (cache folder, grid padding).
World buildWorld(const Scene& scene, const CollisionShapeOptions& options);

/// The seed's solve order: greedy colouring in creation order (a joint joins the first group
/// in which none of its bodies or particles is used yet), groups in order. Returns indices
/// into `ends`.
std::vector<int> colouredJointOrder(const std::vector<JointEnds>& ends, std::size_t bodyCount);

}  // namespace pbd
