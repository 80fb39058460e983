#include "adapters/pbd/pbd_engine.h"

#include <algorithm>
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
  // Both methods: the collision detection's threads (results are bitwise the same for any count).
  const ParameterSpec threads = integerParameter(
      "threads", 1, 1, 64,
      "threads of the collision detection's narrow phase (results bitwise equal for any count)");
  seed.parameters = {threads};
  MethodInfo xpbd;
  xpbd.name = "pbd.xpbd";
  xpbd.engine = "pbd";
  xpbd.description =
      "XPBD rigid bodies (Mueller et al. 2020): substeps with one position iteration each, "
      "compliant joints, position-level contacts with static friction, dynamic friction and "
      "restitution in a velocity pass (docs/methods.md)";
  const pbd::XpbdSettings defaults;
  xpbd.parameters = {
      integerParameter("substeps", defaults.substeps, 1, pbd::kMaxSubSteps,
                       "substeps per step, one position iteration each"),
      realParameter("jointLinearCompliance", double(defaults.jointLinearCompliance), 0, 1e6, "m/N",
                    "compliance of the point, axis and distance rows of joints"),
      realParameter("jointAngularCompliance", double(defaults.jointAngularCompliance), 0, 1e6,
                    "rad/(N m)", "compliance of the rotation rows of joints"),
      realParameter("contactCompliance", double(defaults.contactCompliance), 0, 1e6, "m/N",
                    "compliance of the contact normal rows"),
      realParameter("speculativeMargin", double(defaults.speculativeMargin), 0, 1e3, "",
                    "contacts are collected within contactTolerance + margin x h x (fastest "
                    "point speed)"),
      realParameter("jointLinearDamping", double(defaults.jointLinearDamping), 0, 1e6, "1/s",
                    "joint damping of the anchors' relative velocity (Mueller et al. 2020, 3.6)"),
      realParameter("jointAngularDamping", double(defaults.jointAngularDamping), 0, 1e6, "1/s",
                    "joint damping of the relative angular velocity"),
      choiceParameter("jointDirections", pbd::jointDirectionsName(defaults.jointDirections),
                      {pbd::jointDirectionsName(pbd::JointDirections::Start),
                       pbd::jointDirectionsName(pbd::JointDirections::Predicted)},
                      "joints' constraint directions (Jacobians): start = of the substep's start "
                      "(SHAKE), predicted = of the current poses (PBD/XPBD)"),
      integerParameter("jointIterations", defaults.jointIterations, 1, 1000,
                       "Gauss-Seidel sweeps over the joints per substep (lambda continued after "
                       "the first; contacts keep one)"),
      threads,
  };
  return {seed, xpbd};
}

}  // namespace

pbd::SimulationSettings pbdSettingsFor(const pbd::Scene& scene, const Method& method) {
  pbd::SimulationSettings settings = scene.simulation;
  settings.detectionThreads = static_cast<int>(method.integer("threads"));
  if (method.name != "pbd.xpbd") return settings;
  settings.stepMethod = pbd::StepMethod::Xpbd;
  settings.xpbd.substeps = static_cast<int>(method.integer("substeps"));
  settings.xpbd.jointLinearCompliance = pbd::Real(method.real("jointLinearCompliance"));
  settings.xpbd.jointAngularCompliance = pbd::Real(method.real("jointAngularCompliance"));
  settings.xpbd.contactCompliance = pbd::Real(method.real("contactCompliance"));
  settings.xpbd.speculativeMargin = pbd::Real(method.real("speculativeMargin"));
  settings.xpbd.jointLinearDamping = pbd::Real(method.real("jointLinearDamping"));
  settings.xpbd.jointAngularDamping = pbd::Real(method.real("jointAngularDamping"));
  settings.xpbd.jointDirections =
      method.choice("jointDirections") == pbd::jointDirectionsName(pbd::JointDirections::Start)
          ? pbd::JointDirections::Start
          : pbd::JointDirections::Predicted;
  settings.xpbd.jointIterations = static_cast<int>(method.integer("jointIterations"));
  return settings;
}

std::vector<std::string> PbdEngine::unsupported(const pbd::Scene& scene,
                                                const Method& method) const {
  return unsupportedFeatures(pbdFeatures(), scene, method.name);
}

void PbdEngine::load(const pbd::Scene& scene, const Method& method) {
  pbd::Scene configured = scene;
  configured.simulation = pbdSettingsFor(scene, method);
  world_.emplace(pbd::buildWorld(configured, options_.gridCacheFolder));
  bodyIds_.clear();
  for (const pbd::RigidBodyDesc& body : scene.rigidBodies)
    bodyIds_.push_back(body.id);
  motorBodies_.clear();
  for (const pbd::JointDesc& joint : scene.joints) {
    const bool motor = joint.type == pbd::JointType::TargetAngleMotorHinge ||
                       joint.type == pbd::JointType::TargetVelocityMotorHinge ||
                       joint.type == pbd::JointType::TargetPositionMotorSlider ||
                       joint.type == pbd::JointType::TargetVelocityMotorSlider;
    if (!motor) continue;
    for (int body : {joint.body1, joint.body2})
      if (body >= 0 &&
          std::find(motorBodies_.begin(), motorBodies_.end(), body) == motorBodies_.end())
        motorBodies_.push_back(body);
  }
}

