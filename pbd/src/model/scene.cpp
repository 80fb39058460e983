#include "pbd/model/scene.h"

#include <algorithm>
#include <cmath>

namespace pbd {

const char* jointBlockName(JointType type) {
  switch (type) {
    case JointType::Ball:
      return "BallJoints";
    case JointType::BallOnLine:
      return "BallOnLineJoints";
    case JointType::Hinge:
      return "HingeJoints";
    case JointType::Universal:
      return "UniversalJoints";
    case JointType::Slider:
      return "SliderJoints";
    case JointType::RigidBodyParticleBall:
      return "RigidBodyParticleBallJoints";
    case JointType::RigidBodySpring:
      return "RigidBodySprings";
    case JointType::Distance:
      return "DistanceJoints";
    case JointType::Damper:
      return "DamperJoints";
    case JointType::TargetAngleMotorHinge:
      return "TargetAngleMotorHingeJoints";
    case JointType::TargetVelocityMotorHinge:
      return "TargetVelocityMotorHingeJoints";
    case JointType::TargetPositionMotorSlider:
      return "TargetPositionMotorSliderJoints";
    case JointType::TargetVelocityMotorSlider:
      return "TargetVelocityMotorSliderJoints";
    case JointType::StiffRod:
      return "CosseratJoints";
  }
  return "?";
}

const char* jointTypeName(JointType type) {
  switch (type) {
    case JointType::Ball:
      return "ball";
    case JointType::BallOnLine:
      return "ball_on_line";
    case JointType::Hinge:
      return "hinge";
    case JointType::Universal:
      return "universal";
    case JointType::Slider:
      return "slider";
    case JointType::RigidBodyParticleBall:
      return "rigid_body_particle_ball";
    case JointType::RigidBodySpring:
      return "rigid_body_spring";
    case JointType::Distance:
      return "distance";
    case JointType::Damper:
      return "damper";
    case JointType::TargetAngleMotorHinge:
      return "target_angle_motor_hinge";
    case JointType::TargetVelocityMotorHinge:
      return "target_velocity_motor_hinge";
    case JointType::TargetPositionMotorSlider:
      return "target_position_motor_slider";
    case JointType::TargetVelocityMotorSlider:
      return "target_velocity_motor_slider";
    case JointType::StiffRod:
      return "stiff_rod";
  }
  return "?";
}

Real MotorTarget::valueAt(Real time) const {
  if (times.empty()) return constant;
  Real t = time;
  const Real first = times.front();
  const Real period = times.back() - first;
  if (repeat && period > 0 && t > first) t = first + std::fmod(t - first, period);
  if (t <= first) return values.front();
  if (t >= times.back()) return values.back();
  // times is strictly increasing (checked by the loader): find the bracketing samples.
  const auto upper = std::upper_bound(times.begin(), times.end(), t);
  const auto i = static_cast<std::size_t>(upper - times.begin());
  const Real s = (t - times[i - 1]) / (times[i] - times[i - 1]);
  return values[i - 1] + s * (values[i] - values[i - 1]);
}

Real MotorTarget::seedValueAt(Real time) const {
  if (times.empty() || time < 0) return constant;
  Real t = time;
  const Real duration = times.back() - times.front();
  if ((repeatGiven ? repeat : true) && duration > 0)
    while (t > duration)
      t -= duration;
  std::size_t index = 0;
  while (index < times.size() && times[index] <= t)
    ++index;
  if (index == times.size()) return values.back();
  if (index == 0) return values.front();  // before the first sample (the seed reads out of range)
  const Real alpha = (t - times[index - 1]) / (times[index] - times[index - 1]);
  return (Real(1) - alpha) * values[index - 1] + alpha * values[index];
}

const char* contactCombineRuleName(ContactCombineRule rule) {
  switch (rule) {
    case ContactCombineRule::Seed:
      return "seed";
    case ContactCombineRule::Product:
      return "product";
    case ContactCombineRule::Average:
      return "average";
    case ContactCombineRule::Min:
      return "min";
    case ContactCombineRule::Max:
      return "max";
  }
  return "?";
}

const char* stepMethodName(StepMethod method) {
  switch (method) {
    case StepMethod::Seed:
      return "seed";
    case StepMethod::Xpbd:
      return "xpbd";
  }
  return "?";
}

const char* jointDirectionsName(JointDirections directions) {
  switch (directions) {
    case JointDirections::Start:
      return "start";
    case JointDirections::Predicted:
      return "predicted";
  }
  return "?";
}

Real clothStiffnessFor(const SimulationSettings& settings) {
  if (settings.cloth_stiffness) return *settings.cloth_stiffness;
  return settings.clothSimulationMethod == 4 ? Real(1e5) : Real(1);
}

Real clothBendingStiffnessFor(const SimulationSettings& settings) {
  if (settings.cloth_bendingStiffness) return *settings.cloth_bendingStiffness;
  return settings.clothBendingMethod == 3 ? Real(100) : Real(0.01);
}

Real solidStiffnessFor(const SimulationSettings& settings) {
  if (settings.solid_stiffness) return *settings.solid_stiffness;
  if (settings.solidSimulationMethod == 3) return Real(1e6);
  return settings.solidSimulationMethod == 6 ? Real(1e5) : Real(1);
}

Real solidVolumeStiffnessFor(const SimulationSettings& settings) {
  if (settings.solid_volumeStiffness) return *settings.solid_volumeStiffness;
  return settings.solidSimulationMethod == 6 ? Real(1e5) : Real(1);
}

const char* fluidFormulationName(FluidFormulation formulation) {
  return formulation == FluidFormulation::Seed ? "seed" : "symmetric";
}

const char* jointModelName(JointModel model) {
  return model == JointModel::Seed ? "seed" : "corrected";
}

JointModel jointModelFor(const SimulationSettings& settings) {
  if (settings.jointModel) return *settings.jointModel;
  return settings.stepMethod == StepMethod::Xpbd ? JointModel::Corrected : JointModel::Seed;
}

FluidFormulation fluidFormulationFor(const FluidModelDesc& model,
                                     const SimulationSettings& settings) {
  if (model.formulation) return *model.formulation;
  return settings.stepMethod == StepMethod::Xpbd ? FluidFormulation::Symmetric
                                                 : FluidFormulation::Seed;
}

const char* contactGeometryName(ContactGeometry geometry) {
  return geometry == ContactGeometry::Samples ? "samples" : "primitives";
}

ContactGeometry contactGeometryFor(const SimulationSettings& settings) {
  // `pbd` keeps the seed's samples; `pbd.xpbd` finds the pairs that have one in closed form
  // (docs/contacts.md#primitive-contacts).
  if (settings.contactGeometry) return *settings.contactGeometry;
  return settings.stepMethod == StepMethod::Xpbd ? ContactGeometry::Primitives
                                                 : ContactGeometry::Samples;
}

Real femCutoffFor(const SimulationSettings& settings) {
  if (settings.femCutoff) return *settings.femCutoff;
  return settings.stepMethod == StepMethod::Xpbd ? Real(0) : kSeedFemCutoff;
}

GridInterpolation distanceGridFor(const SimulationSettings& settings) {
  if (settings.distanceGrid) return *settings.distanceGrid;
  return settings.stepMethod == StepMethod::Xpbd ? GridInterpolation::CatmullRom
                                                 : GridInterpolation::CubicLagrange;
}

const char* contactModelName(ContactModel model) {
  switch (model) {
    case ContactModel::Seed:
      return "seed";
    case ContactModel::Corrected:
      return "corrected";
  }
  return "?";
}

ContactMaterial combineMaterials(ContactCombineRule rule, const ContactMaterial& a,
                                 const ContactMaterial& b) {
  switch (rule) {
    case ContactCombineRule::Seed:
      return {a.friction + b.friction, a.restitution * b.restitution};
    case ContactCombineRule::Product:
      return {a.friction * b.friction, a.restitution * b.restitution};
    case ContactCombineRule::Average:
      return {(a.friction + b.friction) / 2, (a.restitution + b.restitution) / 2};
    case ContactCombineRule::Min:
      return {std::min(a.friction, b.friction), std::min(a.restitution, b.restitution)};
    case ContactCombineRule::Max:
      return {std::max(a.friction, b.friction), std::max(a.restitution, b.restitution)};
  }
  return {};
}

ContactMaterial Scene::pairMaterial(int bodyA, int bodyB) const {
  const RigidBodyDesc& a = rigidBodies[static_cast<std::size_t>(bodyA)];
  const RigidBodyDesc& b = rigidBodies[static_cast<std::size_t>(bodyB)];
  ContactMaterial m = combineMaterials(simulation.contactCombineRule, {a.friction, a.restitution},
                                       {b.friction, b.restitution});
  for (const ContactPairDesc& pair : contactPairs) {
    if (!((pair.body1 == bodyA && pair.body2 == bodyB) ||
          (pair.body1 == bodyB && pair.body2 == bodyA)))
      continue;
    if (pair.hasFriction) m.friction = pair.friction;
    if (pair.hasRestitution) m.restitution = pair.restitution;
  }
  return m;
}

ContactMaterial Scene::particleMaterial(int particle, int body) const {
  // A particle outside every model (a scene built in code) takes the models' defaults.
  ContactMaterial model{Real(0.2), Real(0.1)};
  bool found = false;
  auto owns = [particle](int first, std::size_t count) {
    return particle >= first && particle < first + static_cast<int>(count);
  };
  for (const TriangleModelDesc& m : triangleModels) {
    if (found || !owns(m.firstParticle, m.mesh.vertices.size())) continue;
    model = {m.friction, m.restitution};
    found = true;
  }
  for (const TetModelDesc& m : tetModels) {
    if (found || !owns(m.firstParticle, m.mesh.vertices.size())) continue;
    model = {m.friction, m.restitution};
    found = true;
  }
  const RigidBodyDesc& b = rigidBodies[static_cast<std::size_t>(body)];
  return combineMaterials(simulation.contactCombineRule, model, {b.friction, b.restitution});
}

int Scene::bodyIndexById(int id) const {
  for (std::size_t i = 0; i < rigidBodies.size(); ++i)
    if (rigidBodies[i].id == id) return static_cast<int>(i);
  return -1;
}

}  // namespace pbd
