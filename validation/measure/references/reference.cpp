// The analytic reference models by name (docs/references.md).
#include "validation/measure/references/reference.h"

#include <functional>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "validation/measure/mechanics.h"
#include "validation/measure/references/analytic_model.h"
#include "validation/measure/references/ballistic.h"
#include "validation/measure/references/bouncing_ball.h"
#include "validation/measure/references/contact_motion.h"
#include "validation/measure/references/harmonic_oscillator.h"
#include "validation/measure/references/pendulum.h"
#include "validation/measure/references/torque_free.h"

namespace pbdval {

namespace {

using Factory =
    std::function<std::unique_ptr<AnalyticModel>(const ModelContext&, const ReferenceParameters&)>;

struct ModelEntry {
  const char* name;
  const char* summary;
  std::vector<std::string> parameters;
  Factory make;
};

template <typename Model, typename... Extra>
Factory factory(Extra... extra) {
  return [=](const ModelContext& context, const ReferenceParameters& parameters) {
    return std::unique_ptr<AnalyticModel>(std::make_unique<Model>(context, parameters, extra...));
  };
}

const std::vector<ModelEntry>& registry() {
  static const std::vector<ModelEntry> entries = {
      {"projectile",
       "centre of mass on the parabola x0 + v0 t + g t^2/2 (or the semi-implicit Euler closed "
       "form)",
       {"form"},
       factory<BallisticModel>()},
      {"free_fall",
       "the projectile model (a body released from its initial state)",
       {"form"},
       factory<BallisticModel>()},
      {"pendulum",
       "physical pendulum about a fixed axis (RK4 trajectory, elliptic-integral period)",
       {"body", "pivot", "axis", "rk4Step"},
       factory<PendulumModel>(false)},
      {"simple_pendulum",
       "point-mass pendulum about a fixed axis (the body's own inertia ignored)",
       {"body", "pivot", "axis", "rk4Step"},
       factory<PendulumModel>(true)},
      {"harmonic_oscillator",
       "a body on a RigidBodySpring or DamperJoint to a static body: s(t) closed form",
       {"joint", "body"},
       factory<HarmonicOscillatorModel>()},
      {"torque_free_symmetric",
       "free axisymmetric body: closed-form precession, ballistic centre of mass",
       {"symmetryTolerance"},
       factory<SymmetricTorqueFreeModel>()},
      {"torque_free_asymmetric",
       "free asymmetric body: ballistic centre of mass; rotation only RK4-integrated on request "
       "(check energy and angular momentum)",
       {"integrateRotation", "rk4Step"},
       factory<AsymmetricTorqueFreeModel>()},
      {"sliding_block",
       "block on an incline with Coulomb friction: a = g (sin - mu cos) or stick",
       {"body", "ground", "normal", "friction"},
       factory<PlaneContactModel>(PlaneContactModel::Kind::Block)},
      {"rolling_sphere",
       "sphere on an incline: slides, then rolls at a = g sin / (1 + I/(m r^2)) (5/7 g sin)",
       {"body", "ground", "normal", "friction", "radius"},
       factory<PlaneContactModel>(PlaneContactModel::Kind::Sphere)},
      {"bowling_ball",
       "sphere on a level plane from sliding to rolling (Drake's benchmark)",
       {"body", "ground", "normal", "friction", "radius"},
       factory<PlaneContactModel>(PlaneContactModel::Kind::BowlingBall)},
      {"bouncing_ball",
       "ball bouncing on a level plane: apex heights e^(2k) h0",
       {"body", "ground", "normal", "restitution", "contactHeight", "radius"},
       factory<BouncingBallModel>()},
  };
  return entries;
}

const ModelEntry& findModel(const std::string& name) {
  for (const ModelEntry& entry : registry())
    if (name == entry.name) return entry;
  std::string known;
  for (const ModelEntry& entry : registry())
    known += (known.empty() ? "" : ", ") + std::string(entry.name);
  throw std::invalid_argument("analytic reference '" + name + "': unknown model (known: " + known +
                              ")");
}

void checkTimes(const std::string& model, const std::vector<double>& times) {
  for (std::size_t i = 0; i < times.size(); ++i) {
    if (!(times[i] >= 0) || (i > 0 && !(times[i] >= times[i - 1]))) {
      std::ostringstream message;
      message << "analytic reference '" << model << "': sample time " << i << " (" << times[i]
              << " s) is negative or earlier than the one before";
      throw std::invalid_argument(message.str());
    }
  }
}

}  // namespace

ReferenceTrajectory buildAnalyticReference(const pbd::Scene& scene, const ReferenceSpec& spec,
                                           const std::vector<double>& times,
                                           double integrationStep) {
  const ModelEntry& entry = findModel(spec.model);
  checkTimes(spec.model, times);
  const ReferenceParameters parameters(spec.model, spec.parametersJson, entry.parameters);
  const ModelContext context{&scene, &spec, integrationStep};
  const std::unique_ptr<AnalyticModel> model = entry.make(context, parameters);

  ReferenceTrajectory reference;
  reference.description = "analytic " + spec.model + ": " + model->description();
  reference.hasRotation = model->hasRotation();
  reference.bodies.assign(scene.rigidBodies.size(), false);
  for (const int body : model->bodies())
    reference.bodies[static_cast<std::size_t>(body)] = true;
  const State start = initialState(scene);
  reference.samples.reserve(times.size());
  for (const double t : times) {
    State state = start;
    state.time = t;
    model->evaluate(state);
    reference.samples.push_back(std::move(state));
  }
  return reference;
}

std::vector<std::pair<std::string, std::string>> analyticReferenceModels() {
  std::vector<std::pair<std::string, std::string>> out;
  for (const ModelEntry& entry : registry())
    out.emplace_back(entry.name, entry.summary);
  return out;
}

}  // namespace pbdval
