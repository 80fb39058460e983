// The seed formulation of a position-based fluid (FluidFormulation::Seed): the density
// constraint, its multiplier and correction, XSPH and Akinci's boundary volume computed as the
// seed's FluidDemo computes them (PositionBasedDynamics/PositionBasedFluids.cpp,
// Demos/FluidDemo/TimeStepFluidModel.cpp and FluidModel.cpp of PositionBasedDynamics 2.2.2),
// operation for operation, so that pbdval follows the original to round-off. The mathematics
// is that of constraints/fluid_density.h; what differs is the arithmetic and two choices:
//
// - One neighbour list per particle, fluid and boundary particles mixed: entries j < n are
//   fluid particles, j ≥ n the boundary particle j − n, in the seed's spatial-hash order
//   (seedOrderNeighbours in fluids/fluid_model.h). Sums run in list order.
// - ∇_{x_j} C_i = (−m / ρ₀) ∇W and Δx_i = −Σ_j (λ_i + λ_j) ∇_{x_j} C_i − Σ_b λ_i ∇_{x_b} C_i
//   (the seed's factorisation; fluid_density.h factors 1/ρ₀ out of the sum).
// - XSPH in place (a Gauss–Seidel sweep: particle i sees the already updated velocities of
//   the particles before it), weighted by m/ρ_j, with the densities of the last density
//   iteration (before its correction):
//     v_i ← v_i − c (m / ρ_j) (v_i − v_j) W(x_i − x_j)   for each fluid neighbour j in order.
//   This does not conserve momentum (docs/methods.md#fluids: the symmetric formulation does).
//
// The kernel is the seed's (SeedCubicKernel, sph_kernels.h). Pure functions; nothing allocates.
#pragma once

#include <cstddef>

#include "pbd/fluids/sph_kernels.h"
#include "pbd/math/types.h"

namespace pbd {

/// The seed formulation's view of a fluid: n particles, the boundary, one mixed list each.
struct SeedFluidSamples {
  const Vector3* positions = nullptr;
  std::size_t particleCount = 0;  ///< n: list entries ≥ n are boundary particles
  Real particleMass = 0;
  const Vector3* boundaryPositions = nullptr;
  const Real* boundaryPsi = nullptr;
  Real restDensity = 1000;
};

/// ρ_i (PositionBasedFluids::computePBFDensity).
Real seedPbfDensity(std::size_t i, const SeedFluidSamples& samples, const int* neighbours,
                    int neighbourCount, const SeedCubicKernel& kernel);
/// λ_i for the density ρ_i (PositionBasedFluids::computePBFLagrangeMultiplier, ε = 1e-6).
Real seedPbfLambda(std::size_t i, Real density, const SeedFluidSamples& samples,
                   const int* neighbours, int neighbourCount, const SeedCubicKernel& kernel);
/// Δx_i (PositionBasedFluids::solveDensityConstraint).
Vector3 seedPbfCorrection(std::size_t i, const Real* lambdas, const SeedFluidSamples& samples,
                          const int* neighbours, int neighbourCount, const SeedCubicKernel& kernel);
/// The XSPH sweep of TimeStepFluidModel::computeXSPHViscosity over particle i: updates
/// velocities[i] in place.
void seedXsphViscosity(std::size_t i, Vector3* velocities, const Real* densities,
                       const SeedFluidSamples& samples, const int* neighbours, int neighbourCount,
                       const SeedCubicKernel& kernel, Real viscosity);
/// ψ_b = ρ₀ / (W(0) + Σ_k W(x_b − x_k)) over b's boundary neighbours in list order
/// (FluidModel::initModel).
Real seedBoundaryPsi(const Vector3& xb, const Vector3* boundaryPositions, const int* neighbours,
                     int neighbourCount, const SeedCubicKernel& kernel, Real restDensity);

}  // namespace pbd
