// Per-pair contact materials in Bullet.
//
// Bullet combines two bodies' friction and restitution by multiplying them
// (btManifoldResult::calculateCombinedFriction/Restitution). The Scene prescribes the pair's
// values instead (Scene::pairMaterial: the combination rule or an explicit ContactPairs
// entry). Bullet calls the global hooks gCalculateCombinedFrictionCallback and
// gCalculateCombinedRestitutionCallback for every contact point it adds or refreshes; pbdval
// installs stateless hooks that find the pair's values through the collision objects' user
// pointers (a BodyTag naming the body's index and its engine's PairMaterials). Objects without
// a tag keep Bullet's product rule.
#pragma once

#include <map>
#include <utility>
#include <vector>

#include "adapters/bullet/bullet_convert.h"
#include "pbd/model/scene.h"

namespace pbdval::bullet {

/// The friction and restitution of every pair of rigid bodies of one Scene, as
/// Scene::pairMaterial gives them.
class PairMaterials {
 public:
  explicit PairMaterials(const pbd::Scene& scene);
  pbd::ContactMaterial of(int bodyA, int bodyB) const;

 private:
  pbd::ContactCombineRule rule_;
  std::vector<pbd::ContactMaterial> bodies_;
  std::map<std::pair<int, int>, pbd::ContactMaterial> explicitPairs_;  ///< (min, max) index
};

/// What a btCollisionObject's user pointer points to.
struct BodyTag {
  int body = -1;  ///< index into Scene::rigidBodies
  const PairMaterials* materials = nullptr;
};

/// Installs the combination hooks (once per process; the hooks hold no state).
void installPairMaterialHooks();

/// The hooks, exposed for tests.
btScalar pairFriction(const btCollisionObject* a, const btCollisionObject* b);
btScalar pairRestitution(const btCollisionObject* a, const btCollisionObject* b);

}  // namespace pbdval::bullet
