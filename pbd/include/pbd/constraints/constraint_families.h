// The constraint families of a World: every array of constraints that a position iteration
// sweeps once, Gauss–Seidel, after the joints and the stiff-rod trees and before the contacts —
// rigid-body generic constraints, particle distances, cloth triangles, tet volumes and elements,
// shape matching, cloth bending, particle generic constraints and Cosserat rods. Joints,
// stiff-rod trees, contacts and fluids are not families: they have their own substep set-up,
// velocity passes or iterations, and each step method schedules them itself.
//
// The one list (ConstraintFamilies::forEachFamily; cf. Jolt's SoftBodyUpdateContext /
// ProcessGroup, which applies the arrays of SoftBodySharedSettings one after the other):
// - Every family is listed exactly once, in the order in which a position iteration solves
//   them. Both step methods — the seed's step (step/step_controller.cpp) and the XPBD step
//   (step/xpbd_step.cpp) — solve the families only through solvePositions, so they share this
//   order; buildWorld (model/world.cpp) fills them only through fromScene, in the same order
//   (so that of two invalid families the same one is reported first).
// - An entry names the array, how it is built from a Scene (a function of the scene, or
//   kAddedInCpp for the arrays the user fills in C++ after buildWorld) and its sweep: one
//   Gauss–Seidel pass over the array in order, given the bodies, the substep size and whether
//   this is the first iteration of the substep (the XPBD families reset their multipliers λ
//   then; the seed's step passes iteration == 0, the XPBD step, with one iteration per substep,
//   always true).
// - A sweep is serial, deterministic and allocates nothing (the step's no-allocation rule).
// Adding a family: declare its array below and add its entry to forEachFamily — nothing else
// (the steps and buildWorld follow the list).
#pragma once

#include <cstddef>
#include <vector>

#include "pbd/constraints/cosserat_rod.h"
#include "pbd/constraints/dihedral_bending.h"
#include "pbd/constraints/fem_tet.h"
#include "pbd/constraints/fem_triangle.h"
#include "pbd/constraints/generic_constraint.h"
#include "pbd/constraints/generic_rigid_constraint.h"
#include "pbd/constraints/isometric_bending.h"
#include "pbd/constraints/particle_distance.h"
#include "pbd/constraints/shape_matching.h"
#include "pbd/constraints/strain_tet.h"
#include "pbd/constraints/strain_triangle.h"
#include "pbd/constraints/tet_volume.h"
#include "pbd/model/body_states.h"
#include "pbd/model/scene.h"

namespace pbd {

/// The build rule of a family that has no scene key: the user adds its constraints in C++
/// after buildWorld; fromScene leaves it empty.
struct AddedInCpp {};
inline constexpr AddedInCpp kAddedInCpp{};

struct ConstraintFamilies {
  /// User rigid-body constraints (constraints/generic_rigid_constraint.h).
  std::vector<GenericRigidConstraint> genericRigidConstraints;
  /// Distance constraints between particles: cloth and solid edges (particle_distance.h).
  std::vector<ParticleDistanceConstraint> particleDistances;
  std::vector<FemTriangleConstraint> femTriangles;        ///< cloth method 2 (fem_triangle.h)
  std::vector<StrainTriangleConstraint> strainTriangles;  ///< cloth method 3 (strain_triangle.h)
  std::vector<TetVolumeConstraint> tetVolumes;            ///< tet volumes (tet_volume.h)
  std::vector<FemTetConstraint> femTets;                  ///< FEM tets (fem_tet.h)
  std::vector<StrainTetConstraint> strainTets;            ///< solid method 4 (strain_tet.h)
  std::vector<ShapeMatchingConstraint> shapeMatching;     ///< solid method 5 (shape_matching.h)
  /// Bending of cloth, isometric (isometric_bending.h) or dihedral (dihedral_bending.h).
  std::vector<IsometricBendingConstraint> clothBending;
  std::vector<DihedralBendingConstraint> clothDihedrals;
  /// User particle constraints (constraints/generic_constraint.h).
  std::vector<GenericParticleConstraint> genericConstraints;
  /// Cosserat rods of the scene's line models (cosserat_rod.h), on the particles and
  /// BodyStates::segments.
  RodConstraints rods;

