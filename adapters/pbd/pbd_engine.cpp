#include "adapters/pbd/pbd_engine.h"

#include <cstdio>

#include "pbd/io/number_text.h"
#include "pbd/io/scene_loader.h"

namespace pbdval {
namespace {

std::vector<MethodInfo> pbdMethods() {
  MethodInfo seed;
  seed.name = "pbd";
  seed.engine = "pbd";
  seed.description =
      "PositionBasedDynamics 2.2.2's algorithm: substepped semi-implicit Euler, Gauss-Seidel "
      "joint projection (Deul et al. 2014), velocity-level contacts once per step; solver "
      "settings from the scene's Simulation block (--set subSteps=..., maxIterations=..., "
      "contactModel=seed|corrected)";
  return {seed};
}

}  // namespace

std::vector<std::string> PbdEngine::unsupported(const pbd::Scene& scene,
                                                const Method& /*method*/) const {
  std::vector<std::string> missing;
  for (const pbd::TriangleModelDesc& model : scene.triangleModels)
    if (scene.simulation.clothSimulationMethod != 0)
      missing.push_back(model.jsonPath + ": cloth simulation (clothSimulationMethod " +
                        std::to_string(scene.simulation.clothSimulationMethod) +
                        ") is not implemented yet; set clothSimulationMethod 0 for free particles");
  for (const pbd::TetModelDesc& model : scene.tetModels)
    if (scene.simulation.solidSimulationMethod != 0)
      missing.push_back(model.jsonPath + ": deformable solids (solidSimulationMethod " +
                        std::to_string(scene.simulation.solidSimulationMethod) +
                        ") are not implemented yet; set solidSimulationMethod 0 for free particles");
  return missing;
}

void PbdEngine::load(const pbd::Scene& scene, const Method& /*method*/) {
  world_.emplace(pbd::buildWorld(scene, options_.gridCacheFolder));
  bodyIds_.clear();
  for (const pbd::RigidBodyDesc& body : scene.rigidBodies) bodyIds_.push_back(body.id);
}

void PbdEngine::step() { world_->step(); }

void PbdEngine::read(State& state) const {
  const pbd::World& w = *world_;
  state.time = static_cast<double>(w.time);
  state.bodies.resize(bodyIds_.size());
  for (std::size_t i = 0; i < bodyIds_.size(); ++i) {
    const pbd::SceneFrameState s = w.sceneFrameState(i);
    state.bodies[i] = {bodyIds_[i], s.centerOfMass, s.rotation, s.velocity, s.angularVelocity};
  }
  const pbd::ParticleStates& p = w.bodies.particles;
  state.particles.resize(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) state.particles[i] = {p.position[i], p.velocity[i]};
}

RunFacts PbdEngine::runFacts() const {
  RunFacts facts;
  facts.engineVersion = "pbdval PBD library (PositionBasedDynamics 2.2.2 algorithm)";
  facts.integratorStepsPerSceneStep = world_->settings.subSteps;
  facts.contactMargin = 0;  // contacts are generated within contactTolerance but pushed apart
  return facts;
}

std::map<std::string, std::string> PbdEngine::effectiveSettings() const {
  const pbd::SimulationSettings& s = world_->settings;
  const auto number = [](pbd::Real v) { return pbd::formatReal(double(v)); };
  return {{"timeStepSize", number(s.timeStepSize)},
          {"subSteps", std::to_string(s.subSteps)},
          {"maxIterations", std::to_string(s.maxIterations)},
          {"maxIterationsV", std::to_string(s.maxIterationsV)},
          {"velocityUpdateMethod", std::to_string(s.velocityUpdateMethod)},
          {"contactTolerance", number(s.contactTolerance)},
          {"contactStiffnessRigidBody", number(s.contactStiffnessRigidBody)},
          {"contactStiffnessParticleRigidBody", number(s.contactStiffnessParticleRigidBody)},
          {"contactModel", pbd::contactModelName(s.contactModel)},
          {"contactCombineRule", pbd::contactCombineRuleName(s.contactCombineRule)},
          {"precision", sizeof(pbd::Real) == 8 ? "double" : "float"}};
}

std::optional<std::string> PbdEngine::stateHash() const {
  char buffer[17];
  std::snprintf(buffer, sizeof buffer, "%016llx",
                static_cast<unsigned long long>(world_->stateHash()));
  return std::string(buffer);
}

EngineEntry pbdEngineEntry() {
  EngineEntry entry;
  entry.name = "pbd";
  entry.defaultMethod = "pbd";
  entry.methods = pbdMethods();
  entry.honouredSettings = pbd::simulationSettingKeys();
  entry.make = [](const EngineOptions& options) {
    return std::unique_ptr<Engine>(new PbdEngine(options));
  };
  return entry;
}

}  // namespace pbdval
