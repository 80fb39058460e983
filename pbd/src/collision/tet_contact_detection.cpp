#include "pbd/collision/tet_contact_detection.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "pbd/model/mesh.h"

namespace pbd {
namespace {

/// A particle can be inside at most this many other tet models at once in a sensible scene.
constexpr std::size_t kTetContactsPerParticle = 4;

/// The face opposite each vertex slot of a tet (p₀ p₁ p₂ p₃), any orientation.
constexpr std::array<std::array<int, 3>, 4> kFaceOpposite = {
    {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}}};

/// Barycentric coordinates of `q` in the triangle (a, b, c), clamped to the triangle and
/// renormalised (q is the closest point of the triangle, so only round-off is clamped).
std::array<Real, 3> triangleBarycentrics(const Vector3& a, const Vector3& b, const Vector3& c,
                                         const Vector3& q) {
  const Vector3 e0 = b - a, e1 = c - a, d = q - a;
  const Real d00 = e0.dot(e0), d01 = e0.dot(e1), d11 = e1.dot(e1);
  const Real d20 = d.dot(e0), d21 = d.dot(e1);
  const Real det = d00 * d11 - d01 * d01;
  if (!(det > 0)) return {Real(1) / 3, Real(1) / 3, Real(1) / 3};  // degenerate face
  Real v = (d11 * d20 - d01 * d21) / det;
  Real w = (d00 * d21 - d01 * d20) / det;
  Real u = 1 - v - w;
  u = std::max(u, Real(0));
  v = std::max(v, Real(0));
  w = std::max(w, Real(0));
  const Real sum = u + v + w;
  return {u / sum, v / sum, w / sum};
}

}  // namespace

TetContactDetector::TetContactDetector(const Scene& scene) {
  if (scene.tetModels.size() < 2) return;  // no pairs: nothing to build
  std::size_t particles = 0;
  const std::size_t others = std::min(scene.tetModels.size() - 1, kTetContactsPerParticle);
  for (const TetModelDesc& desc : scene.tetModels) {
    Model model;
    model.firstParticle = desc.firstParticle;
    model.particleCount = static_cast<int>(desc.mesh.vertices.size());
    model.vertexSide = desc.collision.type == CollisionObjectType::None || desc.collision.testMesh;
    model.reference = desc.mesh.vertices;
    for (const std::array<int, 4>& t : desc.mesh.tetrahedra)
      model.tets.push_back({t[0] + desc.firstParticle, t[1] + desc.firstParticle,
                            t[2] + desc.firstParticle, t[3] + desc.firstParticle});
    if (model.vertexSide) particles += std::size_t(model.particleCount);
    if (!model.tets.empty()) {
      model.hierarchy = TetBvh(desc.mesh.tetrahedra, desc.mesh.vertices.data());
      // The boundary: faces of exactly one tet, oriented away from the tet's fourth vertex.
      std::map<std::array<int, 3>, std::pair<int, int>> faceUse;  // sorted face → (tet, slot)
      std::map<std::array<int, 3>, int> count;
      for (std::size_t t = 0; t < desc.mesh.tetrahedra.size(); ++t)
        for (int slot = 0; slot < 4; ++slot) {
          std::array<int, 3> key;
          for (int k = 0; k < 3; ++k)
            key[std::size_t(k)] =
                desc.mesh
                    .tetrahedra[t][std::size_t(kFaceOpposite[std::size_t(slot)][std::size_t(k)])];
          std::sort(key.begin(), key.end());
          ++count[key];
          faceUse[key] = {int(t), slot};
        }
      TriangleMesh surface;
      surface.vertices = desc.mesh.vertices;
      for (const auto& [key, use] : faceUse) {
        if (count[key] != 1) continue;
        BoundaryFace face;
        face.tet = use.first;
        face.opposite = use.second;
        face.corners = kFaceOpposite[std::size_t(use.second)];
        const std::array<int, 4>& tet = desc.mesh.tetrahedra[std::size_t(face.tet)];
        const Vector3& a = desc.mesh.vertices[std::size_t(tet[std::size_t(face.corners[0])])];
        const Vector3& b = desc.mesh.vertices[std::size_t(tet[std::size_t(face.corners[1])])];
        const Vector3& c = desc.mesh.vertices[std::size_t(tet[std::size_t(face.corners[2])])];
        const Vector3& d = desc.mesh.vertices[std::size_t(tet[std::size_t(face.opposite)])];
        if ((b - a).cross(c - a).dot(d - a) > 0) std::swap(face.corners[1], face.corners[2]);
        model.faces.push_back(face);
        surface.triangles.push_back({tet[std::size_t(face.corners[0])],
                                     tet[std::size_t(face.corners[1])],
                                     tet[std::size_t(face.corners[2])]});
      }
      model.boundary = std::make_shared<const MeshDistance>(surface);
    }
    models_.push_back(std::move(model));
  }
  capacity_ = particles * others;
}

void TetContactDetector::reserve(ParticleTetGeometryBuffer& out) const {
  out.contacts.clear();
  out.contacts.reserve(capacity_);
}