  /// The list: calls visit(array, build, sweep) for every family, in solve order, where
  /// build(scene) returns the array (or is kAddedInCpp) and sweep(array, bodies, substepSize,
  /// firstIteration) is its Gauss–Seidel pass.
  template <typename Visitor>
  void forEachFamily(Visitor&& visit) {
    using Range = std::size_t;
    visit(genericRigidConstraints, kAddedInCpp,
          [](auto& c, BodyStates& b, Real h, bool first, Range, Range) {
            solveGenericRigidConstraints(c, b.rigid, h, first);
          });
    visit(particleDistances, deformableDistanceConstraints,
          [](auto& c, BodyStates& b, Real h, bool first, Range begin, Range end) {
            solveParticleDistances(c, b.particles, h, first, begin, end);
          });
    visit(femTriangles, femTriangleConstraints,
          [](auto& c, BodyStates& b, Real, bool, Range begin, Range end) {
            solveFemTriangles(c, b.particles, begin, end);
          });
    visit(strainTriangles, strainTriangleConstraints,
          [](auto& c, BodyStates& b, Real, bool, Range begin, Range end) {
            solveStrainTriangles(c, b.particles, begin, end);
          });
    visit(tetVolumes, solidVolumeConstraints,
          [](auto& c, BodyStates& b, Real h, bool first, Range begin, Range end) {
            solveTetVolumes(c, b.particles, h, first, begin, end);
          });
    visit(femTets, solidFemConstraints,
          [](auto& c, BodyStates& b, Real h, bool first, Range begin, Range end) {
            solveFemTets(c, b.particles, h, first, begin, end);
          });
    visit(strainTets, strainTetConstraints,
          [](auto& c, BodyStates& b, Real, bool, Range begin, Range end) {
            solveStrainTets(c, b.particles, begin, end);
          });
    visit(shapeMatching, shapeMatchingConstraints,
          [](auto& c, BodyStates& b, Real, bool, Range begin, Range end) {
            solveShapeMatching(c, b.particles, begin, end);
          });
    visit(clothBending, clothBendingConstraints,
          [](auto& c, BodyStates& b, Real h, bool first, Range begin, Range end) {
            solveIsometricBending(c, b.particles, h, first, begin, end);
          });
    visit(clothDihedrals, clothDihedralConstraints,
          [](auto& c, BodyStates& b, Real, bool, Range begin, Range end) {
            solveDihedralBending(c, b.particles, begin, end);
          });
    visit(genericConstraints, kAddedInCpp, [](auto& c, BodyStates& b, Real, bool, Range, Range) {
      solveGenericConstraints(c, b.particles);
    });
    visit(rods, rodConstraints, [](auto& c, BodyStates& b, Real h, bool first, Range, Range) {
      solveRods(c, b.particles, b.segments, h, first);
    });
  }

  /// The seed's Gauss–Seidel order of the cloth and solid families (indices kFirstSeedOrdered …
  /// kLastSeedOrdered of the list), set by orderAsTheSeed: runs of consecutive elements of one
  /// family. Empty: family by family, in list order.
  struct SeedRun {
    int family = 0;
    std::size_t begin = 0, end = 0;
  };
  std::vector<SeedRun> seedOrder;
  static constexpr int kFirstSeedOrdered = 1;  ///< particleDistances
  static constexpr int kLastSeedOrdered = 9;   ///< clothDihedrals

  /// Puts the cloth and solid families in PositionBasedDynamics' order: its constraint list
  /// (per triangle model its cloth elements, then its bending elements; then per tet model its
  /// solid elements — method 1 and 6: edges, then volumes) split greedily into groups of
  /// elements that share no particle (SimulationModel::initConstraintGroups), solved group by
  /// group. Each family's array is permuted into that order and seedOrder lists the runs. The
  /// rods, still swept last, are put in the seed's order among themselves (orderRodsAsTheSeed).
  void orderAsTheSeed(const Scene& scene);

  /// Every family with a scene key built from `scene`, in list order (the families' own
  /// std::invalid_argument for bad input); the kAddedInCpp families empty.
  static ConstraintFamilies fromScene(const Scene& scene);

  /// One sweep of every family, in list order (the cloth and solid families in seedOrder when it
  /// is set): the families' part of a position iteration. `firstIteration`: the first iteration
  /// of a substep of size `substepSize`.
  void solvePositions(BodyStates& bodies, Real substepSize, bool firstIteration);
};

}  // namespace pbd
