#include "pbd/contacts/contact_materials.h"

#include <algorithm>

namespace pbd {

ContactMaterials::ContactMaterials(const Scene& scene)
    : rule_(scene.simulation.contactCombineRule) {
  for (const RigidBodyDesc& body : scene.rigidBodies)
    bodies_.push_back({body.friction, body.restitution});
  // Scene::particleMaterial's answer without the body: the model part of the combination.
  particleModels_.resize(scene.particles.size(), {Real(0.2), Real(0.1)});
  auto assign = [&](int first, std::size_t count, Real friction, Real restitution) {
    for (std::size_t i = 0; i < count; ++i)
      particleModels_[std::size_t(first) + i] = {friction, restitution};
  };
  // Tet models first, then triangle models: where a particle index appears in both (it
  // cannot after loading), the triangle model wins, as in Scene::particleMaterial.
  for (const TetModelDesc& m : scene.tetModels)
    assign(m.firstParticle, m.mesh.vertices.size(), m.friction, m.restitution);
  for (const TriangleModelDesc& m : scene.triangleModels)
    assign(m.firstParticle, m.mesh.vertices.size(), m.friction, m.restitution);
  for (const ContactPairDesc& pair : scene.contactPairs)
    overrides_.push_back(
        {std::min(pair.body1, pair.body2), std::max(pair.body1, pair.body2), pair});
  std::stable_sort(overrides_.begin(), overrides_.end(), [](const Override& a, const Override& b) {
    return a.first < b.first || (a.first == b.first && a.second < b.second);
  });
}

ContactMaterial ContactMaterials::rigid(int a, int b) const {
  ContactMaterial m = combineMaterials(rule_, bodies_[std::size_t(a)], bodies_[std::size_t(b)]);
  const int first = std::min(a, b), second = std::max(a, b);
  auto it = std::lower_bound(overrides_.begin(), overrides_.end(), std::make_pair(first, second),
                             [](const Override& o, const std::pair<int, int>& key) {
                               return o.first < key.first ||
                                      (o.first == key.first && o.second < key.second);
                             });
  for (; it != overrides_.end() && it->first == first && it->second == second; ++it) {
    if (it->pair.hasFriction) m.friction = it->pair.friction;
    if (it->pair.hasRestitution) m.restitution = it->pair.restitution;
  }
  return m;
}

ContactMaterial ContactMaterials::particle(int particle, int body) const {
  return combineMaterials(rule_, particleModels_[std::size_t(particle)],
                          bodies_[std::size_t(body)]);
}

ContactMaterial ContactMaterials::particles(int a, int b) const {
  return combineMaterials(rule_, particleModels_[std::size_t(a)], particleModels_[std::size_t(b)]);
}

}  // namespace pbd
