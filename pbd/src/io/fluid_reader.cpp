// FluidModels[] (pbdval's extension; the seed's fluids are demo-only): position-based fluids
// whose particles fill axis-aligned blocks on a lattice of spacing 2r, optionally in a box
// container whose walls are sampled with boundary particles. The particles are appended to
// Scene::particles after every other particle model (the block is read last of the particle
// blocks). Keys and their checks: docs/scene-format.md#fluidmodels.
#include <string>

#include "pbd/fluids/fluid_lattice.h"
#include "pbd/fluids/fluid_model.h"
#include "pbd/io/scene_loader.h"
#include "scene_reading.h"

namespace pbd::scene_io {
namespace {

/// More particles than this in one model is a mistake in the scene (a block in metres meant in
/// centimetres), not a simulation this library runs.
constexpr std::size_t kMaxFluidParticles = 1000000;
/// The same for the boundary particles of a model's boundaryWalls.
constexpr std::size_t kMaxBoundaryParticles = 10000000;

const char* axisName(int axis) {
  static const char* const names[] = {"x", "y", "z"};
  return names[axis];
}

/// {"min": [..], "max": [..]}: a box has min < max in every component; a wall (flat walls
/// allowed) min ≤ max.
enum class BoxKind { Solid, Wall };

AxisAlignedBox readBox(const JsonValue& value, BoxKind kind = BoxKind::Solid) {
  JsonObject object = value.object();
  AxisAlignedBox box;
  box.min = object.require("min").vector3();
  box.max = object.require("max").vector3();
  const bool wall = kind == BoxKind::Wall;
  for (int a = 0; a < 3; ++a)
    if (!(wall ? box.min(a) <= box.max(a) : box.min(a) < box.max(a)))
      value.error(std::string(wall ? "an inverted wall: min ≤ max is needed in every component, "
                                     "but along "
                                   : "an empty box: min < max is needed in every component, "
                                     "but along ") +
                  axisName(a) + " min = " + formatNumber(double(box.min(a))) +
                  " and max = " + formatNumber(double(box.max(a))));
  object.warnUnknownKeys();
  return box;
}

/// Extension: "symmetric" | "seed".
FluidFormulation fluidFormulation(const JsonValue& value) {
  const std::string name = value.string();
  for (FluidFormulation f : {FluidFormulation::Symmetric, FluidFormulation::Seed})
    if (name == fluidFormulationName(f)) return f;
  value.fail("one of \"symmetric\", \"seed\"");
}

bool contains(const AxisAlignedBox& outer, const AxisAlignedBox& inner) {
  return (inner.min.array() >= outer.min.array()).all() &&
         (inner.max.array() <= outer.max.array()).all();
}

bool overlap(const AxisAlignedBox& a, const AxisAlignedBox& b) {
  return (a.min.array() < b.max.array()).all() && (b.min.array() < a.max.array()).all();
}

KeyTable<FluidModelDesc> fluidKeys() {
  using F = FluidModelDesc;
  return {
      numberKey("particleRadius", &F::particleRadius, positive()),
      numberKey("density0", &F::density0, positive()),
      // XSPH blends a particle's velocity towards its neighbours': c > 1 overshoots.
      numberKey("viscosity", &F::viscosity, between(0, 1)),
      integerKey("iterations", &F::iterations, between(1, kMaxIterations)),
      {"formulation", [](const JsonValue& v, F& f) { f.formulation = fluidFormulation(v); }, false,
       [](const F& f, Json& j) {
         if (f.formulation) writeString(j, "formulation", fluidFormulationName(*f.formulation));
       }},
  };
}

FluidModelDesc readFluidModel(const JsonValue& element, Scene& scene) {
  JsonObject object = element.object();
  FluidModelDesc model;
  model.jsonPath = element.path();
  readKeys(object, fluidKeys(), model);
  if (auto container = object.find("container")) model.container = readBox(*container);

  std::vector<Vector3> positions;
  if (auto listed = object.find("particles")) {
    for (const JsonValue& p : listed->elements("particle positions [x, y, z]"))
      model.particles.push_back(p.vector3());
    if (model.particles.size() > kMaxFluidParticles)
      listed->error("more than " + std::to_string(kMaxFluidParticles) + " particles");
  }
  if (auto walls = object.find("boundaryWalls")) {
    long double boundaryCount = 0;
    for (const JsonValue& wall : walls->elements("walls {\"min\", \"max\"}")) {
      model.boundaryWalls.push_back(readBox(wall, BoxKind::Wall));
      boundaryCount += seedWallParticleCount(model.boundaryWalls.back(), model.particleRadius);
      if (boundaryCount > (long double)kMaxBoundaryParticles)
        wall.error("the walls hold more than " + std::to_string(kMaxBoundaryParticles) +
                   " boundary particles; check the units of the wall and particleRadius");
    }
  }
  // `blocks` may be left out when particles are listed.
  const std::optional<JsonValue> blocks = model.particles.empty()
                                              ? std::optional<JsonValue>(object.require("blocks"))
                                              : object.find("blocks");
  const std::vector<JsonValue> blockValues =
      blocks ? blocks->elements("fluid blocks {\"min\", \"max\"}") : std::vector<JsonValue>{};
  if (blocks && blockValues.empty() && model.particles.empty())
    blocks->fail("at least one block {\"min\", \"max\"} (or listed particles)");
  const Real spacing = 2 * model.particleRadius;
  for (std::size_t i = 0; i < blockValues.size(); ++i) {
    const AxisAlignedBox block = readBox(blockValues[i]);
    for (int a = 0; a < 3; ++a)
      if (double(block.max(a) - block.min(a)) < double(spacing) * (1 - kLatticeSlack))
        blockValues[i].error(std::string("holds no particle: its extent along ") + axisName(a) +
                             " is " + formatNumber(double(block.max(a) - block.min(a))) +
                             ", less than the particle diameter 2 particleRadius = " +
                             formatNumber(double(spacing)));
    if (model.container && !contains(*model.container, block))
      blockValues[i].error("lies outside the container " + formatVector(model.container->min) +
                           " .. " + formatVector(model.container->max) +
                           " (every block must be inside it)");
    for (std::size_t k = 0; k < model.blocks.size(); ++k)
      if (overlap(model.blocks[k], block))
        blockValues[i].error("overlaps " + blockValues[k].path() +
                             " (the particles would sit on top of each other)");
    model.blocks.push_back(block);
    const std::array<long long, 3> lattice = fluidBlockLatticeSize(block, model.particleRadius);
    // Counted before any particle is made (each factor ≤ 2^30: no overflow in long double).
    const long double count =
        (long double)lattice[0] * (long double)lattice[1] * (long double)lattice[2];
    if ((long double)positions.size() + count > (long double)kMaxFluidParticles)
      blockValues[i].error("the model's blocks hold more than " +
                           std::to_string(kMaxFluidParticles) +
                           " particles; check the units of the block and particleRadius");
    const std::vector<Vector3> filled = fluidBlockParticles(block, model.particleRadius);
    positions.insert(positions.end(), filled.begin(), filled.end());
  }
  if ((long double)positions.size() + (long double)model.particles.size() >
      (long double)kMaxFluidParticles)
    element.error("the model holds more than " + std::to_string(kMaxFluidParticles) + " particles");
  positions.insert(positions.end(), model.particles.begin(), model.particles.end());
  object.warnUnknownKeys();

  model.firstParticle = static_cast<int>(scene.particles.size());
  model.particleCount = static_cast<int>(positions.size());
  const Real mass = model.particleMass();
  for (const Vector3& x : positions)
    scene.particles.push_back(ParticleDesc{x, Vector3::Zero(), mass});
  return model;
}

}  // namespace

void readFluidModels(const JsonValue& block, Scene& scene) {
  for (const JsonValue& element : block.elements("fluid-model objects"))
    scene.fluidModels.push_back(readFluidModel(element, scene));
}

KeyTable<FluidModelDesc> fluidModelKeys() {
  return fluidKeys();
}

}  // namespace pbd::scene_io
