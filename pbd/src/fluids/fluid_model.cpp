#include "pbd/fluids/fluid_model.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "pbd/constraints/fluid_density.h"
#include "pbd/constraints/seed_fluid_density.h"
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

SeedFluidSamples seedSamplesOf(const Fluid& fluid, const ParticleStates& particles) {
  SeedFluidSamples s;
  s.positions = particles.position.data() + fluid.firstParticle;
  s.particleCount = std::size_t(fluid.particleCount);
  s.particleMass = fluid.particleMass;
  s.boundaryPositions = fluid.boundaryPositions.data();
  s.boundaryPsi = fluid.boundaryPsi.data();
  s.restDensity = fluid.restDensity;
  return s;
}

/// The seed's NeighborhoodSearchSpatialHashing::floor of v · factor.
int seedCell(Real v, Real factor) {
  return int(v * factor + Real(32768.f)) - 32768;
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

std::vector<Vector3> seedWallParticles(const AxisAlignedBox& wall, Real particleRadius) {
  const Real distance = Real(2.0) * particleRadius;
  const Vector3 diff = wall.max - wall.min;
  unsigned steps[3];
  for (int a = 0; a < 3; ++a)
    steps[a] = unsigned(diff(a) / distance) + 1u;
  std::vector<Vector3> points;
  points.reserve(std::size_t(steps[0]) * steps[1] * steps[2]);
  for (unsigned j = 0; j < steps[0]; ++j)
    for (unsigned k = 0; k < steps[1]; ++k)
      for (unsigned l = 0; l < steps[2]; ++l)
        points.push_back(wall.min +
                         Vector3(Real(j) * distance, Real(k) * distance, Real(l) * distance));
  return points;
}

long double seedWallParticleCount(const AxisAlignedBox& wall, Real particleRadius) {
  const Real distance = Real(2.0) * particleRadius;
  long double count = 1;
  for (int a = 0; a < 3; ++a)
    count *= std::min(std::floor((long double)((wall.max(a) - wall.min(a)) / distance)) + 1,
                      1073741824.0L);
  return count;
}

int seedOrderNeighbours(const Vector3& query, Real support, const int* candidates,
                        int candidateCount, const Vector3* fluidPositions, std::size_t fluidCount,
                        const Vector3* boundaryPositions, int* out, std::size_t& dropped) {
  const Real factor = Real(1.0) / support;
  const int cx = seedCell(query.x(), factor), cy = seedCell(query.y(), factor),
            cz = seedCell(query.z(), factor);
  int keys[2 * kMaxFluidNeighbours];
  int n = 0;
  for (int c = 0; c < candidateCount; ++c) {
    const auto j = std::size_t(candidates[c]);
    const Vector3& p = j < fluidCount ? fluidPositions[j] : boundaryPositions[j - fluidCount];
    const int dx = seedCell(p.x(), factor) - cx, dy = seedCell(p.y(), factor) - cy,
              dz = seedCell(p.z(), factor) - cz;
    if (std::abs(dx) > 1 || std::abs(dy) > 1 || std::abs(dz) > 1) continue;  // not searched
    const int key = (dx + 1) * 9 + (dy + 1) * 3 + (dz + 1);
    // Stable insertion by cell: within a cell the candidates keep their increasing order.
    int position = n;
    while (position > 0 && keys[position - 1] > key)
      --position;
    for (int m = n; m > position; --m) {
      keys[m] = keys[m - 1];
      out[m] = out[m - 1];
    }
    keys[position] = key;
    out[position] = candidates[c];
    ++n;
  }
  if (n > kSeedMaxNeighbours) {
    dropped += std::size_t(n - kSeedMaxNeighbours);
    n = kSeedMaxNeighbours;
  }
  return n;
}

AxisAlignedBox containerWalls(const AxisAlignedBox& container, Real particleRadius) {
  const Vector3 r = Vector3::Constant(particleRadius);
  return {container.min - r, container.max + r};
}

Fluid buildFluid(const FluidModelDesc& model, const SimulationSettings& settings) {
  Fluid fluid;
  fluid.firstParticle = model.firstParticle;
  fluid.particleCount = model.particleCount;
  fluid.particleMass = model.particleMass();
  fluid.restDensity = model.density0;
  fluid.viscosity = model.viscosity;
  fluid.iterations = model.iterations;
  const Real support = 4 * model.particleRadius;  // the seed's support radius
  fluid.kernel = CubicSplineKernel(support);
  fluid.seedKernel = SeedCubicKernel(support);
  fluid.formulation = fluidFormulationFor(model, settings);
  if (model.container)
    fluid.boundaryPositions = containerBoundaryParticles(
        containerWalls(*model.container, model.particleRadius), model.particleRadius);
  for (const AxisAlignedBox& wall : model.boundaryWalls) {
    const std::vector<Vector3> points = seedWallParticles(wall, model.particleRadius);
    fluid.boundaryPositions.insert(fluid.boundaryPositions.end(), points.begin(), points.end());
  }

  const std::size_t boundaryCount = fluid.boundaryPositions.size();
  fluid.boundaryGrid = NeighbourSearch(support, boundaryCount);
  fluid.boundaryGrid.index(fluid.boundaryPositions.data(), boundaryCount);
  NeighbourLists boundaryLists(boundaryCount, kMaxFluidNeighbours);
  fluid.boundaryGrid.query(fluid.boundaryPositions.data(), boundaryCount, true, boundaryLists);
  if (boundaryLists.dropped > 0)
    throw std::logic_error(model.jsonPath +
                           ": a boundary particle has more neighbours than the list capacity");
  fluid.boundaryPsi.resize(boundaryCount);
  if (fluid.formulation == FluidFormulation::Seed) {
    // The seed's ψ: its own search over the boundary particles, in its order, capped at 60.
    int ordered[2 * kMaxFluidNeighbours];
    std::size_t dropped = 0;
    for (std::size_t b = 0; b < boundaryCount; ++b) {
      const int count = seedOrderNeighbours(
          fluid.boundaryPositions[b], support, boundaryLists.begin(b), boundaryLists.count(b),
          fluid.boundaryPositions.data(), boundaryCount, nullptr, ordered, dropped);
      fluid.boundaryPsi[b] =
          seedBoundaryPsi(fluid.boundaryPositions[b], fluid.boundaryPositions.data(), ordered,
                          count, fluid.seedKernel, model.density0);
    }
  } else {
    for (std::size_t b = 0; b < boundaryCount; ++b)
      fluid.boundaryPsi[b] =
          model.density0 *
          akinciBoundaryVolume(fluid.boundaryPositions[b], fluid.boundaryPositions.data(),
                               boundaryLists.begin(b), boundaryLists.count(b), fluid.kernel);
  }

  const auto n = std::size_t(model.particleCount);
  fluid.fluidGrid = NeighbourSearch(support, n);
  fluid.fluidNeighbours = NeighbourLists(n, kMaxFluidNeighbours);
  fluid.boundaryNeighbours = NeighbourLists(n, kMaxFluidNeighbours);
  if (fluid.formulation == FluidFormulation::Seed)
    fluid.seedNeighbours = NeighbourLists(n, 2 * kMaxFluidNeighbours);
  fluid.density.assign(n, 0);
  fluid.lambda.assign(n, 0);
  fluid.delta.assign(n, Vector3::Zero());
  return fluid;
}

std::vector<Fluid> buildFluids(const Scene& scene) {
  std::vector<Fluid> fluids;
  fluids.reserve(scene.fluidModels.size());
  for (const FluidModelDesc& model : scene.fluidModels)
    fluids.push_back(buildFluid(model, scene.simulation));
  return fluids;
}

void findFluidNeighbours(Fluid& fluid, const ParticleStates& particles) {
  const Vector3* x = particles.position.data() + fluid.firstParticle;
  const auto n = std::size_t(fluid.particleCount);
  fluid.fluidGrid.index(x, n);
  fluid.fluidGrid.query(x, n, /*skipSameIndex=*/true, fluid.fluidNeighbours);
  fluid.boundaryGrid.query(x, n, /*skipSameIndex=*/false, fluid.boundaryNeighbours);
  fluid.droppedNeighbours += fluid.fluidNeighbours.dropped + fluid.boundaryNeighbours.dropped;
  if (fluid.formulation != FluidFormulation::Seed) return;
  // The seed's mixed lists: fluid candidates (by index), then boundary ones as n + b.
  const Vector3* boundary = fluid.boundaryPositions.data();
  for (std::size_t i = 0; i < n; ++i) {
    int candidates[2 * kMaxFluidNeighbours];
    int count = 0;
    for (int k = 0; k < fluid.fluidNeighbours.count(i); ++k)
      candidates[count++] = fluid.fluidNeighbours.begin(i)[k];
    for (int k = 0; k < fluid.boundaryNeighbours.count(i); ++k)
      candidates[count++] = int(n) + fluid.boundaryNeighbours.begin(i)[k];
    int* list = fluid.seedNeighbours.indices.data() + i * fluid.seedNeighbours.capacity;
    fluid.seedNeighbours.counts[i] =
        seedOrderNeighbours(x[i], fluid.kernel.supportRadius(), candidates, count, x, n, boundary,
                            list, fluid.droppedNeighbours);
  }
}

void computeFluidDensities(Fluid& fluid, const ParticleStates& particles) {
  const FluidSamples samples = samplesOf(fluid, particles);
  for (std::size_t i = 0; i < std::size_t(fluid.particleCount); ++i)
    fluid.density[i] = pbfDensity(i, samples, neighbourhoodOf(fluid, i), fluid.kernel);
}

void solveFluidDensity(Fluid& fluid, ParticleStates& particles) {
  const auto n = std::size_t(fluid.particleCount);
  Vector3* x = particles.position.data() + fluid.firstParticle;
  if (fluid.formulation == FluidFormulation::Seed) {
    const SeedFluidSamples samples = seedSamplesOf(fluid, particles);
    const NeighbourLists& lists = fluid.seedNeighbours;
    for (int iteration = 0; iteration < fluid.iterations; ++iteration) {
      for (std::size_t i = 0; i < n; ++i) {
        fluid.density[i] =
            seedPbfDensity(i, samples, lists.begin(i), lists.count(i), fluid.seedKernel);
        fluid.lambda[i] = seedPbfLambda(i, fluid.density[i], samples, lists.begin(i),
                                        lists.count(i), fluid.seedKernel);
      }
      for (std::size_t i = 0; i < n; ++i)
        fluid.delta[i] = seedPbfCorrection(i, fluid.lambda.data(), samples, lists.begin(i),
                                           lists.count(i), fluid.seedKernel);
      for (std::size_t i = 0; i < n; ++i)
        x[i] += fluid.delta[i];
    }
    return;
  }
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
  if (fluid.formulation == FluidFormulation::Seed) {
    // In place, with the densities of the last density iteration (the seed's order).
    const SeedFluidSamples samples = seedSamplesOf(fluid, particles);
    Vector3* v = particles.velocity.data() + fluid.firstParticle;
    const NeighbourLists& lists = fluid.seedNeighbours;
    for (std::size_t i = 0; i < std::size_t(fluid.particleCount); ++i)
      seedXsphViscosity(i, v, fluid.density.data(), samples, lists.begin(i), lists.count(i),
                        fluid.seedKernel, fluid.viscosity);
    return;
  }
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