void PbdEngine::step() {
  world_->step();
}

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
  for (std::size_t i = 0; i < p.size(); ++i)
    state.particles[i] = {p.position[i], p.velocity[i]};
  const pbd::SegmentStates& r = w.bodies.segments;
  state.segments.resize(r.size());
  for (std::size_t i = 0; i < r.size(); ++i)
    state.segments[i] = {r.rotation[i], r.angularVelocity[i]};
}

RunFacts PbdEngine::runFacts() const {
  RunFacts facts;
  facts.engineVersion = "pbdval PBD library";
  const pbd::SimulationSettings& s = world_->settings;
  facts.integratorStepsPerSceneStep =
      s.stepMethod == pbd::StepMethod::Xpbd ? s.xpbd.substeps : s.subSteps;
  facts.contactMargin = 0;  // contacts are generated within contactTolerance but pushed apart
  if (s.stepMethod != pbd::StepMethod::Xpbd) {
    // The seed's step sets v = (x − x_prev)/h and then applies the contact impulses at the
    // velocity level (restitution, friction, the penetration push): a body resting in contact
    // reports the impulse that cancels the next step's gravity, (1 + e)‖g‖h with e ≤ 1.
    facts.restVelocityAllowance = 2 * double(s.gravitation.norm()) * double(s.timeStepSize);
    facts.restVelocityReason =
        "the seed's velocity pass applies contact impulses after the positions are set: up to "
        "(1 + e) |g| h at rest";
  }
  if (!motorBodies_.empty()) {
    facts.velocityDrivenBodies = motorBodies_;
    facts.velocityDrivenReason =
        "motor joints: a position motor's target moves once per scene step (the driven body's "
        "velocity is its last substep's, the seed's order), and a velocity motor sets the "
        "velocity in the velocity pass after the positions are set";
  }
  return facts;
}

std::map<std::string, std::string> PbdEngine::effectiveSettings() const {
  const pbd::SimulationSettings& s = world_->settings;
  const auto number = [](pbd::Real v) { return pbd::formatReal(double(v)); };
  std::map<std::string, std::string> settings = {
      {"timeStepSize", number(s.timeStepSize)},
      {"subSteps", std::to_string(s.subSteps)},
      {"maxIterations", std::to_string(s.maxIterations)},
      {"maxIterationsV", std::to_string(s.maxIterationsV)},
      {"velocityUpdateMethod", std::to_string(s.velocityUpdateMethod)},
      {"contactTolerance", number(s.contactTolerance)},
      {"contactStiffnessRigidBody", number(s.contactStiffnessRigidBody)},
      {"contactStiffnessParticleRigidBody", number(s.contactStiffnessParticleRigidBody)},
      {"contactModel", pbd::contactModelName(s.contactModel)},
      {"distanceGrid", pbd::gridInterpolationName(pbd::distanceGridFor(s))},
      {"jointModel", pbd::jointModelName(pbd::jointModelFor(s))},
      {"contactGeometry", pbd::contactGeometryName(pbd::contactGeometryFor(s))},
      {"femCutoff", number(pbd::femCutoffFor(s))},
      {"objPrecision", pbd::objPrecisionName(s.objPrecision)},
      {"contactCombineRule", pbd::contactCombineRuleName(s.contactCombineRule)},
      {"jointedBodiesCollide", "yes (the seed's rule: every pair of collision objects)"},
      {"stepMethod", pbd::stepMethodName(s.stepMethod)},
      {"detectionThreads", std::to_string(s.detectionThreads)},
      {"xpbd.substeps", std::to_string(s.xpbd.substeps)},
      {"xpbd.jointLinearCompliance", number(s.xpbd.jointLinearCompliance)},
      {"xpbd.jointAngularCompliance", number(s.xpbd.jointAngularCompliance)},
      {"xpbd.contactCompliance", number(s.xpbd.contactCompliance)},
      {"xpbd.speculativeMargin", number(s.xpbd.speculativeMargin)},
      {"xpbd.jointLinearDamping", number(s.xpbd.jointLinearDamping)},
      {"xpbd.jointAngularDamping", number(s.xpbd.jointAngularDamping)},
      {"xpbd.jointDirections", pbd::jointDirectionsName(s.xpbd.jointDirections)},
      {"xpbd.jointIterations", std::to_string(s.xpbd.jointIterations)},
      {"precision", sizeof(pbd::Real) == 8 ? "double" : "float"}};
  // Each fluid's formulation (fluidFormulationFor: the scene's, else the method's own).
  for (std::size_t f = 0; f < world_->fluids.size(); ++f)
    settings["FluidModels[" + std::to_string(f) + "].formulation"] =
        pbd::fluidFormulationName(world_->fluids[f].formulation);
  return settings;
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
  // Both of the library's methods run on every case: the seed's algorithm and XPBD.
  entry.runMethods = {"pbd", "pbd.xpbd"};
  entry.methods = pbdMethods();
  entry.honouredSettings = pbd::simulationSettingKeys();
  entry.features = pbdFeatures();
  entry.make = [](const EngineOptions& options) {
    return std::unique_ptr<Engine>(new PbdEngine(options));
  };
  return entry;
}

}  // namespace pbdval
