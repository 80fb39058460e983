#include "pbd/constraints/fluid_density.h"

#include <algorithm>

namespace pbd {

Real pbfDensity(std::size_t i, const FluidSamples& samples, const FluidNeighbourhood& neighbours,
                const CubicSplineKernel& kernel) {
  const Vector3& xi = samples.positions[i];
  Real density = samples.particleMass * kernel.valueAtZero();
  for (int n = 0; n < neighbours.fluidCount; ++n)
    density += samples.particleMass *
               kernel.value(xi - samples.positions[std::size_t(neighbours.fluid[n])]);
  for (int n = 0; n < neighbours.boundaryCount; ++n) {
    const auto b = std::size_t(neighbours.boundary[n]);
    density += samples.boundaryPsi[b] * kernel.value(xi - samples.boundaryPositions[b]);
  }
  return density;
}

Real pbfConstraint(Real density, Real restDensity) {
  return std::max(density / restDensity - 1, Real(0));
}

Vector3 pbfGradientOwn(std::size_t i, const FluidSamples& samples,
                       const FluidNeighbourhood& neighbours, const CubicSplineKernel& kernel,
                       Real restDensity) {
  const Vector3& xi = samples.positions[i];
  Vector3 sum = Vector3::Zero();
  for (int n = 0; n < neighbours.fluidCount; ++n)
    sum += samples.particleMass *
           kernel.gradient(xi - samples.positions[std::size_t(neighbours.fluid[n])]);
  for (int n = 0; n < neighbours.boundaryCount; ++n) {
    const auto b = std::size_t(neighbours.boundary[n]);
    sum += samples.boundaryPsi[b] * kernel.gradient(xi - samples.boundaryPositions[b]);
  }
  return sum / restDensity;
}

Vector3 pbfGradientNeighbour(const Vector3& xi, const Vector3& xj, Real particleMass,
                             Real restDensity, const CubicSplineKernel& kernel) {
  return (-particleMass / restDensity) * kernel.gradient(xi - xj);
}

Real pbfLambda(std::size_t i, Real constraint, const FluidSamples& samples,
               const FluidNeighbourhood& neighbours, const CubicSplineKernel& kernel,
               Real restDensity, Real epsilon) {
  if (!(constraint > 0)) return 0;
  const Vector3& xi = samples.positions[i];
  Vector3 own = Vector3::Zero();
  Real sumOfSquares = 0;
  for (int n = 0; n < neighbours.fluidCount; ++n) {
    const Vector3 g = pbfGradientNeighbour(xi, samples.positions[std::size_t(neighbours.fluid[n])],
                                           samples.particleMass, restDensity, kernel);
    sumOfSquares += g.squaredNorm();
    own -= g;
  }
  for (int n = 0; n < neighbours.boundaryCount; ++n) {
    const auto b = std::size_t(neighbours.boundary[n]);
    const Vector3 g = (-samples.boundaryPsi[b] / restDensity) *
                      kernel.gradient(xi - samples.boundaryPositions[b]);
    sumOfSquares += g.squaredNorm();
    own -= g;
  }
  sumOfSquares += own.squaredNorm();
  return -constraint / (sumOfSquares + epsilon);
}

Vector3 pbfCorrection(std::size_t i, const Real* lambdas, const FluidSamples& samples,
                      const FluidNeighbourhood& neighbours, const CubicSplineKernel& kernel,
                      Real restDensity) {
  const Vector3& xi = samples.positions[i];
  Vector3 sum = Vector3::Zero();
  for (int n = 0; n < neighbours.fluidCount; ++n) {
    const auto j = std::size_t(neighbours.fluid[n]);
    sum += ((lambdas[i] + lambdas[j]) * samples.particleMass) *
           kernel.gradient(xi - samples.positions[j]);
  }
  for (int n = 0; n < neighbours.boundaryCount; ++n) {
    const auto b = std::size_t(neighbours.boundary[n]);
    sum +=
        (lambdas[i] * samples.boundaryPsi[b]) * kernel.gradient(xi - samples.boundaryPositions[b]);
  }
  return sum / restDensity;
}

Vector3 xsphVelocityChange(std::size_t i, const Vector3* velocities, const Real* densities,
                           const FluidSamples& samples, const FluidNeighbourhood& neighbours,
                           const CubicSplineKernel& kernel, Real viscosity) {
  const Vector3& xi = samples.positions[i];
  Vector3 sum = Vector3::Zero();
  for (int n = 0; n < neighbours.fluidCount; ++n) {
    const auto j = std::size_t(neighbours.fluid[n]);
    const Real weight = samples.particleMass * kernel.value(xi - samples.positions[j]) * 2 /
                        (densities[i] + densities[j]);
    sum += weight * (velocities[j] - velocities[i]);
  }
  return viscosity * sum;
}

Real akinciBoundaryVolume(const Vector3& xb, const Vector3* boundaryPositions,
                          const int* neighbours, int neighbourCount,
                          const CubicSplineKernel& kernel) {
  Real sum = kernel.valueAtZero();
  for (int n = 0; n < neighbourCount; ++n)
    sum += kernel.value(xb - boundaryPositions[std::size_t(neighbours[n])]);
  return 1 / sum;
}

}  // namespace pbd
