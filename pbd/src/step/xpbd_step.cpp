#include "pbd/step/xpbd_step.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "pbd/model/world.h"
#include "pbd/step/time_integration.h"
#include "pbd/step/world_integration.h"

namespace pbd {
namespace {

/// contactTolerance + speculativeMargin · h · (the largest speed of any point in the world,
/// plus h |a| for its acceleration).
///
/// The h |a| term: a point that starts the step at rest is not at rest at its end — the
/// substeps move it by Σ_k k h_s² |a| = ½ (1 + 1/n) h² |a| ≤ h² |a| (semi-implicit Euler, n
/// substeps). Without it a body resting on a surface with contactTolerance 0 is only seen when
/// it has already sunk: the step where its corners sit exactly on (or a round-off above) the
/// surface collects no contact (tolerance ≈ speculativeMargin · h · 0), the box falls freely
/// for the whole step (by ½ (1 + 1/n) g h² = 0.13 mm at h = 5 ms), the next step collects the
/// corners and projects them out — unevenly, because one Gauss–Seidel sweep over four corners
/// tilts the box — and the cycle repeats: a box that never leaves the surface by more than 0.13
/// mm yet reports v_y ≈ −0.02 m/s and ω ≈ 0.2 rad/s at every fifth step and turns by 10° in 5 s
/// (issue 24). With the term every point that can reach a surface during the step has its
/// contact from the step's start, as the paper's speculative margin intends.
Real detectionTolerance(const World& world) {
  const Real h = world.settings.timeStepSize;
  const RigidBodyStates& b = world.bodies.rigid;
  Real speed = 0;
  for (std::size_t i = 0; i < b.size(); ++i)
    if (b.isDynamic(i))
      speed = std::max(speed, b.velocity[i].norm() +
                                  b.angularVelocity[i].norm() * world.xpbd.sampleRadius[i] +
                                  h * b.acceleration[i].norm());
  const ParticleStates& p = world.bodies.particles;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.inverseMass[i] > 0)
      speed = std::max(speed, p.velocity[i].norm() + h * p.acceleration[i].norm());
  return world.settings.contactTolerance + world.settings.xpbd.speculativeMargin * h * speed;
}

void solvePositions(World& world, Real h) {
  const XpbdSettings& settings = world.settings.xpbd;
  for (int sweep = 0; sweep < settings.jointIterations; ++sweep)
    solveJointPositionsXpbd(world.joints, world.xpbd.jointSchedule, world.bodies, h, settings,
                            world.xpbd.jointMultipliers, /*firstSweep=*/sweep == 0);
  // Stiff-rod trees: their own compliances, one direct solve per substep.
  for (StiffRodTreeSolver& tree : world.stiffRodTrees) {
    tree.beginSubstep(h);
    tree.solvePosition(world.bodies);
  }
  // The constraint families (constraints/constraint_families.h), each PBD or XPBD as it says:
  // one iteration per substep, so every sweep is its substep's first (λ from zero).
  world.constraints.solvePositions(world.bodies, h, /*firstIteration=*/true);
  for (XpbdContact& contact : world.xpbd.contacts.contacts)
    contact.solvePosition(world.bodies, h, settings.contactCompliance);
  world.tetContacts.solvePositions(world.bodies.particles, ParticleTetSchedule::Current,
                                   settings.contactCompliance / (h * h));
}

void solveVelocities(World& world, Real h) {
  solveJointVelocitiesXpbd(world.joints, world.xpbd.jointSchedule, world.bodies);
  const XpbdSettings& settings = world.settings.xpbd;
  if (settings.jointLinearDamping > 0 || settings.jointAngularDamping > 0)
    for (const JointDampingAnchor& anchor : world.xpbd.jointAnchors)
      dampJoint(world.bodies.rigid, anchor, settings.jointLinearDamping,
                settings.jointAngularDamping, h);
  const Real restitutionThreshold = 2 * world.settings.gravitation.norm() * h;  // 2|g|h
  XpbdContactSet& contacts = world.xpbd.contacts;
  if (!contacts.anyActive()) return;
  contacts.formRotations(world.bodies.rigid);  // the poses are fixed in the velocity pass
  for (const XpbdContact& contact : contacts.contacts)
    contact.solveVelocity(world.bodies, contacts.rotations, h, restitutionThreshold);
}

}  // namespace