void TetContactDetector::testParticle(const Model& tetSide, int tetModel, int particle,
                                      const ParticleStates& particles,
                                      ParticleTetGeometryBuffer& out) const {
  const Vector3& x = particles.position[std::size_t(particle)];
  const Vector3* positions = particles.position.data();
  int found = -1;
  Real bestMinimum = 0;
  std::array<Real, 4> bestWeights{};
  tetSide.hierarchy.tetsContaining(x, [&](int t) {
    const std::array<int, 4>& tet = tetSide.tets[std::size_t(t)];
    std::array<Real, 4> b;
    if (!tetBarycentric(
            {positions[tet[0]], positions[tet[1]], positions[tet[2]], positions[tet[3]]}, x, b))
      return;
    const Real minimum = *std::min_element(b.begin(), b.end());
    if (!(minimum >= 0)) return;
    if (found < 0 || minimum > bestMinimum || (minimum == bestMinimum && t < found)) {
      found = t;
      bestMinimum = minimum;
      bestWeights = b;
    }
  });
  if (found < 0) return;
  // The particle's place in the reference configuration and the closest reference boundary point.
  const int first = tetSide.firstParticle;
  const std::array<int, 4>& tet = tetSide.tets[std::size_t(found)];
  Vector3 reference = Vector3::Zero();
  for (std::size_t k = 0; k < 4; ++k)
    reference += bestWeights[k] * tetSide.reference[std::size_t(tet[k] - first)];
  Vector3 closest;
  const int triangle = tetSide.boundary->closestTriangle(reference, closest);
  if (triangle < 0) return;
  const BoundaryFace& face = tetSide.faces[std::size_t(triangle)];
  const std::array<int, 4>& contactTet = tetSide.tets[std::size_t(face.tet)];
  const auto at = [&](const std::array<int, 4>& t, int slot) -> int {
    return t[std::size_t(slot)];
  };
  const std::array<Real, 3> faceWeights = triangleBarycentrics(
      tetSide.reference[std::size_t(at(contactTet, face.corners[0]) - first)],
      tetSide.reference[std::size_t(at(contactTet, face.corners[1]) - first)],
      tetSide.reference[std::size_t(at(contactTet, face.corners[2]) - first)], closest);
  ParticleTetContactGeometry contact;
  contact.particle = particle;
  contact.tetModel = tetModel;
  contact.tet = face.tet;
  contact.vertices = contactTet;
  contact.weights[std::size_t(face.opposite)] = 0;
  for (std::size_t k = 0; k < 3; ++k)
    contact.weights[std::size_t(face.corners[k])] = faceWeights[k];
  Vector3 point = Vector3::Zero();
  bool allStatic = !(particles.inverseMass[std::size_t(particle)] > 0);
  for (std::size_t k = 0; k < 4; ++k) {
    point += contact.weights[k] * positions[contactTet[k]];
    allStatic = allStatic && !(particles.inverseMass[std::size_t(contactTet[k])] > 0);
  }
  if (allStatic) return;
  // The normal: the contact face's current outward normal (the seed: (c − x_p)/|c − x_p|,
  // whose direction the reference mapping tilts as the solid deforms; docs/contacts.md).
  const Vector3& a = positions[at(contactTet, face.corners[0])];
  const Vector3 faceNormal = (positions[at(contactTet, face.corners[1])] - a)
                                 .cross(positions[at(contactTet, face.corners[2])] - a);
  if (!(faceNormal.squaredNorm() > 0)) return;  // a collapsed face: no direction
  contact.normal = faceNormal.normalized();
  contact.distance = contact.normal.dot(x - point);
  if (out.contacts.size() == out.contacts.capacity()) {
    ++out.droppedContacts;
    return;
  }
  out.contacts.push_back(contact);
}

void TetContactDetector::detect(const ParticleStates& particles, ParticleTetGeometryBuffer& out) {
  out.contacts.clear();
  out.droppedContacts = 0;
  if (models_.size() < 2) return;
  for (Model& model : models_) {
    const Vector3* positions = particles.position.data();
    model.box.active = model.particleCount > 0;
    if (!model.box.active) continue;
    model.hierarchy.refit(model.tets, positions);
    model.box.min = model.box.max = positions[model.firstParticle];
    for (int p = 1; p < model.particleCount; ++p) {
      model.box.min = model.box.min.cwiseMin(positions[model.firstParticle + p]);
      model.box.max = model.box.max.cwiseMax(positions[model.firstParticle + p]);
    }
  }
  for (std::size_t a = 0; a < models_.size(); ++a) {
    const Model& vertexSide = models_[a];
    if (!vertexSide.vertexSide || !vertexSide.box.active) continue;
    for (std::size_t b = 0; b < models_.size(); ++b) {
      const Model& tetSide = models_[b];
      if (a == b || tetSide.tets.empty() || !tetSide.box.active ||
          !vertexSide.box.overlaps(tetSide.box))
        continue;
      for (int p = 0; p < vertexSide.particleCount; ++p) {
        const int particle = vertexSide.firstParticle + p;
        const Vector3& x = particles.position[std::size_t(particle)];
        if ((x.array() < tetSide.box.min.array()).any() ||
            (x.array() > tetSide.box.max.array()).any())
          continue;
        testParticle(tetSide, static_cast<int>(b), particle, particles, out);
      }
    }
  }
}

}  // namespace pbd
