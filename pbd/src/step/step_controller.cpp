#include "pbd/step/step_controller.h"

#include "pbd/model/world.h"
#include "pbd/step/time_integration.h"
#include "pbd/step/world_integration.h"

namespace pbd {
namespace {

/// The particle–tet contacts' schedule: the seed's (detected after the substeps, solved one
/// step late against snapshots) or, corrected, detected and solved in every substep.
ParticleTetSchedule tetSchedule(const World& world) {
  return world.settings.contactModel == ContactModel::Seed ? ParticleTetSchedule::Seed
                                                           : ParticleTetSchedule::Current;
}

void detectTetContacts(World& world) {
  world.collision.detectParticleTet(world.bodies.particles, world.tetContacts.geometry);
  world.tetContacts.initialise(world.bodies.particles, world.materials);
}

void projectPositions(World& world, Real h) {
  for (Joint& joint : world.joints)
    std::visit([&](auto& j) { j.beginSubstep(h); }, joint);
  for (StiffRodTreeSolver& tree : world.stiffRodTrees)
    tree.beginSubstep(h);
  for (int iteration = 0; iteration < world.settings.maxIterations; ++iteration) {
    for (Joint& joint : world.joints)
      std::visit([&](auto& j) { j.solvePosition(world.bodies, h); }, joint);
    for (StiffRodTreeSolver& tree : world.stiffRodTrees)
      tree.solvePosition(world.bodies);
    world.constraints.solvePositions(world.bodies, h, iteration == 0);
    // Then, serially, the particle–tet contacts (the seed's place for them).
    world.tetContacts.solvePositions(world.bodies.particles, tetSchedule(world), 0);
  }
}

/// Collision detection on the positions after the substeps; contacts are set up from the
/// current velocities (the seed's order: docs/seed.md#the-step, steps 5–6).
void detectContacts(World& world) {
  world.collision.detect(world.bodies, world.settings.contactTolerance, world.contacts.geometry,
                         world.settings.contactModel == ContactModel::Seed
                             ? ContactOrder::Seed
                             : ContactOrder::DeepestFirst);
  world.contacts.initialise(world.bodies, world.materials, world.settings);
  // The seed: particle–tet contacts found here act in the next step's substeps.
  if (tetSchedule(world) == ParticleTetSchedule::Seed) detectTetContacts(world);
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
  // Motor set points: pbdval's f(t + h), the end of this step (jointModel corrected); the
  // seed's f(t − h), set after the previous step from that step's start time (negative before
  // the first step: the loader's initial target; MotorTarget::seedValueAt).
  const Real targetTime = jointModelFor(world.settings) == JointModel::Seed
                              ? static_cast<Real>(world.stepCount - 1) * h
                              : static_cast<Real>(world.stepCount + 1) * h;

  for (Joint& joint : world.joints)
    std::visit([&](auto& j) { j.updateTarget(targetTime); }, joint);
  resetAccelerations(world);
  for (int s = 0; s < substeps; ++s) {
    predictPositions(world, hs);
    if (tetSchedule(world) == ParticleTetSchedule::Current) detectTetContacts(world);
    projectPositions(world, hs);
    solveFluids(world.fluids, world.bodies.particles);  // own neighbour search and iterations
    updateVelocities(world, hs, world.settings.velocityUpdateMethod == 1);
    applyFluidViscosity(world.fluids, world.bodies.particles);
  }
  detectContacts(world);
  projectVelocities(world);
  world.contacts.rememberImpulses();

  ++world.stepCount;
  world.time = static_cast<Real>(world.stepCount) * h;
}

}  // namespace pbd