void prepareXpbd(World& world, const Scene& scene) {
  const XpbdSettings& settings = world.settings.xpbd;
  if (settings.substeps < 1)
    throw std::invalid_argument("XPBD settings: substeps must be at least 1, got " +
                                std::to_string(settings.substeps));
  if (settings.jointIterations < 1)
    throw std::invalid_argument("XPBD settings: jointIterations must be at least 1, got " +
                                std::to_string(settings.jointIterations));
  if (!(settings.jointLinearCompliance >= 0) || !(settings.jointAngularCompliance >= 0) ||
      !(settings.contactCompliance >= 0) || !(settings.speculativeMargin >= 0) ||
      !(settings.jointLinearDamping >= 0) || !(settings.jointAngularDamping >= 0))
    throw std::invalid_argument(
        "XPBD settings: compliances, speculativeMargin and damping must be >= 0 (not NaN)");
  XpbdState& state = world.xpbd;
  state.jointMultipliers.assign(world.joints.size(), XpbdJointMultipliers::Zero());
  state.jointSchedule = scheduleJointsXpbd(world.joints);
  state.jointAnchors.clear();
  const RigidBodyStates& rigid = world.bodies.rigid;
  for (int sceneIndex : world.jointSceneIndex) {
    const JointDesc& desc = scene.joints[static_cast<std::size_t>(sceneIndex)];
    JointDampingAnchor anchor;
    if (desc.body2 >= 0) {
      const auto i0 = static_cast<std::size_t>(desc.body1),
                 i1 = static_cast<std::size_t>(desc.body2);
      Vector3 point = Real(0.5) * (rigid.position[i0] + rigid.position[i1]);
      switch (desc.type) {
        case JointType::RigidBodySpring:
        case JointType::Distance:
          point = Real(0.5) * (desc.position1 + desc.position2);
          break;
        case JointType::Slider:
        case JointType::Damper:
        case JointType::TargetPositionMotorSlider:
        case JointType::TargetVelocityMotorSlider:
          break;  // no point: the middle of the centres of mass
        default:
          point = desc.position;
      }
      anchor = {desc.body1, desc.body2,
                rigid.rotation[i0].conjugate() * (point - rigid.position[i0]),
                rigid.rotation[i1].conjugate() * (point - rigid.position[i1])};
    }
    state.jointAnchors.push_back(anchor);
  }
  state.contacts.reserve(world.contacts.geometry, world.bodies.rigid.size());
  const RigidBodyStates& b = world.bodies.rigid;
  state.sampleRadius.assign(b.size(), 0);
  for (std::size_t i = 0; i < b.size() && i < world.collision.rigidBodyCount(); ++i)
    for (const Vector3& sample : world.collision.samples(i))
      state.sampleRadius[i] =
          std::max(state.sampleRadius[i], (sample - b.centerOfMassInScene[i]).norm());
}

void stepWorldXpbd(World& world) {
  const Real h = world.settings.timeStepSize;
  const int substeps = world.settings.xpbd.substeps;
  const Real hs = h / static_cast<Real>(substeps);
  const Real startTime = static_cast<Real>(world.stepCount) * h;

  resetAccelerations(world);
  const Real tolerance = detectionTolerance(world);
  world.collision.detect(world.bodies, tolerance, world.contacts.geometry);
  world.xpbd.contacts.initialise(world.contacts.geometry, world.bodies, world.materials, tolerance);
  const bool hasRestitution = world.xpbd.contacts.anyRestitution();
  for (int s = 0; s < substeps; ++s) {
    const Real substepEnd = startTime + static_cast<Real>(s + 1) * hs;
    updateJointTargetsXpbd(world.joints, world.xpbd.jointSchedule, substepEnd);
    for (XpbdContact& contact : world.xpbd.contacts.contacts)
      contact.followSupportPoint(world.bodies);  // spheres: the rolling contact's new point
    predictPositions(world, hs, /*keepLastState=*/false);  // first order: no last*
    if (hasRestitution) world.xpbd.contacts.formRotations(world.bodies.rigid);
    for (XpbdContact& contact : world.xpbd.contacts.contacts)
      contact.beginSubstep(world.bodies, world.xpbd.contacts.rotations);
    // Particle–tet contacts: detected on the predicted positions of every substep.
    world.collision.detectParticleTet(world.bodies.particles, world.tetContacts.geometry);
    world.tetContacts.initialise(world.bodies.particles, world.materials);
    solvePositions(world, hs);
    solveFluids(world.fluids, world.bodies.particles);   // own neighbour search and iterations
    updateVelocities(world, hs, /*secondOrder=*/false);  // XPBD: first order (the paper)
    solveVelocities(world, hs);
    applyFluidViscosity(world.fluids, world.bodies.particles);
  }

  ++world.stepCount;
  world.time = static_cast<Real>(world.stepCount) * h;
}

}  // namespace pbd
