#include "pbd/fluids/fluid_model.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "pbd/constraints/fluid_density.h"
#include "pbd/fluids/fluid_lattice.h"

namespace pbd {
namespace {

FluidSamples samplesOf(const Fluid& fluid, const ParticleStates& particles) {
  FluidSamples s;
  s.positions = particles.position.data() + fluid.firstParticle;
  s.particleMass = fluid.particleMass;
  s.boundaryPositions = fluid.boundaryPositions.data();
  s.boundaryPsi = fluid.boundaryPsi.data();
  return s;
}

FluidNeighbourhood neighbourhoodOf(const Fluid& fluid, std::size_t i) {
  return {fluid.fluidNeighbours.begin(i), fluid.fluidNeighbours.count(i),
          fluid.boundaryNeighbours.begin(i), fluid.boundaryNeighbours.count(i)};
}

}  // namespace

std::array<long long, 3> fluidBlockLatticeSize(const AxisAlignedBox& block, Real particleRadius) {
  std::array<long long, 3> n{};
  for (int a = 0; a < 3; ++a) {
    const double cells = double(block.max(a) - block.min(a)) / double(2 * particleRadius);
    n[std::size_t(a)] =
        cells > 0 ? (long long)(std::min(std::floor(cells * (1 + kLatticeSlack)), 1073741824.0))
                  : 0;
  }
  return n;
}

std::vector<Vector3> fluidBlockParticles(const AxisAlignedBox& block, Real particleRadius) {
  const Real spacing = 2 * particleRadius;
  const std::array<long long, 3> n = fluidBlockLatticeSize(block, particleRadius);
  std::vector<Vector3> points;
  points.reserve(std::size_t(n[0]) * std::size_t(n[1]) * std::size_t(n[2]));
  for (long long i = 0; i < n[0]; ++i)
    for (long long j = 0; j < n[1]; ++j)
      for (long long k = 0; k < n[2]; ++k)
        points.push_back(block.min + Vector3::Constant(particleRadius) +
                         spacing * Vector3(Real(i), Real(j), Real(k)));
  return points;
}

std::vector<Vector3> containerBoundaryParticles(const AxisAlignedBox& box, Real particleRadius) {
  const Real spacing = 2 * particleRadius;
  int n[3];
  Vector3 step;
  for (int a = 0; a < 3; ++a) {
    const Real extent = box.max(a) - box.min(a);
    n[a] = std::max(1, int(std::ceil(double(extent / spacing) * (1 - kLatticeSlack))));
    step(a) = extent / Real(n[a]);
  }
  std::vector<Vector3> points;
  for (int i = 0; i <= n[0]; ++i)
    for (int j = 0; j <= n[1]; ++j)
      for (int k = 0; k <= n[2]; ++k) {
        const bool surface = i == 0 || i == n[0] || j == 0 || j == n[1] || k == 0 || k == n[2];
        if (!surface) continue;
        // The far faces exactly at max (not min + n·step, which may differ by rounding).
        const Vector3 p(i == n[0] ? box.max.x() : box.min.x() + Real(i) * step.x(),
                        j == n[1] ? box.max.y() : box.min.y() + Real(j) * step.y(),
                        k == n[2] ? box.max.z() : box.min.z() + Real(k) * step.z());
        points.push_back(p);
      }
  return points;
}

AxisAlignedBox containerWalls(const AxisAlignedBox& container, Real particleRadius) {
  const Vector3 r = Vector3::Constant(particleRadius);
  return {container.min - r, container.max + r};
}

Fluid buildFluid(const FluidModelDesc& model) {
  Fluid fluid;
  fluid.firstParticle = model.firstParticle;
  fluid.particleCount = model.particleCount;
  fluid.particleMass = model.particleMass();
  fluid.restDensity = model.density0;
  fluid.viscosity = model.viscosity;
  fluid.iterations = model.iterations;
  const Real support = 4 * model.particleRadius;  // the seed's support radius
  fluid.kernel = CubicSplineKernel(support);
  if (model.container)
    fluid.boundaryPositions = containerBoundaryParticles(
        containerWalls(*model.container, model.particleRadius), model.particleRadius);

  const std::size_t boundaryCount = fluid.boundaryPositions.size();
  fluid.boundaryGrid = NeighbourSearch(support, boundaryCount);
  fluid.boundaryGrid.index(fluid.boundaryPositions.data(), boundaryCount);
  NeighbourLists boundaryLists(boundaryCount, kMaxFluidNeighbours);
  fluid.boundaryGrid.query(fluid.boundaryPositions.data(), boundaryCount, true, boundaryLists);
  if (boundaryLists.dropped > 0)
    throw std::logic_error(model.jsonPath +
                           ": a boundary particle has more neighbours than the list capacity");
  fluid.boundaryPsi.resize(boundaryCount);
  for (std::size_t b = 0; b < boundaryCount; ++b)
    fluid.boundaryPsi[b] =
        model.density0 *
        akinciBoundaryVolume(fluid.boundaryPositions[b], fluid.boundaryPositions.data(),
                             boundaryLists.begin(b), boundaryLists.count(b), fluid.kernel);

  const auto n = std::size_t(model.particleCount);
  fluid.fluidGrid = NeighbourSearch(support, n);
  fluid.fluidNeighbours = NeighbourLists(n, kMaxFluidNeighbours);
  fluid.boundaryNeighbours = NeighbourLists(n, kMaxFluidNeighbours);
  fluid.density.assign(n, 0);
  fluid.lambda.assign(n, 0);
  fluid.delta.assign(n, Vector3::Zero());
  return fluid;
}

std::vector<Fluid> buildFluids(const Scene& scene) {
  std::vector<Fluid> fluids;
  fluids.reserve(scene.fluidModels.size());
  for (const FluidModelDesc& model : scene.fluidModels)
    fluids.push_back(buildFluid(model));
  return fluids;
}

void findFluidNeighbours(Fluid& fluid, const ParticleStates& particles) {
  const Vector3* x = particles.position.data() + fluid.firstParticle;
  const auto n = std::size_t(fluid.particleCount);
  fluid.fluidGrid.index(x, n);
  fluid.fluidGrid.query(x, n, /*skipSameIndex=*/true, fluid.fluidNeighbours);
  fluid.boundaryGrid.query(x, n, /*skipSameIndex=*/false, fluid.boundaryNeighbours);
  fluid.droppedNeighbours += fluid.fluidNeighbours.dropped + fluid.boundaryNeighbours.dropped;
}

void computeFluidDensities(Fluid& fluid, const ParticleStates& particles) {
  const FluidSamples samples = samplesOf(fluid, particles);
  for (std::size_t i = 0; i < std::size_t(fluid.particleCount); ++i)
    fluid.density[i] = pbfDensity(i, samples, neighbourhoodOf(fluid, i), fluid.kernel);
}

void solveFluidDensity(Fluid& fluid, ParticleStates& particles) {
  const auto n = std::size_t(fluid.particleCount);
  Vector3* x = particles.position.data() + fluid.firstParticle;
  const FluidSamples samples = samplesOf(fluid, particles);
  for (int iteration = 0; iteration < fluid.iterations; ++iteration) {
    for (std::size_t i = 0; i < n; ++i) {
      const FluidNeighbourhood neighbours = neighbourhoodOf(fluid, i);
      fluid.density[i] = pbfDensity(i, samples, neighbours, fluid.kernel);
      fluid.lambda[i] = pbfLambda(i, pbfConstraint(fluid.density[i], fluid.restDensity), samples,
                                  neighbours, fluid.kernel, fluid.restDensity, kPbfEpsilon);
    }
    for (std::size_t i = 0; i < n; ++i)
      fluid.delta[i] = pbfCorrection(i, fluid.lambda.data(), samples, neighbourhoodOf(fluid, i),
                                     fluid.kernel, fluid.restDensity);
    for (std::size_t i = 0; i < n; ++i)
      x[i] += fluid.delta[i];
  }
}

void applyXsphViscosity(Fluid& fluid, ParticleStates& particles) {
  if (!(fluid.viscosity != 0)) return;
  computeFluidDensities(fluid, particles);
  const auto n = std::size_t(fluid.particleCount);
  Vector3* v = particles.velocity.data() + fluid.firstParticle;
  const FluidSamples samples = samplesOf(fluid, particles);
  for (std::size_t i = 0; i < n; ++i)
    fluid.delta[i] = xsphVelocityChange(i, v, fluid.density.data(), samples,
                                        neighbourhoodOf(fluid, i), fluid.kernel, fluid.viscosity);
  for (std::size_t i = 0; i < n; ++i)
    v[i] += fluid.delta[i];
}

void solveFluids(std::vector<Fluid>& fluids, ParticleStates& particles) {
  for (Fluid& fluid : fluids) {
    findFluidNeighbours(fluid, particles);
    solveFluidDensity(fluid, particles);
  }
}

void applyFluidViscosity(std::vector<Fluid>& fluids, ParticleStates& particles) {
  for (Fluid& fluid : fluids)
    applyXsphViscosity(fluid, particles);
}

}  // namespace pbd
