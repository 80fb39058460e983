// World: the complete state of one PBD simulation — bodies and particles (structure of
// arrays), joints in solve order, settings and time. No globals: several worlds can live and
// step side by side. Built once from a Scene; stepping allocates nothing.
#pragma once

#include <cstdint>
#include <vector>

#include "pbd/collision/collision_detection.h"
#include "pbd/constraints/cosserat_rod.h"
#include "pbd/constraints/dihedral_bending.h"
#include "pbd/constraints/fem_triangle.h"
#include "pbd/constraints/fem_tet.h"
#include "pbd/constraints/generic_constraint.h"
#include "pbd/constraints/generic_rigid_constraint.h"
#include "pbd/constraints/isometric_bending.h"
#include "pbd/constraints/particle_distance.h"
#include "pbd/constraints/shape_matching.h"
#include "pbd/constraints/strain_tet.h"
#include "pbd/constraints/strain_triangle.h"
#include "pbd/constraints/tet_volume.h"
#include "pbd/contacts/contact_set.h"
#include "pbd/fluids/fluid_model.h"
#include "pbd/contacts/particle_tet_contact.h"
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
  /// User rigid-body constraints (constraints/generic_rigid_constraint.h), added in C++ after
  /// buildWorld (no scene key); solved after the joints and the stiff-rod trees.
  std::vector<GenericRigidConstraint> genericRigidConstraints;
  /// Distance constraints between particles (cloth and solid edges,
  /// constraints/particle_distance.h), the triangles of cloth (FEM or strain-based), volume
  /// constraints of tets (constraints/tet_volume.h),
  /// and the bending of cloth, isometric (constraints/isometric_bending.h) or dihedral
  /// (constraints/dihedral_bending.h), solved in this order after the joints in every position
  /// iteration.
  std::vector<ParticleDistanceConstraint> particleDistances;
  std::vector<FemTriangleConstraint> femTriangles;  ///< cloth method 2 (fem_triangle.h)
  std::vector<StrainTriangleConstraint> strainTriangles;  ///< cloth method 3 (strain_triangle.h)
  std::vector<TetVolumeConstraint> tetVolumes;
  std::vector<FemTetConstraint> femTets;  ///< FEM tets (constraints/fem_tet.h), after the volumes
  std::vector<StrainTetConstraint> strainTets;  ///< solid method 4 (strain_tet.h)
  std::vector<ShapeMatchingConstraint> shapeMatching;  ///< solid method 5 (shape_matching.h)
  std::vector<IsometricBendingConstraint> clothBending;
  std::vector<DihedralBendingConstraint> clothDihedrals;
  /// User constraints (constraints/generic_constraint.h), added in C++ after buildWorld (no
  /// scene key); solved after every other particle constraint.
  std::vector<GenericParticleConstraint> genericConstraints;
  /// Cosserat rods of the scene's line models (constraints/cosserat_rod.h), on the particles
  /// and bodies.segments; solved after the generic constraints.
  RodConstraints rods;
  /// Position-based fluids (fluids/fluid_model.h), one per scene FluidModel: solved in every
  /// substep after the other particle constraints, XSPH after the velocity update.
  std::vector<Fluid> fluids;
  CollisionDetector collision;       ///< shapes, surface samples, hierarchies, broad phase
  ContactMaterials materials;        ///< friction and restitution per pair
  ContactSet contacts;               ///< the contacts of the last step
  /// Particle–tet contacts between tet models (contacts/particle_tet_contact.h): those of the
  /// last detection (seed model: after the last step's substeps; else the last substep's).
  ParticleTetContactSet tetContacts;
  XpbdState xpbd;                    ///< the XPBD step's contacts and multipliers
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
