#include "pbd/contacts/contact_set.h"

#include <algorithm>

namespace pbd {
namespace {

ContactMemory keyOf(const ContactPointGeometry& g) {
  ContactMemory key;
  key.vertexSide = g.vertexSide;
  key.sdfBody = g.sdfBody;
  key.sample = g.sample;
  return key;
}

/// Applies each contact's impulses from the previous step, where the same contact existed.
template <typename Contact, typename Bodies>
void warmStart(std::vector<Contact>& contacts, const std::vector<ContactPointGeometry>& geometry,
               const std::vector<ContactMemory>& memory, Bodies& bodies) {
  for (std::size_t i = 0; i < contacts.size(); ++i) {
    const ContactMemory key = keyOf(geometry[i]);
    const auto found = std::lower_bound(memory.begin(), memory.end(), key);
    if (found == memory.end() || !found->sameContact(key)) continue;
    contacts[i].applyImpulse(
        bodies,
        warmStartContactImpulse(contacts[i].impulse, found->normalImpulse, found->tangentImpulse));
  }
}

template <typename Contact>
void remember(const std::vector<Contact>& contacts,
              const std::vector<ContactPointGeometry>& geometry,
              std::vector<ContactMemory>& memory) {
  memory.clear();
  for (std::size_t i = 0; i < contacts.size(); ++i) {
    ContactMemory entry = keyOf(geometry[i]);
    entry.normalImpulse = contacts[i].impulse.normalImpulse;
    entry.tangentImpulse = tangentImpulseWorld(contacts[i].impulse);
    memory.push_back(entry);  // within the reserved capacity
  }
  std::sort(memory.begin(), memory.end());  // in place: no allocation
}

}  // namespace

void ContactSet::reserve(const CollisionDetector& detector) {
  detector.reserve(geometry);
  rigid.reserve(geometry.rigid.capacity());
  particle.reserve(geometry.particle.capacity());
  rigidMemory.reserve(geometry.rigid.capacity());
  particleMemory.reserve(geometry.particle.capacity());
}

void ContactSet::initialise(BodyStates& bodies, const ContactMaterials& materials,
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
  if (solveSettings.model != ContactModel::Corrected) return;
  warmStart(rigid, geometry.rigid, rigidMemory, bodies.rigid);
  warmStart(particle, geometry.particle, particleMemory, bodies);
}

void ContactSet::solveVelocities(BodyStates& bodies) {
  for (RigidBodyContact& contact : rigid)
    contact.solveVelocity(bodies.rigid, solveSettings.model);
  for (ParticleRigidBodyContact& contact : particle)
    contact.solveVelocity(bodies, solveSettings.model);
}

void ContactSet::rememberImpulses() {
  if (solveSettings.model != ContactModel::Corrected) return;
  remember(rigid, geometry.rigid, rigidMemory);
  remember(particle, geometry.particle, particleMemory);
}

}  // namespace pbd
