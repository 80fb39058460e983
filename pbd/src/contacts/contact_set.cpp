#include "pbd/contacts/contact_set.h"

namespace pbd {

void ContactSet::reserve(const CollisionDetector& detector) {
  detector.reserve(geometry);
  rigid.reserve(geometry.rigid.capacity());
  particle.reserve(geometry.particle.capacity());
}

void ContactSet::initialise(const BodyStates& bodies, const ContactMaterials& materials,
                            const SimulationSettings& settings) {
  solveSettings.model = settings.contactModel;
  solveSettings.restitutionThreshold =
      2 * settings.gravitation.norm() * settings.timeStepSize;  // 2|g|h
  rigid.resize(geometry.rigid.size());  // within the reserved capacity: no allocation
  for (std::size_t i = 0; i < rigid.size(); ++i) {
    const ContactPointGeometry& g = geometry.rigid[i];
    rigid[i].init(g, bodies.rigid, materials.rigid(g.vertexSide, g.sdfBody),
                  settings.contactStiffnessRigidBody, solveSettings);
  }
  particle.resize(geometry.particle.size());
  for (std::size_t i = 0; i < particle.size(); ++i) {
    const ContactPointGeometry& g = geometry.particle[i];
    particle[i].init(g, bodies, materials.particle(g.vertexSide, g.sdfBody),
                     settings.contactStiffnessParticleRigidBody, solveSettings);
  }
}

void ContactSet::solveVelocities(BodyStates& bodies) {
  for (RigidBodyContact& contact : rigid)
    contact.solveVelocity(bodies.rigid, solveSettings.model);
  for (ParticleRigidBodyContact& contact : particle)
    contact.solveVelocity(bodies, solveSettings.model);
}

}  // namespace pbd
