#include "pbd/step/step_controller.h"

#include "pbd/model/world.h"
#include "pbd/step/time_integration.h"

namespace pbd {
namespace {

void resetAccelerations(World& world) {
  const Vector3& g = world.settings.gravitation;
  auto& rigid = world.bodies.rigid;
  for (std::size_t i = 0; i < rigid.size(); ++i)
    rigid.acceleration[i] = rigid.isDynamic(i) ? g : Vector3::Zero();
  auto& particles = world.bodies.particles;
  for (std::size_t i = 0; i < particles.size(); ++i)
    particles.acceleration[i] = particles.inverseMass[i] > 0 ? g : Vector3::Zero();
}

void predict(World& world, Real h) {
  auto& b = world.bodies.rigid;
  for (std::size_t i = 0; i < b.size(); ++i) {
    b.lastPosition[i] = b.oldPosition[i];
    b.oldPosition[i] = b.position[i];
    integration::semiImplicitEuler(h, b.inverseMass[i], b.position[i], b.velocity[i],
                                   b.acceleration[i]);
    b.lastRotation[i] = b.oldRotation[i];
    b.oldRotation[i] = b.rotation[i];
    integration::semiImplicitEulerRotation(h, b.inverseMass[i], b.inertia[i], b.inverseInertia[i],
                                           b.rotation[i], b.angularVelocity[i], b.torque[i]);
  }
  auto& p = world.bodies.particles;
  for (std::size_t i = 0; i < p.size(); ++i) {
    p.lastPosition[i] = p.oldPosition[i];
    p.oldPosition[i] = p.position[i];
    integration::semiImplicitEuler(h, p.inverseMass[i], p.position[i], p.velocity[i],
                                   p.acceleration[i]);
  }
}

void projectPositions(World& world, Real h) {
  for (Joint& joint : world.joints)
    std::visit([&](auto& j) { j.beginSubstep(h); }, joint);
  for (int iteration = 0; iteration < world.settings.maxIterations; ++iteration)
    for (Joint& joint : world.joints)
      std::visit([&](auto& j) { j.solvePosition(world.bodies, h); }, joint);
}

void updateVelocities(World& world, Real h) {
  const bool secondOrder = world.settings.velocityUpdateMethod == 1;
  auto& b = world.bodies.rigid;
  for (std::size_t i = 0; i < b.size(); ++i) {
    if (secondOrder)
      integration::velocityUpdateSecondOrder(h, b.inverseMass[i], b.position[i], b.oldPosition[i],
                                             b.lastPosition[i], b.velocity[i]);
    else
      integration::velocityUpdateFirstOrder(h, b.inverseMass[i], b.position[i], b.oldPosition[i],
                                            b.velocity[i]);
    integration::angularVelocityUpdateFirstOrder(h, b.inverseMass[i], b.rotation[i],
                                                 b.oldRotation[i], b.angularVelocity[i]);
  }
  auto& p = world.bodies.particles;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (secondOrder)
      integration::velocityUpdateSecondOrder(h, p.inverseMass[i], p.position[i], p.oldPosition[i],
                                             p.lastPosition[i], p.velocity[i]);
    else
      integration::velocityUpdateFirstOrder(h, p.inverseMass[i], p.position[i], p.oldPosition[i],
                                            p.velocity[i]);
  }
}

/// Collision detection on the positions after the substeps; contacts are set up from the
/// current velocities (the seed's order: research/pbd.md §3.1, steps 6–7).
void detectContacts(World& world) {
  world.collision.detect(world.bodies, world.settings.contactTolerance, world.contacts.geometry,
                         world.settings.contactModel == ContactModel::Seed
                             ? ContactOrder::Seed
                             : ContactOrder::DeepestFirst);
  world.contacts.initialise(world.bodies, world.materials, world.settings);
}

void projectVelocities(World& world) {
  for (int iteration = 0; iteration < world.settings.maxIterationsV; ++iteration) {
    for (Joint& joint : world.joints)
      std::visit([&](auto& j) { j.solveVelocity(world.bodies); }, joint);
    world.contacts.solveVelocities(world.bodies);
  }
}

}  // namespace

void stepWorld(World& world) {
  const Real h = world.settings.timeStepSize;
  const int substeps = world.settings.subSteps;
  const Real hs = h / static_cast<Real>(substeps);
  const Real endTime = static_cast<Real>(world.stepCount + 1) * h;

  for (Joint& joint : world.joints)
    std::visit([&](auto& j) { j.updateTarget(endTime); }, joint);
  resetAccelerations(world);
  for (int s = 0; s < substeps; ++s) {
    predict(world, hs);
    projectPositions(world, hs);
    updateVelocities(world, hs);
  }
  detectContacts(world);
  projectVelocities(world);
  world.contacts.rememberImpulses();

  ++world.stepCount;
  world.time = endTime;
}

}  // namespace pbd
