#include "adapters/bullet/bullet_materials.h"

#include <algorithm>

namespace pbdval::bullet {
namespace {

std::pair<int, int> orderedPair(int a, int b) {
  return {std::min(a, b), std::max(a, b)};
}

const BodyTag* tagOf(const btCollisionObject* object) {
  return static_cast<const BodyTag*>(object->getUserPointer());
}

/// The Scene's material of the pair, or nothing when either object is not a pbdval body of
/// the same engine.
const PairMaterials* sharedMaterials(const BodyTag* a, const BodyTag* b) {
  if (a == nullptr || b == nullptr || a->materials == nullptr) return nullptr;
  return a->materials == b->materials ? a->materials : nullptr;
}

// Bullet's own rule (btManifoldResult.cpp), for objects pbdval did not create.
constexpr btScalar kBulletMaxFriction = 10;

}  // namespace

PairMaterials::PairMaterials(const pbd::Scene& scene) : rule_(scene.simulation.contactCombineRule) {
  for (const pbd::RigidBodyDesc& body : scene.rigidBodies)
    bodies_.push_back({body.friction, body.restitution});
  for (const pbd::ContactPairDesc& pair : scene.contactPairs)
    explicitPairs_[orderedPair(pair.body1, pair.body2)] =
        scene.pairMaterial(pair.body1, pair.body2);
}

pbd::ContactMaterial PairMaterials::of(int bodyA, int bodyB) const {
  const auto it = explicitPairs_.find(orderedPair(bodyA, bodyB));
  if (it != explicitPairs_.end()) return it->second;
  return pbd::combineMaterials(rule_, bodies_[static_cast<std::size_t>(bodyA)],
                               bodies_[static_cast<std::size_t>(bodyB)]);
}

btScalar pairFriction(const btCollisionObject* a, const btCollisionObject* b) {
  const BodyTag *tagA = tagOf(a), *tagB = tagOf(b);
  if (const PairMaterials* materials = sharedMaterials(tagA, tagB))
    return materials->of(tagA->body, tagB->body).friction;
  return std::clamp(a->getFriction() * b->getFriction(), -kBulletMaxFriction, kBulletMaxFriction);
}

btScalar pairRestitution(const btCollisionObject* a, const btCollisionObject* b) {
  const BodyTag *tagA = tagOf(a), *tagB = tagOf(b);
  if (const PairMaterials* materials = sharedMaterials(tagA, tagB))
    return materials->of(tagA->body, tagB->body).restitution;
  return a->getRestitution() * b->getRestitution();
}

void installPairMaterialHooks() {
  // A function-local static: installed once, thread-safe, and identical for every engine.
  static const bool installed = [] {
    gCalculateCombinedFrictionCallback = &pairFriction;
    gCalculateCombinedRestitutionCallback = &pairRestitution;
    return true;
  }();
  (void)installed;
}

}  // namespace pbdval::bullet
