#include "pbd/constraints/seed_fluid_density.h"

#include <algorithm>

namespace pbd {
namespace {

/// The seed's ε in the denominator of λ.
constexpr Real kSeedEpsilon = Real(1.0e-6);

}  // namespace

Real seedPbfDensity(std::size_t i, const SeedFluidSamples& samples, const int* neighbours,
                    int neighbourCount, const SeedCubicKernel& kernel) {
  const Vector3& xi = samples.positions[i];
  Real density = samples.particleMass * kernel.valueAtZero();
  for (int n = 0; n < neighbourCount; ++n) {
    const auto j = std::size_t(neighbours[n]);
    if (j < samples.particleCount)
      density += samples.particleMass * kernel.value(xi - samples.positions[j]);
    else
      density += samples.boundaryPsi[j - samples.particleCount] *
                 kernel.value(xi - samples.boundaryPositions[j - samples.particleCount]);
  }
  return density;
}

Real seedPbfLambda(std::size_t i, Real density, const SeedFluidSamples& samples,
                   const int* neighbours, int neighbourCount, const SeedCubicKernel& kernel) {
  const Real rho0 = samples.restDensity;
  const Real constraint = std::max(density / rho0 - Real(1.0), Real(0.0));
  if (constraint == 0) return 0;
  const Vector3& xi = samples.positions[i];
  Real sumOfSquares = 0;
  Vector3 own(0, 0, 0);
  for (int n = 0; n < neighbourCount; ++n) {
    const auto j = std::size_t(neighbours[n]);
    Vector3 gradient;
    if (j < samples.particleCount) {
      gradient = -samples.particleMass / rho0 * kernel.gradient(xi - samples.positions[j]);
    } else {
      const std::size_t b = j - samples.particleCount;
      gradient =
          -samples.boundaryPsi[b] / rho0 * kernel.gradient(xi - samples.boundaryPositions[b]);
    }
    sumOfSquares += gradient.squaredNorm();
    own -= gradient;
  }
  sumOfSquares += own.squaredNorm();
  return -constraint / (sumOfSquares + kSeedEpsilon);
}

Vector3 seedPbfCorrection(std::size_t i, const Real* lambdas, const SeedFluidSamples& samples,
                          const int* neighbours, int neighbourCount,
                          const SeedCubicKernel& kernel) {
  const Real rho0 = samples.restDensity;
  const Vector3& xi = samples.positions[i];
  Vector3 correction = Vector3::Zero();
  for (int n = 0; n < neighbourCount; ++n) {
    const auto j = std::size_t(neighbours[n]);
    if (j < samples.particleCount) {
      const Vector3 gradient =
          -samples.particleMass / rho0 * kernel.gradient(xi - samples.positions[j]);
      correction -= (lambdas[i] + lambdas[j]) * gradient;
    } else {
      const std::size_t b = j - samples.particleCount;
      const Vector3 gradient =
          -samples.boundaryPsi[b] / rho0 * kernel.gradient(xi - samples.boundaryPositions[b]);
      correction -= (lambdas[i]) * gradient;
    }
  }
  return correction;
}

void seedXsphViscosity(std::size_t i, Vector3* velocities, const Real* densities,
                       const SeedFluidSamples& samples, const int* neighbours, int neighbourCount,
                       const SeedCubicKernel& kernel, Real viscosity) {
  const Vector3& xi = samples.positions[i];
  Vector3& vi = velocities[i];
  for (int n = 0; n < neighbourCount; ++n) {
    const auto j = std::size_t(neighbours[n]);
    if (j >= samples.particleCount) continue;  // the seed's boundary term is commented out
    const Vector3& vj = velocities[j];
    vi -= viscosity * (samples.particleMass / densities[j]) * (vi - vj) *
          kernel.value(xi - samples.positions[j]);
  }
}

Real seedBoundaryPsi(const Vector3& xb, const Vector3* boundaryPositions, const int* neighbours,
                     int neighbourCount, const SeedCubicKernel& kernel, Real restDensity) {
  Real delta = kernel.valueAtZero();
  for (int n = 0; n < neighbourCount; ++n)
    delta += kernel.value(xb - boundaryPositions[std::size_t(neighbours[n])]);
  const Real volume = Real(1.0) / delta;
  return restDensity * volume;
}

}  // namespace pbd
