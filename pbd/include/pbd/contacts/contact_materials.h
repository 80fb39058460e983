// The friction and restitution of every contact, precomputed from the Scene when the world is
// built, so that a step looks them up without allocating. The values equal
// Scene::pairMaterial (rigid pairs: the combination rule, then explicit ContactPairs) and
// Scene::particleMaterial (a particle's triangle or tet model combined with the body).
#pragma once

#include <vector>

#include "pbd/model/scene.h"

namespace pbd {

class ContactMaterials {
 public:
  ContactMaterials() = default;
  explicit ContactMaterials(const Scene& scene);

  /// Rigid bodies `a` and `b` (indices).
  ContactMaterial rigid(int a, int b) const;
  /// Global particle index `particle` against rigid body `body`.
  ContactMaterial particle(int particle, int body) const;
  /// Global particles `a` and `b` of two models (particle–tet contacts): their models'
  /// materials combined by the rule.
  ContactMaterial particles(int a, int b) const;

 private:
  struct Override {
    int first = 0, second = 0;  ///< first < second
    ContactPairDesc pair;
  };
  ContactCombineRule rule_ = ContactCombineRule::Seed;
  std::vector<ContactMaterial> bodies_;
  std::vector<ContactMaterial> particleModels_;  ///< per particle: its model's material
  std::vector<Override> overrides_;              ///< sorted by (first, second), scene order kept
};

}  // namespace pbd
