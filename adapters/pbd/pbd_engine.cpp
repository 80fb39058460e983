#include "adapters/pbd/pbd_engine.h"

#include <cmath>
#include <cstdio>
#include <utility>

namespace pbdval {
namespace {

// Method parameters that override a Simulation setting, with the valid range.
struct SettingOverride {
  const char* name;
  const char* description;
  int pbd::SimulationSettings::*field;
  int minimum;
  int maximum;
};
constexpr SettingOverride kIntegerOverrides[] = {
    {"subSteps", "substeps per step", &pbd::SimulationSettings::subSteps, 1, 1 << 20},
    {"maxIterations", "position iterations per substep", &pbd::SimulationSettings::maxIterations,
     1, 1 << 20},
    {"maxIterationsV", "velocity iterations per step", &pbd::SimulationSettings::maxIterationsV,
     0, 1 << 20},
    {"velocityUpdateMethod", "0 first order, 1 second order (the seed's BDF2 variant)",
     &pbd::SimulationSettings::velocityUpdateMethod, 0, 1},
};

std::vector<MethodInfo> pbdMethods() {
  MethodInfo seed;
  seed.name = "pbd";
  seed.engine = "pbd";
  seed.description =
      "PositionBasedDynamics 2.2.2's algorithm: substepped semi-implicit Euler, Gauss-Seidel "
      "joint projection (Deul et al. 2014), velocity-level contacts once per step";
  for (const SettingOverride& o : kIntegerOverrides)
    seed.parameters.push_back({o.name, "scene", std::string(o.description) + " (default: the scene's value)"});
  seed.parameters.push_back({"contactModel", "scene",
                             "seed (PositionBasedDynamics 2.2.2, flaws included) or corrected "
                             "(restitution threshold, Coulomb cone on the accumulated friction "
                             "impulse; docs/contacts.md) (default: the scene's value)"});
  MethodInfo xpbd;
  xpbd.name = "pbd.xpbd";
  xpbd.engine = "pbd";
  xpbd.description =
      "XPBD rigid bodies (Mueller et al. 2020): substeps with one position iteration each, "
      "compliant joints, position-level contacts with static friction, dynamic friction and "
      "restitution in a velocity pass (docs/methods.md)";
  xpbd.parameters.push_back({"substeps", "20", "substeps per step, integer in [1, 1048576]"});
  xpbd.parameters.push_back(
      {"jointLinearCompliance", "0", "m/N, >= 0: point, axis and distance rows of joints"});
  xpbd.parameters.push_back(
      {"jointAngularCompliance", "0", "rad/(N m), >= 0: rotation rows of joints"});
  xpbd.parameters.push_back({"contactCompliance", "0", "m/N, >= 0: contact normal rows"});
  xpbd.parameters.push_back({"speculativeMargin", "2",
                             ">= 0: contacts are collected within contactTolerance + margin h "
                             "(fastest point speed)"});
  return {seed, xpbd};
}

/// The pbd.xpbd parameters into settings.xpbd (each must be present: the registry fills in
/// the defaults).
void applyXpbdParameters(const Method& method, pbd::SimulationSettings& settings) {
  settings.stepMethod = pbd::StepMethod::Xpbd;
  const double substeps = method.number("substeps");
  if (substeps != std::floor(substeps) || substeps < 1 || substeps > (1 << 20))
    throw std::invalid_argument("method " + method.name +
                                ": substeps must be an integer in [1, 1048576], got '" +
                                method.text("substeps") + "'");
  settings.xpbd.substeps = static_cast<int>(substeps);
  const std::pair<const char*, pbd::Real pbd::XpbdSettings::*> nonNegative[] = {
      {"jointLinearCompliance", &pbd::XpbdSettings::jointLinearCompliance},
      {"jointAngularCompliance", &pbd::XpbdSettings::jointAngularCompliance},
      {"contactCompliance", &pbd::XpbdSettings::contactCompliance},
      {"speculativeMargin", &pbd::XpbdSettings::speculativeMargin}};
  for (const auto& [name, field] : nonNegative) {
    const double value = method.number(name);
    if (!(value >= 0) || !std::isfinite(value))
      throw std::invalid_argument("method " + method.name + ": " + name +
                                  " must be a finite number >= 0, got '" + method.text(name) +
                                  "'");
    settings.xpbd.*field = static_cast<pbd::Real>(value);
  }
}

}  // namespace

pbd::SimulationSettings pbdSettingsFor(const pbd::Scene& scene, const Method& method) {
  pbd::SimulationSettings settings = scene.simulation;
  for (const SettingOverride& o : kIntegerOverrides) {
    const auto it = method.parameters.find(o.name);
    if (it == method.parameters.end() || it->second == "scene") continue;
    const double value = method.number(o.name);
    if (value != std::floor(value) || value < o.minimum || value > o.maximum)
      throw std::invalid_argument("method " + method.name + ": " + o.name + " must be an integer in [" +
                                  std::to_string(o.minimum) + ", " + std::to_string(o.maximum) +
                                  "], got '" + it->second + "'");
    settings.*(o.field) = static_cast<int>(value);
  }
  const auto model = method.parameters.find("contactModel");
  if (model != method.parameters.end() && model->second != "scene") {
    if (model->second == pbd::contactModelName(pbd::ContactModel::Seed))
      settings.contactModel = pbd::ContactModel::Seed;
    else if (model->second == pbd::contactModelName(pbd::ContactModel::Corrected))
      settings.contactModel = pbd::ContactModel::Corrected;
    else
      throw std::invalid_argument("method " + method.name +
                                  ": contactModel must be 'seed', 'corrected' or 'scene', got '" +
                                  model->second + "'");
  }
  if (method.name == "pbd.xpbd") applyXpbdParameters(method, settings);
  return settings;
}

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

void PbdEngine::load(const pbd::Scene& scene, const Method& method) {
  pbd::Scene configured = scene;
  configured.simulation = pbdSettingsFor(scene, method);
  world_.emplace(pbd::buildWorld(configured));
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

std::map<std::string, std::string> PbdEngine::effectiveSettings() const {
  const pbd::SimulationSettings& s = world_->settings;
  auto number = [](double v) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.17g", v);
    return std::string(buffer);
  };
  return {{"timeStepSize", number(s.timeStepSize)},
          // The substeps actually taken (the runner derives the integration step from it).
          {"subSteps", std::to_string(s.stepMethod == pbd::StepMethod::Xpbd ? s.xpbd.substeps
                                                                             : s.subSteps)},
          {"maxIterations", std::to_string(s.maxIterations)},
          {"maxIterationsV", std::to_string(s.maxIterationsV)},
          {"velocityUpdateMethod", std::to_string(s.velocityUpdateMethod)},
          {"contactTolerance", number(s.contactTolerance)},
          {"contactStiffnessRigidBody", number(s.contactStiffnessRigidBody)},
          {"contactStiffnessParticleRigidBody", number(s.contactStiffnessParticleRigidBody)},
          {"contactModel", pbd::contactModelName(s.contactModel)},
          {"contactCombineRule", pbd::contactCombineRuleName(s.contactCombineRule)},
          {"stepMethod", pbd::stepMethodName(s.stepMethod)},
          {"xpbd.jointLinearCompliance", number(s.xpbd.jointLinearCompliance)},
          {"xpbd.jointAngularCompliance", number(s.xpbd.jointAngularCompliance)},
          {"xpbd.contactCompliance", number(s.xpbd.contactCompliance)},
          {"xpbd.speculativeMargin", number(s.xpbd.speculativeMargin)},
          {"precision", sizeof(pbd::Real) == 8 ? "double" : "float"}};
}

std::optional<std::string> PbdEngine::stateHash() const {
  char buffer[17];
  std::snprintf(buffer, sizeof buffer, "%016llx",
                static_cast<unsigned long long>(world_->stateHash()));
  return std::string(buffer);
}

EngineEntry pbdEngineEntry() {
  return {"pbd", "pbd", &pbdMethods, [] { return std::unique_ptr<Engine>(new PbdEngine()); }};
}

}  // namespace pbdval
