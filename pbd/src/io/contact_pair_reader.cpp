// The `ContactPairs` block (extension): explicit friction and/or restitution for pairs of rigid
// bodies, overriding Simulation.contactCombineRule for those pairs.
//   "ContactPairs": [ { "bodyID1": 1, "bodyID2": 2, "friction": 0.5, "restitution": 0.0 } ]
#include "scene_reading.h"

namespace pbd::scene_io {

void readContactPairs(const JsonValue& block, Scene& scene) {
  for (const JsonValue& element : block.elements("an array of contact-pair objects")) {
    JsonObject object = element.object();
    ContactPairDesc pair;
    pair.jsonPath = element.path();
    const JsonValue id1 = object.require("bodyID1");
    const JsonValue id2 = object.require("bodyID2");
    pair.bodyId1 = id1.integer();
    pair.bodyId2 = id2.integer();
    pair.body1 = resolveBodyId(id1, scene);
    pair.body2 = resolveBodyId(id2, scene);
    if (pair.body1 == pair.body2) id2.fail("a body other than bodyID1");
    if (auto friction = object.find("friction")) {
      pair.hasFriction = true;
      pair.friction = friction->number(nonNegative());
    }
    if (auto restitution = object.find("restitution")) {
      pair.hasRestitution = true;
      pair.restitution = restitution->number(between(0, 1));
    }
    if (!pair.hasFriction && !pair.hasRestitution)
      object.error("a contact pair needs \"friction\" and/or \"restitution\"");
    for (const ContactPairDesc& other : scene.contactPairs)
      if ((other.body1 == pair.body1 && other.body2 == pair.body2) ||
          (other.body1 == pair.body2 && other.body2 == pair.body1))
        object.error("the pair (" + std::to_string(pair.bodyId1) + ", " +
                     std::to_string(pair.bodyId2) + ") is already given at " + other.jsonPath);
    object.warnUnknownKeys();
    scene.contactPairs.push_back(pair);
  }
}

}  // namespace pbd::scene_io
