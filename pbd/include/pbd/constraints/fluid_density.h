// Position-based fluids: the density constraint of every fluid particle and XSPH viscosity
// (Macklin & Müller 2013, "Position Based Fluids", §3–§6; boundary particles after Akinci et
// al. 2012, "Versatile rigid-fluid coupling for incompressible SPH").
//
// Density of fluid particle i (m the particle mass, ψ_b = ρ₀ V_b a boundary particle's
// "mass"; the sums run over the fluid neighbours j and the boundary neighbours b, i itself in
// the first sum through W(0)):
//   ρ_i = Σ_j m W(x_i − x_j) + Σ_b ψ_b W(x_i − x_b)
// Constraint, clamped to compression only (the seed's choice; no tensile instability, so no
// s_corr term):
//   C_i = max(ρ_i / ρ₀ − 1, 0)
// Gradients (where C_i > 0):
//   ∇_{x_j} C_i = −(m / ρ₀) ∇W(x_i − x_j)                 (j ≠ i a fluid neighbour)
//   ∇_{x_i} C_i =  (1 / ρ₀) [Σ_j m ∇W(x_i − x_j) + Σ_b ψ_b ∇W(x_i − x_b)]
// Multiplier (ε = 1e-6 regularises an empty neighbourhood; boundary particles do not move, but
// their terms |ψ_b/ρ₀ ∇W|² enter the denominator as in the seed):
//   λ_i = −C_i / (Σ_j |∇_{x_j} C_i|² + Σ_b |(ψ_b/ρ₀) ∇W(x_i − x_b)|² + |∇_{x_i} C_i|² + ε)
// Correction (Jacobi: all λ first, then all Δx), equal masses so no inverse-mass weights:
//   Δx_i = (1 / ρ₀) [Σ_j (λ_i + λ_j) m ∇W(x_i − x_j) + Σ_b λ_i ψ_b ∇W(x_i − x_b)]
// Σ_i m Δx_i over the fluid terms is zero (∇W is odd, the pair weight λ_i + λ_j symmetric):
// the fluid–fluid part conserves linear momentum; the boundary terms are the walls' push.
//
// XSPH viscosity (Schechter & Bridson 2012 form used by the paper's eq. 17), after the velocity
// update, Jacobi:
//   Δv_i = c Σ_j m (v_j − v_i) W(x_i − x_j) · 2 / (ρ_i + ρ_j)
// Difference from the seed: the seed weighs the pair by m / ρ_j, which is not symmetric in i
// and j, so Σ m Δv ≠ 0 when densities differ; the symmetric 2 / (ρ_i + ρ_j) conserves linear
// momentum exactly and equals m / ρ at uniform density.
//
// The seed's other choices kept: ρ₀ = 1000, particle mass 0.8 (2r)³ ρ₀ (the lattice of
// spacing 2r starts under-dense and settles), support 4r, 5 Jacobi iterations, ε = 1e-6.
// Akinci's boundary volume: V_b = 1 / Σ_k W(x_b − x_k) over the boundary particles k (b
// included), ψ_b = ρ₀ V_b.
//
// Pure functions: positions and neighbour lists in, values out; nothing allocates.
#pragma once

#include <cstddef>

#include "pbd/fluids/sph_kernels.h"
#include "pbd/math/types.h"

namespace pbd {

/// The particles the sums run over.
struct FluidSamples {
  const Vector3* positions = nullptr;  ///< the fluid's particles
  Real particleMass = 0;
  const Vector3* boundaryPositions = nullptr;
  const Real* boundaryPsi = nullptr;  ///< ψ_b = ρ₀ V_b
};

/// One fluid particle's neighbours: indices into FluidSamples::positions (itself excluded) and
/// into the boundary arrays.
struct FluidNeighbourhood {
  const int* fluid = nullptr;
  int fluidCount = 0;
  const int* boundary = nullptr;
  int boundaryCount = 0;
};

/// ρ_i (the particle's own m W(0) included).
Real pbfDensity(std::size_t i, const FluidSamples& samples, const FluidNeighbourhood& neighbours,
                const CubicSplineKernel& kernel);

/// C = max(ρ / ρ₀ − 1, 0).
Real pbfConstraint(Real density, Real restDensity);

/// ∇_{x_i} C_i (the unclamped expression; C_i's gradient where C_i > 0).
Vector3 pbfGradientOwn(std::size_t i, const FluidSamples& samples,
                       const FluidNeighbourhood& neighbours, const CubicSplineKernel& kernel,
                       Real restDensity);

/// ∇_{x_j} C_i = −(m / ρ₀) ∇W(x_i − x_j) for a fluid neighbour j.
Vector3 pbfGradientNeighbour(const Vector3& xi, const Vector3& xj, Real particleMass,
                             Real restDensity, const CubicSplineKernel& kernel);

/// λ_i for the constraint value `constraint` (= C_i); 0 when C_i = 0.
Real pbfLambda(std::size_t i, Real constraint, const FluidSamples& samples,
               const FluidNeighbourhood& neighbours, const CubicSplineKernel& kernel,
               Real restDensity, Real epsilon);

/// Δx_i from the multipliers of all fluid particles.
Vector3 pbfCorrection(std::size_t i, const Real* lambdas, const FluidSamples& samples,
                      const FluidNeighbourhood& neighbours, const CubicSplineKernel& kernel,
                      Real restDensity);

/// Δv_i of XSPH viscosity with coefficient `viscosity` (fluid neighbours only).
Vector3 xsphVelocityChange(std::size_t i, const Vector3* velocities, const Real* densities,
                           const FluidSamples& samples, const FluidNeighbourhood& neighbours,
                           const CubicSplineKernel& kernel, Real viscosity);

/// Akinci's V_b = 1 / (W(0) + Σ_k W(x_b − x_k)) over the boundary neighbours k of b.
Real akinciBoundaryVolume(const Vector3& xb, const Vector3* boundaryPositions,
                          const int* neighbours, int neighbourCount,
                          const CubicSplineKernel& kernel);

}  // namespace pbd
