#include "adapters/ode/ode_engine.h"

#include "pbd/io/number_text.h"

#if defined(__SANITIZE_ADDRESS__)
#define PBDVAL_LEAK_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define PBDVAL_LEAK_SANITIZER 1
#endif
#endif
#ifndef PBDVAL_LEAK_SANITIZER
#define PBDVAL_LEAK_SANITIZER 0
#endif
#if PBDVAL_LEAK_SANITIZER
#include <sanitizer/lsan_interface.h>
#endif

namespace pbdval {
namespace {

std::string number(double v) {
  return pbd::formatReal(v);
}

std::string vector(const Vector3& v) {
  return number(v.x()) + " " + number(v.y()) + " " + number(v.z());
}

/// Leaves what `owner` holds to the OS on purpose (see destroyModel) and tells LeakSanitizer
/// so in sanitized builds: the object and everything reachable from it (the ODE world, its
/// bodies, geoms and job queue) are not reported as leaks.
template <typename T>
void abandon(std::unique_ptr<T>& owner) noexcept {
  T* const object = owner.release();
#if PBDVAL_LEAK_SANITIZER
  if (object != nullptr) __lsan_ignore_object(object);
#endif
  (void)object;
}

}  // namespace

OdeEngine::~OdeEngine() {
  destroyModel();
}

void OdeEngine::destroyModel() noexcept {
  if (!world_) return;
  if (!failure_.empty()) {
    // ODE failed inside a call (its error handler threw out of it): the world may be half
    // updated, and destroying it could fail inside ODE again, in a destructor, where an
    // exception ends the process (std::terminate). It is left to the OS instead: a failed run
    // leaks its one world.
    abandon(joints_);
    abandon(world_);
    return;
  }
  try {
    ode::OdeCall call(context_);
    joints_.reset();
    world_.reset();
  } catch (...) {
    // An ODE error while tearing down: nothing is left to recover, and a destructor must not
    // throw. The OS reclaims the memory at exit.
    abandon(joints_);
    abandon(world_);
  }
}

std::vector<std::string> OdeEngine::unsupported(const pbd::Scene& scene,
                                                const Method& method) const {
  return unsupportedFeatures(odeFeatures(), scene, method.name);
}

void OdeEngine::load(const pbd::Scene& scene, const Method& method) {
  destroyModel();
  settings_ = odeSettingsFor(method);
  const std::vector<std::string> missing = unsupported(scene, method);
  if (!missing.empty()) throw EngineError("ode cannot load this scene: " + missing.front());
  methodName_ = method.name;
  scene_ = scene;
  steps_ = 0;
  failure_.clear();
  context_.randomSeed = 0;  // ODE's initial seed: every load starts the same run
  ode::OdeCall call(context_);
  try {
    world_ = std::make_unique<ode::OdeWorld>(scene_, settings_);
    joints_ = std::make_unique<ode::OdeJoints>(*world_, scene_, settings_);
  } catch (const EngineError& e) {
    failure_ = e.what();
    throw;
  }
}

void OdeEngine::step() {
  if (!world_) throw EngineError("ode: step() before a successful load()");
  if (!failure_.empty())
    throw EngineError("ode: the world is unusable after an earlier ODE error (" + failure_ + ")");
  const double h = scene_.simulation.timeStepSize;
  ode::OdeCall call(context_);
  try {
    joints_->prepareStep(double(steps_ + 1) * h, h);
    world_->collide();
    const int stepped = settings_.solver == OdeSettings::Solver::Step
                            ? dWorldStep(world_->id(), h)
                            : dWorldQuickStep(world_->id(), h);
    world_->clearContacts();
    if (stepped == 0) throw EngineError("ODE could not allocate the memory for a step");
    ++steps_;
  } catch (const EngineError& e) {
    failure_ = e.what();
    throw EngineError(failure_ + " (in the step from t = " + number(double(steps_) * h) + " s)");
  }
}

// Reads only this engine's bodies, so it needs no OdeCall.
void OdeEngine::read(State& state) const {
  if (!world_) throw EngineError("ode: read() before a successful load()");
  state.time = double(steps_) * double(scene_.simulation.timeStepSize);
  state.bodies.resize(scene_.rigidBodies.size());
  for (std::size_t i = 0; i < state.bodies.size(); ++i)
    state.bodies[i] = world_->state(int(i));
  state.particles.clear();
}

std::map<std::string, std::string> OdeEngine::effectiveSettings() const {
  const bool quick = settings_.solver == OdeSettings::Solver::QuickStep;
  std::map<std::string, std::string> s = {
      {"method", methodName_},
      {"solver",
       quick ? "dWorldQuickStep (SOR projected Gauss-Seidel)" : "dWorldStep (direct Dantzig LCP)"},
      {"timeStepSize", number(scene_.simulation.timeStepSize)},
      {"stepping", "one ODE step per scene step"},
      {"gravity", vector(scene_.simulation.gravitation)},
      {"erp", number(settings_.erp)},
      {"cfm", number(settings_.cfm)},
      {"contactSoftErp", number(settings_.contactErp)},
      {"contactSoftCfm", number(settings_.contactCfm)},
      {"maxContactsPerPair", std::to_string(settings_.maxContacts)},
      {"friction",
       "Coulomb pyramid (dContactApprox1), fdir1 = world x projected on the contact "
       "plane (world z within 30 degrees of x), mu = Scene::pairMaterial"},
      {"restitution", "bounce = Scene::pairMaterial, bounce_vel 0"},
      {"contactMaxCorrectingVel", number(dInfinity)},
      {"contactSurfaceLayer", "0"},
      {"jointedBodiesCollide", "yes (as in the seed)"},
      {"gyroscopic", settings_.gyroscopic ? "1" : "0"},
      {"finiteRotation", "0 (infinitesimal rotation update)"},
      {"autoDisable", "0"},
      {"linearDamping", "0"},
      {"angularDamping", "0"},
      {"maxAngularSpeed", number(dInfinity)},
      {"auxiliaryBodies", std::to_string(world_ ? world_->auxiliaryBodyCount() : 0)},
      {"precision", "double"},
      {"odeConfiguration", dGetConfiguration()},
  };
  if (quick) {
    s["iterations"] = std::to_string(settings_.iterations);
    s["sor"] = number(settings_.overRelaxation);
  } else {
    s["ballOnLineCarriageMassRatio"] = number(settings_.carriageMassRatio);
  }
  return s;
}

RunFacts OdeEngine::runFacts() const {
  RunFacts facts;
  facts.engineVersion = "ODE 0.16 (double precision)";
  facts.integratorStepsPerSceneStep = 1;
  facts.contactMargin = 0;  // contactSurfaceLayer 0: contacts are corrected to zero depth
  return facts;
}

EngineEntry odeEngineEntry() {
  EngineEntry entry;
  entry.name = "ode";
  entry.defaultMethod = "ode.quickstep";
  entry.methods = odeMethods();
  entry.honouredSettings = {"timeStepSize", "gravitation"};
  entry.features = odeFeatures();
  entry.make = [](const EngineOptions&) { return std::unique_ptr<Engine>(new OdeEngine()); };
  return entry;
}

}  // namespace pbdval
