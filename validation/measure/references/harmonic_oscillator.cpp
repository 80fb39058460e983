#include "validation/measure/references/harmonic_oscillator.h"

#include <cmath>
#include <sstream>

namespace pbdval {

namespace {

bool isSpringLike(pbd::JointType type) {
  return type == pbd::JointType::RigidBodySpring || type == pbd::JointType::Damper;
}

const pbd::JointDesc& findSpring(const pbd::Scene& scene, const ReferenceParameters& parameters) {
  const std::optional<std::string> path = parameters.text("joint");
  const pbd::JointDesc* found = nullptr;
  int candidates = 0;
  for (const pbd::JointDesc& joint : scene.joints) {
    if (!isSpringLike(joint.type)) continue;
    ++candidates;
    if (path ? joint.jsonPath == *path : candidates == 1) found = &joint;
  }
  if (path && !found)
    parameters.fail("joint", "the JSON path of a RigidBodySprings or DamperJoints entry (no \"" +
                                 *path + "\")");
  if (!path && candidates != 1)
    parameters.fail("joint", "the JSON path of the spring (the scene has " +
                                 std::to_string(candidates) + " spring and damper joints)");
  return *found;
}

/// |component of v perpendicular to the unit u|.
double lateral(const Vector3& v, const Vector3& u) {
  return (v - v.dot(u) * u).norm();
}

}  // namespace

HarmonicOscillatorModel::HarmonicOscillatorModel(const ModelContext& context,
                                                 const ReferenceParameters& parameters) {
  const pbd::Scene& scene = *context.scene;
  const pbd::JointDesc& joint = findSpring(scene, parameters);
  jointPath_ = joint.jsonPath;
  const bool firstStatic = !bodyAt(scene, joint.body1).isDynamic;
  const bool secondStatic = !bodyAt(scene, joint.body2).isDynamic;
  if (joint.type == pbd::JointType::Damper ? (!firstStatic || secondStatic)
                                           : firstStatic == secondStatic)
    parameters.failModel(jointPath_ + ": needs " +
                         (joint.type == pbd::JointType::Damper
                              ? std::string("a static first body and a dynamic second body")
                              : std::string("one static and one dynamic body")));
  body_ = firstStatic ? joint.body2 : joint.body1;
  const pbd::RigidBodyDesc& desc = bodyAt(scene, body_);
  if (const std::optional<int> id = parameters.integer("body"); id && *id != desc.id)
    parameters.fail("body", "the dynamic end of " + jointPath_);

  const Vector3 g = scene.simulation.gravitation;
  const Vector3 v0 = desc.velocity;
  if (joint.type == pbd::JointType::Damper) {
    direction_ = joint.axis.normalized();
  } else {
    const Vector3 staticEnd = firstStatic ? joint.position1 : joint.position2;
    const Vector3 movingEnd = firstStatic ? joint.position2 : joint.position1;
    const double restLength = (movingEnd - staticEnd).norm();
    if (!(restLength > 0)) parameters.failModel(jointPath_ + ": rest length 0");
    direction_ = (movingEnd - staticEnd) / restLength;
    if (lateral(g, direction_) > 1e-9 * (1 + g.norm()))
      parameters.failModel(jointPath_ + ": gravity is not along the spring");
    const Vector3 arm = movingEnd - desc.initialCenterOfMass();
    if (lateral(arm, direction_) > 1e-9 * (1 + arm.norm()))
      parameters.failModel(jointPath_ + ": the connector is off the line through " + desc.jsonPath +
                           "'s centre of mass");
  }
  if (!desc.angularVelocity.isZero(0))
    parameters.failModel(desc.jsonPath + " spins at t = 0: not a one-dimensional oscillator");
  if (lateral(v0, direction_) > 1e-9 * (1 + v0.norm()))
    parameters.failModel(desc.jsonPath + "'s initial velocity is not along the spring");

  const double mass = double(desc.massProperties.mass);
  omega_ = std::sqrt(double(joint.stiffness) / mass);
  if (!(omega_ > 0)) parameters.failModel(jointPath_ + ": stiffness must be positive");
  offsetEq_ = g.dot(direction_) / (omega_ * omega_);
  speed0_ = v0.dot(direction_);
  if (joint.type == pbd::JointType::RigidBodySpring) {
    const double amplitude = std::hypot(offsetEq_, speed0_ / omega_);
    const double restLength = (joint.position2 - joint.position1).norm();
    if (!(restLength + offsetEq_ - amplitude > 0))
      parameters.failModel(jointPath_ + ": the spring would pass through zero length");
  }
}

double HarmonicOscillatorModel::offset(double t) const {
  return offsetEq_ * (1 - std::cos(omega_ * t)) + speed0_ / omega_ * std::sin(omega_ * t);
}

std::string HarmonicOscillatorModel::description() const {
  std::ostringstream out;
  out << "harmonic oscillator on " << jointPath_ << " (omega = " << omega_
      << " rad/s, s_eq = " << offsetEq_ << " m)";
  return out.str();
}

void HarmonicOscillatorModel::evaluate(State& state) {
  const double t = state.time;
  BodyState& b = state.bodies[static_cast<std::size_t>(body_)];
  b.position += offset(t) * direction_;
  b.velocity =
      (offsetEq_ * omega_ * std::sin(omega_ * t) + speed0_ * std::cos(omega_ * t)) * direction_;
}

}  // namespace pbdval
