// The contacts of one step: the geometry found by collision detection, turned into velocity
// constraints once per step and solved in the velocity pass, in the seed's order (all
// rigid–rigid contacts, then all particle–rigid contacts, each in detection order).
#pragma once

#include <vector>

#include "pbd/contacts/contact_materials.h"
#include "pbd/contacts/particle_rigid_body_contact.h"
#include "pbd/contacts/rigid_body_contact.h"

namespace pbd {

struct ContactSet {
  ContactGeometryBuffer geometry;  ///< written by CollisionDetector::detect
  std::vector<RigidBodyContact> rigid;
  std::vector<ParticleRigidBodyContact> particle;
  ContactSolveSettings solveSettings;

  /// Sizes every buffer for `detector`'s worst case (at world build).
  void reserve(const CollisionDetector& detector);
  /// Builds the constraints from `geometry` and the current velocities.
  void initialise(const BodyStates& bodies, const ContactMaterials& materials,
                  const SimulationSettings& settings);
  /// One velocity iteration over every contact.
  void solveVelocities(BodyStates& bodies);
};

}  // namespace pbd
