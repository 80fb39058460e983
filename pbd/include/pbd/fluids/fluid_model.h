// A position-based fluid in the World: its particles (a range of the World's particles), its
// container's boundary particles, neighbour search and solver buffers, and the two calls the
// steps make in every substep (solveFluids after the position constraints, applyFluidViscosity
// after the velocity update). The math is in constraints/fluid_density.h.
//
// Per substep: neighbour search on the predicted positions (fluid–fluid and fluid–boundary,
// kept for the substep, as in the paper and the seed), then `iterations` Jacobi iterations of
// the density constraints (all ρ and λ, then all Δx, then x += Δx), then, after the velocity
// update, one XSPH pass on densities at the final positions.
//
// Time step: the World's fixed substep. The seed's FluidDemo adapts its step to a CFL bound
// h = 0.4 · 2r / v_max clamped to [1e-4, 5e-3] s; a World steps every model together at a
// fixed size (validation compares runs at fixed sample times), so no adaptive step is taken:
// a scene must choose substeps with v_max · h_s ≤ 0.4 · 2r (docs/scene-format.md).
//
// No heap allocation after buildFluids: grids, neighbour lists (capacity
// kMaxFluidNeighbours each, see fluids/neighbour_search.h) and buffers are sized at build.
#pragma once

#include <cstddef>
#include <vector>

#include "pbd/fluids/neighbour_search.h"
#include "pbd/fluids/sph_kernels.h"
#include "pbd/math/types.h"
#include "pbd/model/body_states.h"
#include "pbd/model/scene.h"

namespace pbd {

/// Neighbour-list capacity (fluid and boundary lists each): four times the 32 neighbours of an
/// interior lattice particle at rest density (neighbour_search.h).
inline constexpr std::size_t kMaxFluidNeighbours = 128;
/// The seed's neighbour cap (NeighborhoodSearchSpatialHashing's maxNeighbors): the seed
/// formulation keeps the first 60 entries of a list in the seed's order, as the seed does.
inline constexpr int kSeedMaxNeighbours = 60;
/// The seed's ε in the denominator of λ.
inline constexpr Real kPbfEpsilon = Real(1e-6);

struct Fluid {
  int firstParticle = 0;
  int particleCount = 0;
  Real particleMass = 0;
  Real restDensity = 1000;
  Real viscosity = 0;
  int iterations = 5;
  FluidFormulation formulation = FluidFormulation::Symmetric;
  CubicSplineKernel kernel;
  SeedCubicKernel seedKernel;  ///< the seed formulation's kernel
  /// The container's walls, then the boundaryWalls' particles (static).
  std::vector<Vector3> boundaryPositions;
  std::vector<Real> boundaryPsi;  ///< ψ_b = ρ₀ V_b (Akinci 2012)
  NeighbourSearch fluidGrid;
  NeighbourSearch boundaryGrid;  ///< indexed once at build
  NeighbourLists fluidNeighbours;
  NeighbourLists boundaryNeighbours;
  /// The seed formulation's lists: fluid (j < n) and boundary (n + b) mixed, in the seed's order.
  NeighbourLists seedNeighbours;
  std::vector<Real> density;
  std::vector<Real> lambda;
  std::vector<Vector3> delta;  ///< Δx, then Δv
  /// Neighbours left out by the list capacity since the build (0 in every sane scene).
  std::size_t droppedNeighbours = 0;
};

/// The particles filling `block` on a lattice of spacing 2r: centres min + r + 2r k for every k
/// with centre + r ≤ max (to kLatticeSlack relative, fluid_lattice.h), x slowest, z fastest.
/// Empty when an extent is below 2r.
std::vector<Vector3> fluidBlockParticles(const AxisAlignedBox& block, Real particleRadius);

/// Boundary particles on the six faces of `box`: the surface points of a lattice with
/// ceil(extent / 2r) intervals per axis (spacing ≤ 2r), each point once.
std::vector<Vector3> containerBoundaryParticles(const AxisAlignedBox& box, Real particleRadius);

/// The boundary particles of one wall as the seed's FluidDemo samples it (addWall):
/// min + (j, k, l) 2r for j < floor(extent_x / 2r) + 1, … (x slowest, z fastest).
std::vector<Vector3> seedWallParticles(const AxisAlignedBox& wall, Real particleRadius);
/// How many particles seedWallParticles makes (each factor capped at 2^30).
long double seedWallParticleCount(const AxisAlignedBox& wall, Real particleRadius);

/// The seed formulation's neighbour order (NeighborhoodSearchSpatialHashing::neighborhoodSearch
/// of PositionBasedDynamics 2.2.2): the seed hashes cells of edge h (the support) with
/// coordinates c(v) = (int)(v · (1/h) + 32768) − 32768 and lists, for the 3 × 3 × 3 cells
/// around the query's cell (x slowest, z fastest), each cell's points in the order they were
/// inserted (fluid particles by index, then boundary particles by index), keeping the first
/// kSeedMaxNeighbours. `candidates` (count `candidateCount`) are the points closer than h in
/// increasing merged index (fluid j, boundary n + b), `positionOf` maps a merged index to its
/// point. Writes the ordered list to `out` and returns its length; `dropped` counts entries
/// past the cap. Cells that the seed's 32-bit cell hash merges are not merged here (their
/// absence is checked for each recording by its driver).
int seedOrderNeighbours(const Vector3& query, Real support, const int* candidates,
                        int candidateCount, const Vector3* fluidPositions, std::size_t fluidCount,
                        const Vector3* boundaryPositions, int* out, std::size_t& dropped);

/// Where a container's boundary particles lie: its faces moved out by r. A block filling the
/// container then has its outer particle centres at r from the faces and 2r from the walls,
/// the fluid's lattice spacing (the seed's FluidDemo starts its fluid 2r from its walls). At r
/// the boundary's density contribution starts the corner particles at ρ ≈ 1.7 ρ₀, and PBF turns
/// that into a blast of ~80 m/s in the first substep (measured; docs/methods.md#fluids).
AxisAlignedBox containerWalls(const AxisAlignedBox& container, Real particleRadius);

/// The fluid of one scene model: boundary particles and their ψ, grids, buffers.
/// `settings` decides the formulation a model does not give (fluidFormulationFor).
Fluid buildFluid(const FluidModelDesc& model, const SimulationSettings& settings);
std::vector<Fluid> buildFluids(const Scene& scene);

/// Neighbour lists on the current (predicted) positions.
void findFluidNeighbours(Fluid& fluid, const ParticleStates& particles);
/// ρ_i of every particle with the current neighbour lists, into fluid.density.
void computeFluidDensities(Fluid& fluid, const ParticleStates& particles);
/// `fluid.iterations` Jacobi iterations of the density constraints.
void solveFluidDensity(Fluid& fluid, ParticleStates& particles);
/// One XSPH pass (densities recomputed at the current positions).
void applyXsphViscosity(Fluid& fluid, ParticleStates& particles);

/// What the steps call in every substep: neighbour search and density iterations of every
/// fluid, after the other position constraints; XSPH after the velocity update.
void solveFluids(std::vector<Fluid>& fluids, ParticleStates& particles);
void applyFluidViscosity(std::vector<Fluid>& fluids, ParticleStates& particles);

}  // namespace pbd
