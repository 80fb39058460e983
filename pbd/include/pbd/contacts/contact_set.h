// The contacts of one step: the geometry found by collision detection, turned into velocity
// constraints once per step and solved in the velocity pass, in the seed's order (all
// rigid–rigid contacts, then all particle–rigid contacts, each in detection order).
//
// The corrected model also remembers each contact's accumulated impulses, keyed by (point,
// SDF body), and starts the next step's solve from them (warm start; contact_impulse.h).
#pragma once

#include <vector>

#include "pbd/contacts/contact_materials.h"
#include "pbd/contacts/particle_rigid_body_contact.h"
#include "pbd/contacts/rigid_body_contact.h"

namespace pbd {

/// The impulses of one contact at the end of a step, for the next step's warm start.
struct ContactMemory {
  int vertexSide = -1, sdfBody = -1, sample = -1;  ///< the key (ContactPointGeometry)
  Real normalImpulse = 0;
  Vector3 tangentImpulse = Vector3::Zero();  ///< world

  bool sameContact(const ContactMemory& other) const {
    return vertexSide == other.vertexSide && sdfBody == other.sdfBody && sample == other.sample;
  }
  bool operator<(const ContactMemory& other) const {
    if (vertexSide != other.vertexSide) return vertexSide < other.vertexSide;
    if (sdfBody != other.sdfBody) return sdfBody < other.sdfBody;
    return sample < other.sample;
  }
};

struct ContactSet {
  ContactGeometryBuffer geometry;  ///< written by CollisionDetector::detect
  std::vector<RigidBodyContact> rigid;
  std::vector<ParticleRigidBodyContact> particle;
  ContactSolveSettings solveSettings;
  std::vector<ContactMemory> rigidMemory, particleMemory;  ///< sorted; corrected model only

  /// Sizes every buffer for `detector`'s worst case (at world build).
  void reserve(const CollisionDetector& detector);
  /// Builds the constraints from `geometry` and the current velocities (and, in the corrected
  /// model, applies the warm start).
  void initialise(BodyStates& bodies, const ContactMaterials& materials,
                  const SimulationSettings& settings);
  /// One velocity iteration over every contact.
  void solveVelocities(BodyStates& bodies);
  /// After the velocity pass: keeps the impulses for the next step's warm start (corrected).
  void rememberImpulses();
};

}  // namespace pbd
