#include "validation/measure/mechanics.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "validation/measure/joint_error.h"

namespace pbdval {

namespace {

/// Calls f(mass, position, velocity) for every particle of `state` with mass > 0.
template <typename F>
void forEachMovingParticle(const pbd::Scene& scene, const State& state, F&& f) {
  const std::size_t count = std::min(state.particles.size(), scene.particles.size());
  for (std::size_t i = 0; i < count; ++i) {
    const double mass = double(scene.particles[i].mass);
    if (mass > 0) f(mass, state.particles[i].position, state.particles[i].velocity);
  }
}

double springEnergy(const pbd::Scene& scene, const State& state) {
  double energy = 0;
  for (const pbd::JointDesc& joint : scene.joints)
    if (joint.type == pbd::JointType::RigidBodySpring || joint.type == pbd::JointType::Damper ||
        joint.type == pbd::JointType::StiffRod)
      energy += springPotential(captureJointGeometry(scene, joint), state);
  return energy;
}

std::size_t segmentCount(const pbd::Scene& scene) {
  std::size_t count = 0;
  for (const pbd::LineModelDesc& model : scene.lineModels)
    count += model.segmentCount();
  return count;
}

double totalMass(const pbd::Scene& scene) {
  double mass = 0;
  for (const pbd::RigidBodyDesc& body : scene.rigidBodies)
    if (body.isDynamic) mass += double(body.massProperties.mass);
  for (const pbd::ParticleDesc& particle : scene.particles)
    if (particle.mass > 0) mass += double(particle.mass);
  return mass;
}

}  // namespace

Matrix3 worldInertia(const pbd::RigidBodyDesc& body, const Quaternion& sceneRotation) {
  const Matrix3 principalToWorld =
      (sceneRotation.normalized() * body.massProperties.principalRotation.normalized())
          .toRotationMatrix();
  return principalToWorld * body.massProperties.principalInertia.asDiagonal() *
         principalToWorld.transpose();
}

State initialState(const pbd::Scene& scene) {
  State state;
  state.time = 0;
  state.bodies.reserve(scene.rigidBodies.size());
  for (const pbd::RigidBodyDesc& body : scene.rigidBodies) {
    BodyState b;
    b.id = body.id;
    b.position = body.initialCenterOfMass();
    b.rotation = body.rotation.normalized();
    if (body.isDynamic) {
      b.velocity = body.velocity;
      b.angularVelocity = body.angularVelocity;
    }
    state.bodies.push_back(b);
  }
  for (const pbd::ParticleDesc& particle : scene.particles)
    state.particles.push_back(
        {particle.position, particle.mass > 0 ? particle.velocity : Vector3(Vector3::Zero())});
  // Rod segments start in their rest frames, at rest (as the PBD library builds them).
  for (const pbd::LineModelDesc& model : scene.lineModels)
    for (const Quaternion& frame : model.frames)
      state.segments.push_back({frame, Vector3::Zero()});
  return state;
}

void checkStateMatchesScene(const pbd::Scene& scene, const State& state) {
  // Called for every state of every run: the common case (everything matches) builds nothing.
  bool idsMatch = state.bodies.size() == scene.rigidBodies.size();
  for (std::size_t i = 0; idsMatch && i < state.bodies.size(); ++i)
    idsMatch = state.bodies[i].id == scene.rigidBodies[i].id;
  if (idsMatch && (state.particles.empty() || state.particles.size() == scene.particles.size()) &&
      (state.segments.empty() || state.segments.size() == segmentCount(scene)))
    return;
  std::ostringstream problem;
  if (state.bodies.size() != scene.rigidBodies.size()) {
    problem << "the state at t = " << state.time << " s has " << state.bodies.size()
            << " bodies, the scene " << scene.rigidBodies.size();
  } else if (!state.particles.empty() && state.particles.size() != scene.particles.size()) {
    problem << "the state at t = " << state.time << " s has " << state.particles.size()
            << " particles, the scene " << scene.particles.size();
  } else if (!state.segments.empty() && state.segments.size() != segmentCount(scene)) {
    problem << "the state at t = " << state.time << " s has " << state.segments.size()
            << " rod segments, the scene " << segmentCount(scene);
  } else {
    for (std::size_t i = 0; i < state.bodies.size(); ++i)
      if (state.bodies[i].id != scene.rigidBodies[i].id) {
        problem << "body " << i << " of the state at t = " << state.time << " s has id "
                << state.bodies[i].id << ", the scene's " << scene.rigidBodies[i].id;
        break;
      }
  }
  if (!problem.str().empty()) throw std::invalid_argument("metrics: " + problem.str());
}

EnergyTerms energyOf(const pbd::Scene& scene, const State& state) {
  return energyOf(scene, state, ElasticEnergy(scene));
}

EnergyTerms energyOf(const pbd::Scene& scene, const State& state, const ElasticEnergy& elastic) {
  const Vector3 g = scene.simulation.gravitation;
  EnergyTerms e;
  const std::size_t count = std::min(state.bodies.size(), scene.rigidBodies.size());
  for (std::size_t i = 0; i < count; ++i) {
    const pbd::RigidBodyDesc& desc = scene.rigidBodies[i];
    if (!desc.isDynamic) continue;
    const BodyState& b = state.bodies[i];
    const double m = double(desc.massProperties.mass);
    e.translational += 0.5 * m * b.velocity.squaredNorm();
    e.rotational += 0.5 * b.angularVelocity.dot(worldInertia(desc, b.rotation) * b.angularVelocity);
    e.gravitational -= m * g.dot(b.position);
  }
  forEachMovingParticle(scene, state, [&](double m, const Vector3& x, const Vector3& v) {
    e.translational += 0.5 * m * v.squaredNorm();
    e.gravitational -= m * g.dot(x);
  });
  // Rod segments: ½ I |ω|² with the isotropic inertia I = 1/(4 w_q) the step integrates them
  // with (pbd/model/body_states.h SegmentStates); static segments (w_q = 0) carry none.
  if (!state.segments.empty())
    for (const pbd::LineModelDesc& model : scene.lineModels)
      for (std::size_t k = 0; k < model.segmentCount(); ++k) {
        const std::size_t s = std::size_t(model.firstSegment) + k;
        const double wq = double(model.segmentInverseMass(k));
        if (s < state.segments.size() && wq > 0)
          e.rotational += 0.5 * double(state.segments[s].angularVelocity.squaredNorm()) / (4 * wq);
      }
  e.spring = springEnergy(scene, state);
  e.elastic = elastic.of(state);
  return e;
}

Momenta momentaOf(const pbd::Scene& scene, const State& state) {
  Momenta p;
  Vector3 weightedPosition = Vector3::Zero();
  Vector3 moment = Vector3::Zero();  // Σ x × m v + I_w ω, about the origin
  const auto add = [&](double m, const Vector3& x, const Vector3& v) {
    p.mass += m;
    weightedPosition += m * x;
    p.linear += m * v;
    moment += x.cross(m * v);
  };
  const std::size_t count = std::min(state.bodies.size(), scene.rigidBodies.size());
  for (std::size_t i = 0; i < count; ++i) {
    const pbd::RigidBodyDesc& desc = scene.rigidBodies[i];
    if (!desc.isDynamic) continue;
    const BodyState& b = state.bodies[i];
    add(double(desc.massProperties.mass), b.position, b.velocity);
    moment += worldInertia(desc, b.rotation) * b.angularVelocity;
  }
  forEachMovingParticle(scene, state, add);
  if (p.mass > 0) p.centerOfMass = weightedPosition / p.mass;
  // Σ (x − c) × m v = Σ x × m v − c × P.
  p.angular = moment - p.centerOfMass.cross(p.linear);
  return p;
}

double systemInertia(const pbd::Scene& scene, const State& state) {
  const Vector3 c = momentaOf(scene, state).centerOfMass;
  Matrix3 inertia = Matrix3::Zero();
  const auto addPoint = [&](double m, const Vector3& x) {
    const Vector3 r = x - c;
    inertia += m * (r.squaredNorm() * Matrix3::Identity() - r * r.transpose());
  };
  const std::size_t count = std::min(state.bodies.size(), scene.rigidBodies.size());
  for (std::size_t i = 0; i < count; ++i) {
    const pbd::RigidBodyDesc& desc = scene.rigidBodies[i];
    if (!desc.isDynamic) continue;
    inertia += worldInertia(desc, state.bodies[i].rotation);
    addPoint(double(desc.massProperties.mass), state.bodies[i].position);
  }
  forEachMovingParticle(scene, state,
                        [&](double m, const Vector3& x, const Vector3&) { addPoint(m, x); });
  return Eigen::SelfAdjointEigenSolver<Matrix3>(inertia, Eigen::EigenvaluesOnly)
      .eigenvalues()
      .maxCoeff();
}

double defaultEnergyScale(const pbd::Scene& scene) {
  const EnergyTerms initial = energyOf(scene, initialState(scene));
  const double gravityScale = totalMass(scene) * double(scene.simulation.gravitation.norm()) * 1.0;
  return initial.kinetic() + gravityScale + std::abs(initial.spring);
}

double energyScale(const pbd::Scene& scene, const CaseSpec& spec, std::string* note) {
  if (spec.energyScale && *spec.energyScale > 0) {
    if (note) *note = "E_ref = Validation.energyScale";
    return *spec.energyScale;
  }
  const double scale = defaultEnergyScale(scene);
  if (scale > 0) {
    if (note)
      *note = "E_ref = kinetic energy at t = 0 + M |g| (1 m) + spring energy at t = 0 (default)";
    return scale;
  }
  if (note) *note = "E_ref = 1 J (the scene has no initial kinetic energy, gravity or mass)";
  return 1.0;
}

MomentumScales momentumScales(const pbd::Scene& scene, double energyScale) {
  const State start = initialState(scene);
  const Momenta initial = momentaOf(scene, start);
  MomentumScales s;
  s.linear = std::max(double(initial.linear.norm()), std::sqrt(2 * initial.mass * energyScale));
  s.angular = std::max(double(initial.angular.norm()),
                       std::sqrt(2 * systemInertia(scene, start) * energyScale));
  return s;
}

}  // namespace pbdval
